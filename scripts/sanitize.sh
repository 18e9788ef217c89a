#!/usr/bin/env bash
# Builds skred with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs the
# point-lifecycle and checkpoint tests and the other fast unit tests under them: a read or
# write past the end of any per-point array (e.g. after points are added or removed mid-run)
# fails the run.
#   bash scripts/sanitize.sh [extra gtest filter]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKRED_SANITIZE=ON -DSKRED_NATIVE=OFF
cmake --build build-asan -j2
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
filter="${1:-Lifecycle.*:Checkpoint.*:Shape.*:IoTest.*:Scenario.*:BuildParticles.*:Principal.*:MohrCoulomb.*:VonMises.*:PostInvariants.*:PostStrain.*:PostSplit.*:Stages.*:CollidingDiscs.FusedMap*}"
./build-asan/tests/skred_tests --gtest_filter="$filter"
