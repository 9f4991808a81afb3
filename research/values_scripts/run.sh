#!/usr/bin/env bash
# research/values_scripts/run.sh [WORK_DIR] [BUILD_DIR] -- reruns the measurements
# behind research/values_baselines.md (issue 13: how to code per-vertex values).
#
# WORK_DIR (default: build/research/values) receives the inputs the scripts
# read, made here from the repository's data/ with the built tools:
#   ct.dtm   meshenc data/ct_torus.nrrd --threshold 0 --voxel-interior-step 2
#   mri.dtm  meshenc data/fields/mri_s0.nrrd --threshold 150 --voxel-interior-step 2
#   bunny.dtm  meshenc bunny_10k.node (decompressed from data/bunny_10k.node.xz)
# and every level L of each stream as NAME_L<L>.node + NAME_L<L>.ele (meshdec
# --level L). Then the scripts run in order, each printing its figures and
# keeping them in WORK_DIR/SCRIPT.txt: extract.py (the voxel selection, its
# arrays and the compressors' sizes; the others read its arrays), run_vol.py,
# explore.py, explore2.py, explore3.py, table.py (the two volumes), field.py
# and field2.py (a smooth field on the bunny).
# BUILD_DIR (default: build) must hold tools/meshenc, meshdec and meshinfo.
# Needs python3 with numpy (PYTHON, default /usr/bin/python3: Debian's
# python3-numpy), zstd and xz. The codec has changed since the note was
# written, so the level counts and some figures may differ from it.
#   VALUES_SCRIPTS="table.py field2.py" runs only those (after the inputs).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${1:-$root/build/research/values}
build=${2:-$root/build}
case $work in /*) ;; *) work=$PWD/$work ;; esac
case $build in /*) ;; *) build=$root/$build ;; esac
python=${PYTHON:-/usr/bin/python3}
bin=$build/tools
for t in meshenc meshdec meshinfo; do
  [ -x "$bin/$t" ] || { echo "run.sh: $bin/$t not built (scripts/build.sh)" >&2; exit 2; }
done
for t in zstd xz; do
  command -v $t >/dev/null || { echo "run.sh: $t missing; apt-get install -y zstd xz-utils" >&2; exit 2; }
done
"$python" -c 'import numpy' 2>/dev/null ||
  { echo "run.sh: numpy missing for $python; apt-get install -y python3-numpy" >&2; exit 2; }
mkdir -p "$work"

# The streams and their levels, made once.
xz -dc "$root/data/bunny_10k.node.xz" > "$work/bunny_10k.node"
encode() {  # NAME INPUT meshenc-options...
  local name=$1 input=$2; shift 2
  [ -s "$work/$name.dtm" ] || "$bin/meshenc" -q "$input" "$@" -o "$work/$name.dtm"
  local levels
  levels=$("$bin/meshinfo" "$work/$name.dtm" --json | "$python" -c "import json,sys; print(json.load(sys.stdin)['level_count'])")
  rm -f "$work/${name}"_L*.node "$work/${name}"_L*.ele
  for ((l = 0; l < levels; ++l)); do
    "$bin/meshdec" -q "$work/$name.dtm" --level $l -o "$work/${name}_L$l.node"
  done
  echo "run.sh: $name: $levels levels" >&2
}
encode ct "$root/data/ct_torus.nrrd" --threshold 0 --voxel-interior-step 2
encode mri "$root/data/fields/mri_s0.nrrd" --threshold 150 --voxel-interior-step 2
encode bunny "$work/bunny_10k.node"

for s in ${VALUES_SCRIPTS:-extract.py run_vol.py explore.py explore2.py explore3.py table.py field.py field2.py}; do
  echo "== $s" >&2
  "$python" "$here/$s" "$work" | tee "$work/${s%.py}.txt"
done
