#!/usr/bin/env bash
# Builds the WebAssembly decoder and the viewer page into build-wasm/dist/
# (Debian's emscripten; three.js and esbuild from npm, pinned in
# web/package-lock.json). Extra arguments go to cmake.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh" --all
web="$root/web"
if [ ! -f "$web/node_modules/.package-lock.json" ] || [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]; then
  (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
fi
# Debian's emcc finds its node modules (acorn) there only when node itself is
# Debian's; this machine's node may be NodeSource's (cmake/wasm.cmake does the
# same for every link).
export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
emcmake cmake -S "$root" -B "$root/build-wasm" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$root/build-wasm" -j "$(nproc)"
