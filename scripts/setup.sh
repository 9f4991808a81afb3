#!/usr/bin/env bash
# Installs the Debian packages the project needs, only those missing.
#   scripts/setup.sh          what the libraries and the tools meshenc, meshdec
#                             and meshinfo need (scripts/demo.sh)
#   scripts/setup.sh --all    and what the whole test suite, the viewer, the
#                             Python package, the ParaView reader, MPI and the
#                             benchmarks need (scripts/test.sh)
# Runs as root (the project's machines do); uses sudo otherwise when present.
set -euo pipefail
packages=(build-essential cmake xz-utils libcgal-dev libgmp-dev libmpfr-dev libboost-dev
          libtbb-dev nlohmann-json3-dev libcli11-dev libxxhash-dev pkg-config
          # .vtu blocks compressed as VTK's writers do (tools/formats/vtk_compression.cpp)
          zlib1g-dev liblz4-dev liblzma-dev
          # glTF and .drc surfaces (tools/formats/gltf_writer.cpp)
          libdraco-dev libeigen3-dev)
if [ "${1:-}" = "--all" ]; then
  packages+=(libgtest-dev libbenchmark-dev python3 gzip
             # The independent writers and readers the format tests check our
             # files against. python3-paraview also gives Python VTK's modules
             # (vtk, vtkmodules): Debian makes it conflict with python3-vtk9,
             # so that one is not listed.
             python3-meshio gmsh draco tetgen python3-netgen
             # Exodus II files in the tools (optional in the build, over netCDF,
             # HDF5 and OpenMPI's libraries), and through meshio (python/tests:
             # test_exodus_through_meshio; tests/mesher_outputs.sh: meshio's files)
             libexodusii-dev python3-netcdf4
             # XDMF with HDF5 (FEniCS's and dolfinx's mesh files) through meshio
             # (python/tests: test_xdmf_as_fenics_users_convert_gmsh_meshes)
             python3-h5py
             # Draco's and zstd's sizes beside ours (bench/baselines.sh)
             zstd
             # The test "lint" (scripts/lint.sh)
             clang-format clang-tidy
             # The WebAssembly decoder and the viewer, tested in Chromium
             emscripten chromium
             # The Python package and the ParaView reader, installed and run as a user would
             python3-numpy python3-pytest python3-venv python3-pip python3-setuptools python3-pybind11
             pybind11-dev paraview python3-paraview xvfb
             # mpirun meshenc and meshdec (optional in the build; their tests need it)
             libopenmpi-dev openmpi-bin)
  # The viewer's JavaScript dependencies come through npm (scripts/build_web.sh):
  # Debian's package where no npm is on the PATH (a Node.js from elsewhere,
  # NodeSource's, carries its own and conflicts with Debian's npm).
  command -v npm >/dev/null || packages+=(npm)
elif [ $# -gt 0 ]; then
  echo "usage: $0 [--all]" >&2
  exit 2
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "setup: installing ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null && SUDO=sudo
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
