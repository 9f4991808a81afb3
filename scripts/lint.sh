#!/usr/bin/env bash
# The code's form, checked: every tracked C++ file as clang-format writes it
# (.clang-format), and clang-tidy's checks (.clang-tidy) clean on every library
# and tool source file.
#   scripts/lint.sh BUILD_DIR      BUILD_DIR holds compile_commands.json
#   scripts/lint.sh --fix          reformat in place (no tidy)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
mapfile -t files < <(git ls-files '*.h' '*.cpp')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  exit
fi
build="${1:?usage: scripts/lint.sh BUILD_DIR | --fix}"
if ! clang-format --dry-run -Werror "${files[@]}" 2>/tmp/lint_format.$$; then
  head -40 /tmp/lint_format.$$ >&2
  rm -f /tmp/lint_format.$$
  echo "lint: files differ from clang-format's output; scripts/lint.sh --fix rewrites them" >&2
  exit 1
fi
rm -f /tmp/lint_format.$$
# Library and tool sources only: tests and benchmarks follow the format, not tidy.
run-clang-tidy -p "$build" -j "$(nproc)" -quiet "$root/(common|bitstream|mesh|core|codec|tools|web)/.*\.cpp$" \
  > "$build/clang-tidy.log" 2>&1 || {
  grep -E "(error|warning):" "$build/clang-tidy.log" | sort -u | head -40 >&2
  echo "lint: clang-tidy found the above (full log: $build/clang-tidy.log)" >&2
  exit 1
}
echo "lint: clang-format and clang-tidy clean"
