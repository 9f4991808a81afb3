#!/usr/bin/env bash
# tests/golden/make.sh [BUILD_DIR] -- (re)writes the golden streams of the
# current format version and their expected levels. Run it only when the
# format's major version changes (spec/FORMAT.md §6), after moving the
# previous version's streams to v<major>/ (as v2/ to v6/ hold formats 2.0 to 6.0) if
# decoders still read it: a golden stream is a promise that every later
# decoder decodes it identically or refuses its version.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
enc=$build/tools/meshenc
info=$build/tools/meshinfo
make_one() {  # NAME INPUT meshenc-options...
  local name=$1 input=$2; shift 2
  "$enc" "$root/data/$input" -o "$here/$name.dtm" --hash-cells -q "$@"
  "$info" "$here/$name.dtm" --json | python3 -c '
import json, sys
info = json.load(sys.stdin)
print(json.dumps({
    "format": "dtm " + info["version"],
    "qbits": info["qbits"],
    "vertices": info["vertices"],
    "levels": [{"level": l["level"], "vertices": l["vertices"],
                "new_vertices": l["new_vertices"], "cell_hash": l["cell_hash"]}
               for l in info["levels"]]}, indent=1))' >"$here/$name.expected.json"
}
make_one torus_288 torus_288.node --scale 25 --dmax 3 --quality-floor 0 --removal-share 0.3
make_one torus_288_paper torus_288.node --scale 25 --dmax 3 --preset paper --quality-guard 0.3 --quality-floor 0
make_one torus_288_grid_q10_hull torus_288_grid.node --qbits 10 --alpha hull --levels 3
make_one torus_288_q24 torus_288.node --qbits 24 --levels 1
# 7.0: a TetGen mesh whose finer layers send points beside candidates.
make_one ellipsoid_793 ellipsoid_793.node --dmax 3
# 8.0: bricked layers (several chunks in the finer layers).
make_one ellipsoid_793_bricks ellipsoid_793.node --dmax 3 --bricks --brick-points 16 --block-points 100
# 8.0: bricked layers with values (the torus's TetGen markers, int32).
make_one torus_288_bricks torus_288.node --scale 25 --dmax 3 --bricks --brick-points 8 --block-points 64
