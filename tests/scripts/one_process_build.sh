#!/bin/bash
# A build without MPI and PETSc stays possible (cmake -DSKRED_MPI=OFF, issue 55). The whole of
# such a build takes minutes (docs/studies/2026-12-07-build-without-mpi.md, where its own check,
# tests/alone, was run), so the suite checks what differs from the default: the OFF
# configuration, the stand-ins for the sources that call MPI or PETSc (src/parallel/*_alone.cpp,
# src/implicit/linear_system_alone.cpp) and the check compile with the project's warnings as
# errors, and none of them asks for an MPI or PETSc symbol.
#   one_process_build.sh SOURCE_DIR
set -euo pipefail
src=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cmake -S "$src" -B "$out" -DSKRED_MPI=OFF -DCMAKE_CXX_FLAGS=-Werror > "$out/configure.log"
grep -q "SKRED_MPI=OFF" "$out/configure.log"
if grep -qiE "^(PETSC|MPI_C)_" "$out/CMakeCache.txt"; then
  echo "the OFF configuration looked for MPI or PETSc" >&2
  exit 1
fi
cd "$out"
make -s skred_parallel src/implicit/linear_system_alone.cpp.o tests/alone/check_one_process_build.cpp.o \
  > build.log
objects=$(find . -name "*_alone.cpp.o" -o -name "check_one_process_build.cpp.o")
[ "$(echo "$objects" | wc -w)" -eq 4 ] || {
  echo "expected the 4 objects of a build without MPI, found: $objects" >&2
  exit 1
}
asked=$(nm -u --demangle $objects libskred_parallel.a | grep -E "^ +U " | grep -iE "\b(MPI|ompi|Petsc|PetscSF)[A-Za-z_]*" || true)
if [ -n "$asked" ]; then
  echo "the build without MPI asks for MPI or PETSc:" >&2
  echo "$asked" >&2
  exit 1
fi
echo "a build without MPI: configured, its stand-ins compile and call no MPI or PETSc"
