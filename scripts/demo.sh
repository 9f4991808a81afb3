#!/usr/bin/env bash
# The main job on the bundled samples: install what is missing, build, and
# build the level-of-detail hierarchy of the seed paper's torus and of the
# bunny, printing the level table of each.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
enc="$root/build/tools/meshenc"
out="$root/build/demo"
mkdir -p "$out"
xz -dc "$root/data/bunny_10k.node.xz" > "$out/bunny_10k.node"

echo "== torus_288, scaled so that alpha_0 matches the paper's 19.6 (Figure 6), Dmax = 3"
"$enc" "$root/data/torus_288.node" --scale 25 --dmax 3 --report "$out/torus_288.json"
echo
echo "== bunny_10k in a 256-unit box, Dmax = 2 (the paper's Cat settings)"
"$enc" "$out/bunny_10k.node" --box 256 --dmax 2 --report "$out/bunny_10k.json"
echo
echo "JSON reports: $out/torus_288.json $out/bunny_10k.json"
