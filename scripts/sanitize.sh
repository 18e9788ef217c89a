#!/usr/bin/env bash
# Builds skred (Debug: the instrumented optimised build takes very long to compile) with
# AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ and runs the
# point-lifecycle and checkpoint tests and the other fast unit tests under them: a read or
# write past the end of any per-point array (e.g. after points are added or removed mid-run)
# fails the run.
# (The command-line checkpoint test is left out: its runs take minutes in this unoptimised,
# instrumented build.)
#   bash scripts/sanitize.sh [gtest filter]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DSKRED_SANITIZE=ON -DSKRED_NATIVE=OFF
cmake --build build-asan -j2
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
filter="${1:-Lifecycle.*:Checkpoint.*:Stability.*:Shape.*:IoTest.*:Scenario.*:BuildParticles.*:Principal.*:MohrCoulomb.*:VonMises.*:PostInvariants.*:PostStrain.*:PostSplit.*-Checkpoint.CommandLine*}"
./build-asan/tests/skred_tests --gtest_filter="$filter"
