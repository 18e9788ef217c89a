#!/usr/bin/env bash
# Builds skred with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs
# the unit suite under them (default: the whole suite): a read or write past the end of any
# array, a use after free, a leak, a signed overflow or another undefined operation fails
# the run.
# The build is optimised (-O1, line tables only: -g1) and without the forced inlining of the
# Release build (CMakeLists.txt, SKRED_SANITIZE), because at -O0 the instrumented simulation
# tests take minutes each. It is still slow to build: src/solver/explicit_solver.cpp alone
# took more than 9 CPU minutes and 4.5 GB of memory (measured with GCC 12 on the 2-core CI
# machine kind), which is why this build is not part of .ci/run (whole run < 20 min).
# Set CMAKE_CXX_COMPILER_LAUNCHER=ccache to reuse objects between runs.
#   bash scripts/sanitize.sh [gtest filter]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DSKRED_SANITIZE=ON -DSKRED_NATIVE=OFF \
  ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER}
cmake --build build-asan -j2 --target skred skred_tests
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
./build-asan/tests/skred_tests --gtest_filter="${1:-*}"
