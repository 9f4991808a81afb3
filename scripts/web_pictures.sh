#!/usr/bin/env bash
# scripts/web_pictures.sh [BUILD_DIR] -- remakes docs/viewer_*.png with the
# viewer itself: the picture tests of web/test/viewer.test.mjs, run with
# DTM_UPDATE_PICTURES=1 (the test suite writes the same pictures to
# BUILD_DIR/web-artifacts/screenshots/ on every run). Needs BUILD_DIR (default
# build) and build-wasm/ built (scripts/test.sh builds both); the input
# surfaces come from data/surfaces.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
"$root/web/test/make_streams.sh" "$build/tools/meshenc" "$build/web-streams" >/dev/null
export DTM_WEB_DIST=$root/build-wasm/dist DTM_LEVEL_SUMMARY=$build/web/level_summary DTM_WEB_STREAMS=$build/web-streams \
       DTM_SOURCE_DIR=$root DTM_WEB_ARTIFACTS=$build/web-artifacts DTM_UPDATE_PICTURES=1
node --test --test-name-pattern='picture' "$root/web/test/viewer.test.mjs"
ls "$root"/docs/viewer_*.png
