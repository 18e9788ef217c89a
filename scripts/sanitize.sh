#!/usr/bin/env bash
# Builds skred with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs
# the unit suite under them (default: the whole suite): a read or write past the end of any
# array, a use after free or after scope, a leak, a signed overflow or another undefined
# operation fails the run.
#   bash scripts/sanitize.sh                # the whole suite
#   bash scripts/sanitize.sh --quick        # point lifecycle, checkpoints, scenarios and bad
#                                           # input, output files (SANITIZE_QUICK below)
#   bash scripts/sanitize.sh 'Lifecycle.*'  # any gtest filter
# Set CMAKE_CXX_COMPILER_LAUNCHER=ccache to reuse objects between runs.
#
# The build is optimised (-O1, line tables only: -g1) and without forced inlining: CMake's
# SKRED_SANITIZE defines SKRED_NO_FORCE_INLINE, which turns skred's SKRED_INLINE
# (src/core/inline.hpp) into plain `inline` and leaves Eigen's EIGEN_STRONG_INLINE alone.
# With forced inlining the one file that then held both solvers took more than 9.5 CPU
# minutes and 4.6 GB; the 2D and 3D solvers are now also two files
# (src/solver/explicit_solver_{2d,3d}.cpp). At -O0 the simulation tests take far longer.
#
# Cost, measured with GCC 12 on the 2-core machine kind CI uses, while other builds ran on
# it (load average 5-9, so compiles got about 1/2.7 of a core each; CPU times are the
# figures to compare):
#   clean build (ccache refilled, -j2): 40 min wall, about 28 CPU minutes in all
#     (src/ and main.cpp about 14, tests/ about 14): some 14 min at -j2 on an idle machine.
#   worst file: src/solver/explicit_solver_3d.cpp, 1.3 GB peak (2d: 1.2 GB), about 95 CPU s
#     each; no other file above 1.1 GB.
#   suite (216 tests): more than an hour under that load (111 tests took 47 min, then time
#     ran out). --quick (74 tests): 14 min wall, 3 CPU minutes; CliErrors (80 `skred check`
#     processes, 0.8 CPU s each) 6 min of it,
#     Checkpoint.RestartReproducesTheUninterruptedRunBitForBit 2 min, IoTest's render/report
#     tests (Python) 3 min. Slowest of the rest: FrictionalBlock.ThrownBlockStopsAtThe-
#     AnalyticDistanceAndTime (more than 7 min; SKRED_FRICTION_CELLS=0.01 runs one grid of
#     the two), FrictionalBlock.SlidesWithTheAnalyticAcceleration and
#     ElasticColumn.IncrementalGravityReachesTheStaticState (1 min each).
# Cheaper instrumentation (-fno-sanitize-address-use-after-scope, or
# --param=asan-instrumentation-with-call-threshold=0) is not used: the worst file is now
# within 1.3 GB, and they would give up use-after-scope checks (Eigen temporaries) or slow
# the suite; their saving was not measured.
# Not in .ci/run: CI's Release build and suite take ~8.7 min of its 20, and even the quick
# subset needs the whole instrumented library (about 14 CPU min, 7 min at -j2) plus its tests
# (3.5 CPU min) and their run, which would take CI past 17 min.
set -euo pipefail
cd "$(dirname "$0")/.."
SANITIZE_QUICK='Lifecycle.*:Checkpoint.*:Schema.*:Scenario.*:Scenario3D.*:BuildParticles.*:CliErrors.*:IoTest.*:OutputFields.*'
filter=${1:-*}
[ "$filter" = --quick ] && filter=$SANITIZE_QUICK
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DSKRED_SANITIZE=ON -DSKRED_NATIVE=OFF \
  ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER}
cmake --build build-asan -j2 --target skred skred_tests
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
./build-asan/tests/skred_tests --gtest_filter="$filter"
