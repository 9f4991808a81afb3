# shellcheck shell=bash disable=SC2034  # the variables are the caller's
# Sourced by the benchmarks that time meshenc on bunny_1m
# (bench/encoder_cores.sh, bench/bricked_one_rank.sh): with $1 the build
# folder (default build/), sets root, build, enc (its meshenc), data (its
# bench-data/, holding bunny_1m, made by data/make_large.sh, ~70 s, when
# absent), work (a temporary folder removed on exit), cores and commit, and
# moves into data. `script` names the caller in its messages.
script=${script:-a benchmark}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
data=$build/bench-data
[ -x "$enc" ] || { echo "$script: $enc not built" >&2; exit 2; }
if [ ! -s "$data/bunny_1m.ele" ]; then
  mkdir -p "$data"
  "$root/data/make_large.sh" -o "$data" bunny_1m >&2
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cores=$(nproc)
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
cd "$data" || exit 2
