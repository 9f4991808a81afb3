#!/usr/bin/env bash
# The main job on the bundled samples: install what is missing, build, build
# the level-of-detail hierarchy of the seed paper's torus (its preset) and of
# the bunny (the codec's),
# encode each into a .dtm stream, decode every level back, and print the
# tables.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" --tools
bin="$root/build/tools"
out="$root/build/demo"
mkdir -p "$out"
xz -dc "$root/data/bunny_10k.node.xz" > "$out/bunny_10k.node"
xz -dc "$root/data/bunny_10k.ele.xz" > "$out/bunny_10k.ele"

echo "== the seed paper's torus: torus_288 scaled so that alpha_0 matches its 19.6 (Figure 6), Dmax = 3, --preset paper"
"$bin/meshenc" "$root/data/torus_288.node" --scale 25 --dmax 3 --preset paper --hash-cells \
  -o "$out/torus_288.dtm" --report "$out/torus_288.json"
echo
echo "== bunny_10k (TetGen .node + .ele) in a 256-unit box, Dmax = 2: the codec's levels, carved to the input's solid"
"$bin/meshenc" "$out/bunny_10k.node" --box 256 --dmax 2 --hash-cells \
  -o "$out/bunny_10k.dtm" --report "$out/bunny_10k.json"
echo
echo "== decoding every level of bunny_10k.dtm (meshinfo --stats), checked against the encoder's cell hashes"
"$bin/meshinfo" "$out/bunny_10k.dtm" --stats
"$bin/meshdec" "$out/bunny_10k.dtm" -o "$out/bunny_10k.vtu" --verify
"$bin/meshdec" "$out/bunny_10k.dtm" -o "$out/bunny_10k_level2.vtu" --level 2
echo
echo "== a truncated stream: the first 20,000 bytes"
head -c 20000 "$out/bunny_10k.dtm" | "$bin/meshdec" - -o "$out/bunny_10k_preview.vtu"
echo
echo "== a CT-like volume (data/ct_torus.nrrd, 48^3 int16, 0.5 mm voxels): the solid at threshold 0, interior voxels every 2nd, with their CT numbers (the field 'value')"
"$bin/meshenc" "$root/data/ct_torus.nrrd" --threshold 0 --voxel-interior-step 2 --dmax 0.5 --levels 8 --hash-cells \
  -o "$out/ct_torus.dtm"
"$bin/meshdec" "$out/ct_torus.dtm" -o "$out/ct_torus.vtu" --verify
"$bin/meshdec" "$out/ct_torus.dtm" -o "$out/ct_torus_level2_surface.ply" --level 2
echo
echo "Outputs in $out (open the .vtu files in ParaView; colour by 'level', or by 'value' for the CT)."
echo "To watch a stream arrive level by level in the browser viewer:"
echo "  scripts/view.sh $out/bunny_10k.dtm --rate 100KB/s"
