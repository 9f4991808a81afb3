#!/usr/bin/env bash
# bench/bricks.sh [BUILD_DIR] -- what bricked layers (meshenc --bricks, format
# 8.0) cost in bits and what a region decode reads: bunny_100k and bunny_1m
# (TetGen, --box 256 --dmax 2 --no-fields) encoded without bricks (with and
# without candidates) and with bricks of 256 and 2048 points, then 12 random
# boxes of 1% of the level's bounding box decoded from each bricked stream at
# level 0 (build/bench/region_decode, which checks every region against the
# whole level). Writes bench/results/BRICKS.md. The models come from
# bench/scale.sh's BUILD_DIR/bench-data (bunny_1m: data/make_large.sh).
#   BRICKS_MODELS="bunny_100k"  measures only those
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
data=$build/bench-data
meshenc=$build/tools/meshenc
region=$build/bench/region_decode
models=${BRICKS_MODELS:-bunny_100k bunny_1m}
for t in "$meshenc" "$region"; do [ -x "$t" ] || { echo "bricks.sh: $t not built" >&2; exit 2; }; done
out=$data/bricks
mkdir -p "$out"
report=$root/bench/results/BRICKS.md
size() { stat -c %s "$1"; }
{
  echo "# Bricked layers: bits and regions"
  echo
  echo "\`bench/bricks.sh\` at $(git -C "$root" rev-parse --short HEAD) ($(date -u +%Y-%m-%d))."
  echo "Streams: \`meshenc MODEL.node --box 256 --dmax 2 --no-fields\` and the options below."
  echo "Regions: 12 random boxes of 1% of level 0's bounding box, decoded from the"
  echo "file by \`build/bench/region_decode\` (reads by offset) and checked against"
  echo "the whole level filtered to the box; time against reading and decoding the"
  echo "whole level in the same run."
  echo
  echo "| model | stream | bytes | vs 7.0 without candidates | vs 7.0 | boxes | points in the boxes | read (mean) | read (max) | time vs whole |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
} >"$report"
for m in $models; do
  [ -s "$data/$m.node" ] || { echo "bricks.sh: $data/$m.node missing (bench/scale.sh makes it)" >&2; exit 2; }
  common=(--box 256 --dmax 2 --no-fields -q)
  "$meshenc" "$data/$m.node" "${common[@]}" -o "$out/$m.dtm"
  "$meshenc" "$data/$m.node" "${common[@]}" --no-candidates -o "$out/$m.nc.dtm"
  base=$(size "$out/$m.dtm")
  nc=$(size "$out/$m.nc.dtm")
  echo "| $m | 7.0 | $base | $(awk -v a="$base" -v b="$nc" 'BEGIN{printf "%+.1f%%", 100*(a/b-1)}') | | | | | | |" >>"$report"
  for bp in 2048 256; do
    f=$out/$m.bricks$bp.dtm
    "$meshenc" "$data/$m.node" "${common[@]}" --bricks --brick-points "$bp" -o "$f"
    b=$(size "$f")
    row=$("$region" "$f" 0 | tail -1)
    echo "$m --brick-points $bp: $row" >&2
    IFS='|' read -r _ boxes pts rmean rmax tratio _ <<<"$row"
    echo "| $m | --bricks --brick-points $bp | $b | $(awk -v a="$b" -v b="$nc" 'BEGIN{printf "%+.1f%%", 100*(a/b-1)}') | $(awk -v a="$b" -v b="$base" 'BEGIN{printf "%+.1f%%", 100*(a/b-1)}') |$boxes|$pts|$rmean|$rmax|$tratio|" >>"$report"
  done
done
echo "bricks.sh: wrote $report" >&2
