#!/bin/sh
# The thrown elastic block on a frictional base (tests/test_friction.cpp) at 2.5 mm cells, the
# size too slow for the test suite: stop distance and time within 2 % of v0^2/(2 mu g) and
# v0/(mu g), KE0 = friction work + stored energy within 1 %, for XPIC and APIC (FLIP: the distance;
# the affine FLIP: distance and time; docs/method.md, "How FLIP lifts the block").
#   scripts/friction_block.sh [build-dir]
set -e
build=${1:-build}
SKRED_FRICTION_CELLS=0.0025 "$build/tests/skred_tests" \
  --gtest_filter='FrictionalBlock.ThrownBlockStopsAtTheAnalyticDistanceAndTime:FrictionalBlock.AffineFlipStopsAtTheAnalyticDistanceAndTime'
