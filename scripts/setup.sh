#!/usr/bin/env bash
# Installs the Debian packages the project needs, only those missing.
# Runs as root (the project's machines do); uses sudo otherwise when present.
set -euo pipefail
packages=(build-essential cmake libcgal-dev libgmp-dev libmpfr-dev libboost-dev
          nlohmann-json3-dev libcli11-dev libgtest-dev libbenchmark-dev xz-utils
          libxxhash-dev zlib1g-dev python3-meshio gmsh gzip
          clang-format clang-tidy emscripten chromium libdraco-dev libeigen3-dev draco
          libtbb-dev tetgen
          # python3-paraview also gives Python VTK's modules (vtk, vtkmodules), which
          # the format tests use as an independent reader and writer: Debian
          # makes it conflict with python3-vtk9, so that one is not listed.
          python3-numpy python3-pytest python3-venv python3-pip python3-setuptools python3-pybind11
          pybind11-dev paraview python3-paraview xvfb
          # mpirun meshdec (optional in the build; its test needs it)
          libopenmpi-dev openmpi-bin)
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
