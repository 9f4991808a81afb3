#!/usr/bin/env bash
# The code's form, checked: every tracked C++ file as clang-format writes it
# (.clang-format), and clang-tidy's checks (.clang-tidy) clean on every
# library and tool source file.
#   scripts/lint.sh BUILD_DIR           formatting of every file; clang-tidy on
#                                       the sources not found clean before
#   scripts/lint.sh BUILD_DIR --record  the same, then records every source as
#                                       it is now in scripts/tidy_clean.txt
#                                       (commit it with the change)
#   scripts/lint.sh BUILD_DIR --all     clang-tidy on every source
#   scripts/lint.sh --fix               reformat in place (no tidy)
# BUILD_DIR holds compile_commands.json. What "found clean before" means:
# scripts/tidy_clean.txt lists a key per source that passed clang-tidy, a hash
# of the file, every project header it includes and the checks
# (scripts/tidy_keys.py); a source whose key is listed is not checked again.
# So the test suite spends clang-tidy's time (10-60 s a file, parsing CGAL)
# on what a change touched, and a fresh clone on nothing at all.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
mapfile -t files < <(git ls-files '*.h' '*.cpp')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  exit
fi
build="$(cd "${1:?usage: scripts/lint.sh BUILD_DIR [--record|--all] | --fix}" && pwd)"
mode="${2:-}"
log="$build/lint_format.log"
if ! clang-format --dry-run -Werror "${files[@]}" 2>"$log"; then
  head -40 "$log" >&2
  echo "lint: files differ from clang-format's output; scripts/lint.sh --fix rewrites them" >&2
  exit 1
fi
# Library and tool sources only: tests and benchmarks follow the format, not tidy.
clean="$root/scripts/tidy_clean.txt"
keys="$build/tidy_keys.txt"
python3 "$root/scripts/tidy_keys.py" "$build" > "$keys"
mapfile -t check < <(if [ "$mode" = "--all" ] || [ ! -f "$clean" ]; then
                       cut -d' ' -f2 "$keys"
                     else
                       grep -v -x -F -f "$clean" "$keys" | cut -d' ' -f2
                     fi)
if [ ${#check[@]} -gt 0 ]; then
  echo "lint: clang-tidy on ${#check[@]} of $(wc -l < "$keys") sources (the others were found clean as they are)"
  pattern="$(printf '%s|' "${check[@]}")"
  run-clang-tidy -p "$build" -j "$(nproc)" -quiet "$root/(${pattern%|})$" > "$build/clang-tidy.log" 2>&1 || {
    grep -E "(error|warning):" "$build/clang-tidy.log" | sort -u | head -40 >&2
    echo "lint: clang-tidy found the above (full log: $build/clang-tidy.log)" >&2
    exit 1
  }
fi
if [ "$mode" = "--record" ]; then
  cp "$keys" "$clean"
  echo "lint: recorded $(wc -l < "$clean") clean sources in scripts/tidy_clean.txt"
fi
echo "lint: clang-format and clang-tidy clean"
