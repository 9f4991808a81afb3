#!/usr/bin/env bash
# scripts/pictures.sh [BUILD_DIR] -- remakes docs/*_levels.png: the input's
# surface (data/surfaces), then every level of the codec's stream
# (meshenc's default preset, the model's TetGen .node + .ele from data/,
# --box 256 --dmax 2), and for the elephant the paper preset's coarsest level;
# docs/mri_values.png, a slice of the MRI's values at three levels; and
# docs/two_materials_levels.png, a gmsh part's levels cut open, coloured by
# region and tagged face (data/two_materials.geo, finer; pvbatch under Xvfb).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
bin=$build/tools
work=$build/pictures
corpus=${DTM_DATA:-$root/data}
surfaces=$corpus/surfaces
mkdir -p "$work"
for m in bunny elephant; do
  for ext in node ele; do xz -dc "$corpus/${m}_10k.$ext.xz" > "$work/${m}_10k.$ext"; done
  "$bin/meshenc" "$work/${m}_10k.node" --box 256 --dmax 2 -q -o "$work/$m.dtm"
  levels=$("$bin/meshinfo" "$work/$m.dtm" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['level_count'])")
  panels=("$surfaces/$m.off")
  for ((l = 0; l < levels; ++l)); do
    "$bin/meshdec" "$work/$m.dtm" -o "$work/${m}_level$l.ply" --level $l -q
    panels+=("$work/${m}_level$l.ply")
  done
  if [ "$m" = elephant ]; then
    "$bin/meshenc" "$work/${m}_10k.node" --box 256 --dmax 2 --preset paper -q -o "$work/${m}_paper.dtm"
    last=$(( $("$bin/meshinfo" "$work/${m}_paper.dtm" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['level_count'])") - 1 ))
    "$bin/meshdec" "$work/${m}_paper.dtm" -o "$work/${m}_paper_last.ply" --level $last -q
    panels+=("$work/${m}_paper_last.ply")
  fi
  /usr/bin/python3 "$root/scripts/render_levels.py" "$root/docs/${m}_levels.png" --elevation 90 --azimuth 0 "${panels[@]}"
done
# The MRI's values (data/fields/mri_s0.nrrd): its middle slice beside
# the same slice of levels 0, 2 and 4, and level 4's error.
mri=$corpus/fields/mri_s0.nrrd
"$bin/meshenc" "$mri" --threshold 150 -q -o "$work/mri.dtm"
for l in 0 2 4; do "$bin/meshdec" "$work/mri.dtm" --level $l -o "$work/mri_level$l.vtu" -q; done
/usr/bin/python3 "$root/scripts/render_values.py" "$root/docs/mri_values.png" "$mri" --slice 5 --threshold 150 \
  "$work/mri_level0.vtu" "$work/mri_level2.vtu" "$work/mri_level4.vtu"
# The gmsh part of two materials: its levels cut open by region and tag.
sed "s/Mesh.CharacteristicLengthMax = .*/Mesh.CharacteristicLengthMax = 0.3;/" "$corpus/two_materials.geo" \
  > "$work/two_materials.geo"
gmsh -3 "$work/two_materials.geo" -format msh41 -o "$work/two_materials.msh" >/dev/null
# Every level of a stream (STREAM, its .vtu files named PREFIX_L.vtu) cut
# open by region and tag into PNG.
render_region_levels() {  # STREAM PREFIX PNG
  local levels l parts=()
  levels=$("$bin/meshinfo" "$1" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['level_count'])")
  for ((l = 0; l < levels; ++l)); do
    "$bin/meshdec" "$1" --level $l -o "$work/$2_$l.vtu" -q
    parts+=("$work/$2_$l.vtu")
  done
  xvfb-run -a pvbatch "$root/scripts/render_regions.py" "$3" "${parts[@]}"
}
"$bin/meshenc" "$work/two_materials.msh" -q -o "$work/two_materials.dtm"
render_region_levels "$work/two_materials.dtm" level "$root/docs/two_materials_levels.png"
# The same part in bricked layers (format 17.0), built in blocks: its
# regions and tagged faces on every level, from the chunks.
"$bin/meshenc" "$work/two_materials.msh" -q --bricks --brick-points 256 --block-points 2000 \
  -o "$work/two_materials_bricks.dtm"
render_region_levels "$work/two_materials_bricks.dtm" bricks_level "$root/docs/two_materials_bricks_levels.png"
echo "$root/docs/bunny_levels.png $root/docs/elephant_levels.png $root/docs/mri_values.png"
