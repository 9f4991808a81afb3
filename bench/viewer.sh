#!/usr/bin/env bash
# bench/viewer.sh [BUILD_DIR] -- the viewer's figures, written to bench/results/VIEWER.md:
# WebAssembly decoding of bunny_100k against native (node and chromium),
# time to the first picture on a stream throttled to 1 MB/s and 100 KB/s
# against the whole stream's arrival, and the page's download size.
#
# BUILD_DIR (default: build) must hold meshenc and web/level_summary; the
# WebAssembly build is build-wasm/ (scripts/build_web.sh). bunny_100k comes
# from the repository's data/ and is encoded as meshenc does by default
# (--box 256 --dmax 2, its .ele as the reference solid; about a minute).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
data=$build/bench-data
mkdir -p "$data"
for tool in "$build/tools/meshenc" "$build/web/level_summary" "$root/build-wasm/dist/dtm_decoder.mjs"; do
  [ -e "$tool" ] || { echo "viewer.sh: $tool is missing: run scripts/build.sh and scripts/build_web.sh" >&2; exit 2; }
done
stream=$data/bunny_100k.dtm
if [ ! -s "$stream" ]; then
  for ext in node ele; do
    [ -s "$data/bunny_100k.$ext" ] || xz -dc "$root/data/bunny_100k.$ext.xz" > "$data/bunny_100k.$ext"
  done
  echo "viewer.sh: encoding bunny_100k (about a minute)" >&2
  "$build/tools/meshenc" "$data/bunny_100k.node" --box 256 --dmax 2 -q -o "$stream.tmp"
  mv "$stream.tmp" "$stream"
fi
export DTM_WEB_DIST=$root/build-wasm/dist DTM_LEVEL_SUMMARY=$build/web/level_summary DTM_WEB_STREAMS=$build/web-streams \
       DTM_SOURCE_DIR=$root DTM_WEB_ARTIFACTS=$build/web-artifacts
node "$root/bench/viewer.mjs" "$stream" "$root/bench/results/VIEWER.md"
