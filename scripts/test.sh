#!/usr/bin/env bash
# The whole test suite: install what is missing, build, run every test.
#   scripts/test.sh              Release build in build/, the WebAssembly
#                                decoder and the viewer page in build-wasm/
#                                (their tests run in node and in chromium)
#   scripts/test.sh --sanitize   the native suite built with ASan and UBSan in
#                                build-asan/ (any finding fails the run)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [ "${1:-}" = "--sanitize" ]; then
  "$root/scripts/setup.sh" --all
  # RelWithDebInfo: optimized enough for the suite to run in minutes, with
  # line numbers in sanitizer reports. Benchmarks are not built; the web
  # tests run in the Release suite (the sanitizers cannot see into wasm).
  cmake -S "$root" -B "$root/build-asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDTM_SANITIZE=ON \
        -DDTM_BUILD_BENCH=OFF -DDTM_WEB_TESTS=OFF >/dev/null
  cmake --build "$root/build-asan" -j "$(nproc)"
  cd "$root/build-asan"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  ctest --output-on-failure -j "$(nproc)"
  exit
fi
"$root/scripts/build.sh"
"$root/scripts/build_web.sh"
cd "$root/build"
# One job more than cores: many tests wait on processes they start.
ctest --output-on-failure -j "$(($(nproc) + 1))"
