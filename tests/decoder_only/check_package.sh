#!/usr/bin/env bash
# Installs the project from BUILD into a scratch prefix, builds the tiny
# decoder against the installed package (find_package(dtmesh COMPONENTS
# decoder)), and decodes STREAM with it.
#   check_package.sh BUILD SCRATCH STREAM
set -euo pipefail
build=$1 scratch=$2 stream=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" >/dev/null
cmake -S "$here" -B "$scratch/build" -DCMAKE_PREFIX_PATH="$scratch/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$scratch/build" >/dev/null
"$scratch/build/tiny_decoder" "$stream"
