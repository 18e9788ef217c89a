#!/usr/bin/env bash
# Builds skred with AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs
# the whole unit suite under them: a read or write past the end of any array, a use after
# free, a leak, a signed overflow or another undefined operation fails the run.
# The build is optimised (-O1, line tables only) and without the forced inlining of the
# Release build (CMakeLists.txt, SKRED_SANITIZE): at -O0 the instrumented simulation tests
# take minutes each, and forced inlining makes the instrumented solver take over 15 minutes
# and 4 GB to compile.
#   bash scripts/sanitize.sh [gtest filter]
# Left out by default (each takes minutes instrumented; the same code runs in the shorter
# tests): none of the suite at present -- see SLOW below.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DSKRED_SANITIZE=ON -DSKRED_NATIVE=OFF ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER}
cmake --build build-asan -j2 --target skred skred_tests
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
SLOW=""
filter="${1:-*${SLOW:+-$SLOW}}"
./build-asan/tests/skred_tests --gtest_filter="$filter"
