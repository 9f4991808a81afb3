#!/usr/bin/env bash
# web/test/make_streams.sh MESHENC OUT_DIR -- the streams the web tests decode:
# every TetGen corpus model of data/ (codec preset, --box 256 --dmax 2, its
# .ele as the reference solid where data/ has it) and the CT torus with its
# values. Streams newer than both their input and meshenc are kept: a rebuilt
# encoder makes them anew, so the tests see what it writes today.
set -euo pipefail
meshenc=$1
out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
for node in "$root"/data/*_10k.node.xz "$root"/data/*_11k.node.xz; do
  model=$(basename "$node" .node.xz)
  [ -s "$out/$model.dtm" ] && [ "$out/$model.dtm" -nt "$node" ] && [ "$out/$model.dtm" -nt "$meshenc" ] && continue
  xz -dc "$node" > "$out/$model.node"
  ele="$root/data/$model.ele.xz"
  if [ -f "$ele" ]; then xz -dc "$ele" > "$out/$model.ele"; fi
  "$meshenc" "$out/$model.node" --box 256 --dmax 2 --hash-cells -q -o "$out/$model.dtm"
  rm -f "$out/$model.node" "$out/$model.ele"
done
if [ ! -s "$out/ct_torus.dtm" ] || [ "$meshenc" -nt "$out/ct_torus.dtm" ]; then
  "$meshenc" "$root/data/ct_torus.nrrd" --threshold 0 --voxel-interior-step 2 --dmax 0.5 --levels 8 \
    --hash-cells -q -o "$out/ct_torus.dtm"
fi
ls "$out"/*.dtm
