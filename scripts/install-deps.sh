#!/usr/bin/env bash
# Installs the Debian 12 packages skred needs to build, test and run (as root).
# With --run: only what building skred and running and drawing a scenario need (no GoogleTest,
# chromium, clang-format or pip: README's first command, which builds no tests).
set -euo pipefail
run_only=false
[ "${1:-}" = "--run" ] && run_only=true
# python3-matplotlib (with python3-numpy, python3-pil): `skred render` / `skred report`;
# chromium: the test that opens the HTML report headless; clang-format: the test that the
# sources follow .clang-format; zlib1g-dev: the compressed VTK frames; python3-pip,
# python3-setuptools, python3-wheel: installing python/ (skred_post) offline with
# `pip install --no-build-isolation ./python` (and its test); libpetsc-real-dev, pkg-config: the
# implicit integrator's linear solves (PETSc's KSP with MUMPS, src/implicit); libopenblas0-openmp:
# the BLAS under MUMPS (Debian's reference BLAS factorises 3 times slower; measured 2026-12-02);
# libgdal-dev: 3D ground from elevation rasters (GeoTIFF, CRS; src/scenario/raster.cpp; 27 s).
pkgs=(cmake make g++ libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev zlib1g-dev
      python3-numpy python3-matplotlib python3-pil libpetsc-real-dev pkg-config libopenblas0-openmp
      libgdal-dev)
# gdal-bin: the test that opens a written map with GDAL's own gdalinfo (tests/test_hazard_maps.cpp);
# openmpi-bin (already a dependency of PETSc's OpenMPI): mpirun, which starts the test of the step
# split among processes (tests/mpi).
$run_only || pkgs+=(libgtest-dev chromium clang-format python3-pip python3-setuptools python3-wheel gdal-bin
                    openmpi-bin)
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q 'install ok installed'; }
# VTK for Python: Debian's python3-vtk9, or the VTK of ParaView's python3-paraview, which
# replaces python3-vtk9 (installing python3-vtk9 would remove ParaView's). Either will do.
if ! installed python3-paraview && ! /usr/bin/python3 -c 'import vtkmodules.vtkIOXML' >/dev/null 2>&1; then
  pkgs+=(python3-vtk9)
fi
missing=()
for p in "${pkgs[@]}"; do installed "$p" || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
