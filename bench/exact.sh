#!/usr/bin/env bash
# bench/exact.sh [BUILD_DIR] -- what --exact costs (level 0 = the input's
# tetrahedra, spec/FORMAT.md §3.10): on the TetGen corpus (the 10k models,
# bunny_100k and bunny_1m, --box 256 --dmax 2) and on the gmsh and Netgen parts of
# bench/quality_cap.sh (run it first, or this makes them). Per mesh: how
# many input cells are Delaunay cells, the stream with and without --exact
# (the same grid: a model whose cells need a finer grid gets it in both),
# the extra bits per vertex and per non-Delaunay cell, what the exact cell
# section and the carving took of them, and the time to decode level 0
# (in-process, bench_hierarchy --peak-memory X decode) against one
# sequential CGAL construction of the same points (... cgal). Writes
# bench/results/EXACT.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
bench=$build/bench/bench_hierarchy
py=/usr/bin/python3
work=$build/exact-data
mkdir -p "$work"
regions=$build/regions-data
[ -f "$regions/netgen_fine.msh" ] && [ -f "$regions/gmsh_part.msh" ] || "$root/bench/quality_cap.sh" "$build" > /dev/null
cd "$work"
models=(bunny_10k elephant_10k fandisk_11k hand_10k knot1_10k torus_10k triceratops_10k bunny_100k bunny_1m)
for m in "${models[@]::${#models[@]}-1}"; do
  for ext in node ele; do [ -f $m.$ext ] || xz -dc "$root/data/$m.$ext.xz" > $m.$ext; done
done
# bunny_1m as bench/run.sh makes it (TetGen, ~70 s), shared with its data.
large=$build/bench-data
if [ ! -s "$large/bunny_1m.ele" ]; then
  mkdir -p "$large"
  "$root/data/make_large.sh" -o "$large" bunny_1m >&2
fi
for ext in node ele; do ln -sf "$large/bunny_1m.$ext" bunny_1m.$ext; done
cp "$regions/gmsh_part.msh" "$regions/netgen_fine.msh" .
for input in "${models[@]/%/.node}" gmsh_part.msh netgen_fine.msh; do
  m=${input%.*}
  extra=()
  case $input in *.node) extra=(--box 256 --dmax 2) ;; esac
  # A model whose cells turn flat on the default grid: the grid meshenc names.
  if ! "$enc" $input -q -o $m.exact.dtm --report $m.exact.json --exact "${extra[@]}" 2> $m.err; then
    q=$(sed -n 's/.*--qbits \([0-9]*\) keeps.*/\1/p' $m.err)
    [ -n "$q" ] || { cat $m.err; exit 1; }
    extra+=(--qbits $q)
    /usr/bin/time -f "%e %M" -o $m.exact.time "$enc" $input -q -o $m.exact.dtm --report $m.exact.json --exact "${extra[@]}"
  else
    /usr/bin/time -f "%e %M" -o $m.exact.time "$enc" $input -q -o $m.exact.dtm --report $m.exact.json --exact "${extra[@]}"
  fi
  /usr/bin/time -f "%e %M" -o $m.plain.time "$enc" $input -q -o $m.plain.dtm --report $m.plain.json "${extra[@]}"
  # Format 11.0's section (the apexes ranked among all their candidates).
  "$enc" $input -q -o $m.v11.dtm --report $m.v11.json --exact-v11 "${extra[@]}"
  # The points as the decoder has them, for the construction; each stream
  # decoded in a process of its own.
  [ $input = $m.node ] || "$dec" $m.plain.dtm -q -o $m.node
  "$bench" --peak-memory $m.node cgal > $m.cgal.txt
  for kind in plain exact; do
    cp $m.$kind.dtm $m.dtm
    "$bench" --peak-memory $m.node decode > $m.$kind.decode.txt
  done
  rm -f $m.dtm
done
"$py" - "${models[@]}" gmsh_part netgen_fine <<'PY'
import json, re, sys
def seconds(path):
    return float(re.search(r"seconds=([0-9.]+)", open(path).read()).group(1))
def wall(path):
    return float(open(path).read().split()[-2])
what = {"gmsh_part": "gmsh part, 2 materials (gmsh 4.8.4)", "netgen_fine": "Netgen part (Netgen 6.2, maxh 0.03)"}
rows = ["| mesh | vertices | cells | Delaunay cells | non-Delaunay cells | stream | with --exact | extra bits/vertex "
        "| exact section bits/vertex | 11.0's | carving bits/vertex | bits per non-Delaunay cell | apex rank 0 | 11.0's "
        "| decode / construction | decode without | encode time x |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
for m in sys.argv[1:]:
    p, e = json.load(open(m + ".plain.json")), json.load(open(m + ".exact.json"))
    x, v11 = e["exact"], json.load(open(m + ".v11.json"))["exact"]
    n, cells = e["input_points"], x["delaunay_cells"] + x["fill_cells"]
    extra = 8.0 * (e["stream_bytes"] - p["stream_bytes"])
    carving = 8.0 * (e["levels"][0]["carving_bytes"] - p["levels"][0]["carving_bytes"])
    construction = seconds(m + ".cgal.txt")
    rows.append("| %s%s | %d | %d | %.1f%% | %d | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f%% | %.0f%% | %.2fx (%.2f s / %.2f s) | %.2fx | %.2fx |" % (
        what.get(m, m), " (q=%d)" % e["qbits"] if e["qbits"] != 14 and m not in what else "", n, cells,
        100.0 * x["delaunay_cells"] / cells, x["fill_cells"], p["stream_bytes"], e["stream_bytes"], extra / n,
        8.0 * x["bytes"] / n, 8.0 * v11["bytes"] / n, carving / n, extra / max(x["fill_cells"], 1),
        100.0 * x["rank_zero"] / max(x["fill_cells"], 1), 100.0 * v11["rank_zero"] / max(x["fill_cells"], 1),
        seconds(m + ".exact.decode.txt") / construction, seconds(m + ".exact.decode.txt"), construction,
        seconds(m + ".plain.decode.txt") / construction, wall(m + ".exact.time") / wall(m + ".plain.time")))
out = ["# --exact: level 0 as the input's own tetrahedra", "",
       "Made by `bench/exact.sh` (one run each, this project's 2-core machine). Per mesh, `meshenc M --exact` "
       "against `meshenc M` on the same grid (--box 256 --dmax 2 for the TetGen corpus; triceratops_10k has a "
       "sliver of 5e-8 the median cell's volume, flat on the default 14-bit grid, so both of its streams use "
       "the grid meshenc names, q=17). *Extra* = the whole stream's growth; it is the exact cell section "
       "(the non-Delaunay cells, grown face by face) plus what the carving section spends to keep exactly "
       "the Delaunay cells that are input cells (the rest of the difference is the layer header). "
       "*Decode / construction*: level 0 decoded in-process (`bench_hierarchy --peak-memory M.node decode`: "
       "every layer inserted, the carving, the exact cells) over one sequential CGAL construction of the "
       "same points (`... cgal`). *Encode time x*: whole `meshenc` processes, with over without.", ""] + rows + [
       "", "## What it shows", "",
       "* **Where the bits go.** The exact cell section is cheap where the mesher kept close to Delaunay: "
       "on the gmsh and Netgen parts the first candidate is the apex for 93-95% of the non-Delaunay cells "
       "(0.11-0.13 bits a vertex). Most of the extra is the carving: saying which Delaunay cells are not "
       "the input's (alpha keeps them: they lie inside the solid) costs 3-5 bits per non-Delaunay cell on these two parts. "
       "The TetGen models with many slivers (hand_10k, triceratops_10k) are the other way round: their "
       "non-Delaunay cells are less often the Delaunay-like apex (54-63%) and some apexes are not Delaunay "
       "neighbours of their face at all (130-146 sent by index).",
       "* **Against the targets** (#42: at most 1.5 bits a vertex; decode at most 1.3x one construction): "
       "met on 9 of the 11 meshes for the bits (not on hand_10k and triceratops_10k, whose slivers make "
       "the fill itself expensive); not met for the decoding time (below). The carving's contexts are "
       "split by each cell's Delaunay margin (spec/FORMAT.md §3.2): the Delaunay cells that are not the "
       "input's have a median margin of 0.087 (how far the nearest neighbour's far corner lies outside the "
       "circumsphere, over its radius) against 0.305 for those that are (Netgen part); the split took "
       "the Netgen part from 1.58 to 1.37 extra bits a vertex, the gmsh part from 1.36 to 1.23. "
       "Ordering the candidates by the new cell's shape instead of the in-sphere test was tried and is "
       "worse everywhere (rank 0 for 34-85% of the cells against 54-95%). Putting first the "
       "candidates that are corners of the removed Delaunay cells around the face (the cavity the input's "
       "cells refill) was tried too, and moves the exact section by 3% at most either way: 1779 -> "
       "1810-1817 bytes on hand_10k, 3060 -> 3070-3154 on triceratops_10k, 455 -> 446-452 on bunny_10k, "
       "799 -> 789-797 on fandisk_11k: the in-sphere order already holds what the cavity tells.",
       "* **Decoding.** The fill walks the open faces, found through a hash of their corners (chained in "
       "the faces' own array), with a per-vertex list of Delaunay cells for the candidates; its in-sphere "
       "tests are CGAL's exact predicates. Its cost over the default decode is the \"decode / "
       "construction\" against \"decode without\" columns: 0.2-0.5x one construction where the "
       "times are long enough to tell (bunny_1m 0.41x: the carving's margin contexts about 0.7 s, the fill "
       "1.0 s, the per-vertex cell lists 0.4 s, the opening of the kept cells' faces 0.2 s, and since "
       "2026-12-02 the check that no two cells overlap (spec/FORMAT.md §3.10) 0.4-0.5 s on 2 cores: 1.0M "
       "tests of a Delaunay cell against a fill cell and 0.36M comparisons of fill cells, measured apart; "
       "the 10k models' columns, at constructions of 0.05 s, move by up to 0.6x from one run to the "
       "next). The default decode of these meshes is itself 1.6-2.5x one sequential construction on "
       "this 2-core machine (the construction here is CGAL's of the input points, one core), so the "
       "target of 1.3x is out of reach for the exact decode as long as the default one is above it."]
open("EXACT.md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
cp EXACT.md "$root/bench/results/EXACT.md"
