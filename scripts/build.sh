#!/usr/bin/env bash
# Configures and builds the project in build/ (Release).
#   scripts/build.sh [CMAKE_ARGS...]          everything: libraries, tools,
#                                             tests, benchmarks
#   scripts/build.sh --tools [CMAKE_ARGS...]  the libraries and the tools
#                                             meshenc, meshdec, meshinfo only
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [ "${1:-}" = "--tools" ]; then
  shift
  "$root/scripts/setup.sh"
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DDTM_BUILD_TESTS=OFF -DDTM_BUILD_BENCH=OFF "$@" >/dev/null
  cmake --build "$root/build" -j "$(nproc)" --target meshenc meshdec meshinfo
  exit
fi
"$root/scripts/setup.sh" --all
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DDTM_BUILD_TESTS=ON -DDTM_BUILD_BENCH=ON "$@" >/dev/null
cmake --build "$root/build" -j "$(nproc)"
