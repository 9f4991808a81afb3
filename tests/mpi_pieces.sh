#!/usr/bin/env bash
# tests/mpi_pieces.sh MESHENC MESHDEC DATA_DIR -- `mpirun -n P meshdec
# in.dtm -o out.pvtu` for P = 1, 2, 4 (oversubscribed: the machine may have
# fewer cores; as root, Open MPI wants --allow-run-as-root): each rank writes
# its pieces, and they are byte for byte the pieces one process writes with
# --pieces P; the pieces' cells add up to the whole level's; ParaView's
# reader opens the .pvtu to the same count with no complaint (where pvpython
# is installed), every piece declaring the arrays the .pvtu lists, empty
# pieces too, and a stream's regions as cell data; and meshenc reads it back
# as one mesh of level 0's vertices. The
# pieces' exact partition (every cell in one piece) is tests/test_bricks.cpp's
# BrickedStream.PiecesPartitionTheLevel.
set -euo pipefail
meshenc=$1 meshdec=$2 data=$3
command -v mpirun >/dev/null || { echo "mpi_pieces: mpirun missing (apt-get install openmpi-bin)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
as_root=()
[ "$(id -u)" -eq 0 ] && as_root=(--allow-run-as-root)
"$meshenc" "$data/bunny_10k.node" --bricks --brick-points 16 -q -o "$work/b.dtm"
"$meshdec" "$work/b.dtm" -o "$work/whole.vtu" -q
cells_of() { grep -oh 'NumberOfCells="[0-9]*"' "$@" | grep -o '[0-9]*' | awk '{s += $1} END {print s}'; }
whole=$(cells_of "$work/whole.vtu")
echo "whole level 0: $whole cells"
# ParaView's count of a grid's cells (with ARRAY: and per value of that
# cell array), or nothing when its reader complains (an array a piece lacks).
paraview_cells() {
  pvpython -c "
import sys
from paraview.simple import *
from paraview import servermanager
r = OpenDataFile('$1')
r.UpdatePipeline()
d = servermanager.Fetch(r)
if '${2:-}':
    a = d.GetCellData().GetArray('${2:-}')
    counts = {}
    for i in range(d.GetNumberOfCells()):
        counts[int(a.GetTuple1(i))] = counts.get(int(a.GetTuple1(i)), 0) + 1
    print(sorted(counts.items()))
else:
    print(d.GetNumberOfCells())" >"$work/pv.out" 2>"$work/pv.err" || true
  if grep -q 'ERR|' "$work/pv.err"; then
    grep 'ERR|' "$work/pv.err" | head -3 >&2
    return 0
  fi
  tail -1 "$work/pv.out"
}
failed=0
for p in 1 2 4; do
  mkdir -p "$work/mpi$p" "$work/one$p"
  mpirun --oversubscribe "${as_root[@]}" -n "$p" "$meshdec" "$work/b.dtm" -o "$work/mpi$p/b.pvtu"
  "$meshdec" "$work/b.dtm" -o "$work/one$p/b.pvtu" --pieces "$p" -q
  pieces=$(ls "$work/mpi$p"/b_*.vtu | wc -l)
  sum=$(cells_of "$work/mpi$p"/b_*.vtu)
  same=yes
  for f in "$work/one$p"/*; do cmp -s "$f" "$work/mpi$p/$(basename "$f")" || same=no; done
  listed=$(grep -c '<Piece Source=' "$work/mpi$p/b.pvtu")
  echo "mpirun -n $p: $pieces pieces listed $listed times, $sum cells; the same files as --pieces $p: $same"
  [ "$pieces" -eq "$p" ] && [ "$listed" -eq "$p" ] && [ "$sum" -eq "$whole" ] && [ "$same" = yes ] || failed=1
  if command -v pvpython >/dev/null; then
    pv=$(paraview_cells "$work/mpi$p/b.pvtu")
    echo "  ParaView reads $pv cells"
    [ "$pv" = "$whole" ] || failed=1
  fi
done
# A stream with regions (format 15.0, the gmsh part of two materials) in
# more pieces than some levels have bricks: every piece, the empty ones
# too, declares the arrays the .pvtu lists, and the cells' regions add up
# to the whole level's.
xz -dc "$(dirname "$0")/../data/two_materials.msh.xz" >"$work/two.msh"
"$meshenc" "$work/two.msh" --bricks --brick-points 16 --block-points 200 --no-face-tags -q -o "$work/two.dtm" 2>/dev/null
"$meshdec" "$work/two.dtm" --level 1 -o "$work/two_whole.vtu" -q
mkdir -p "$work/two"
"$meshdec" "$work/two.dtm" --level 1 -o "$work/two/p.pvtu" --pieces 9 -q
grep -q '<PDataArray type="Int32" Name="region"/>' "$work/two/p.pvtu" || { echo "no region array listed"; failed=1; }
for f in "$work/two"/p_*.vtu; do
  grep -q 'Name="level"' "$f" && grep -q 'Name="region"' "$f" || { echo "$(basename "$f") lacks level or region"; failed=1; }
done
two_whole=$(cells_of "$work/two_whole.vtu")
two_sum=$(cells_of "$work/two"/p_*.vtu)
echo "regions in 9 pieces of level 1: $two_sum cells, the level $two_whole"
[ "$two_sum" = "$two_whole" ] || failed=1
if command -v pvpython >/dev/null; then
  regions=$(paraview_cells "$work/two/p.pvtu" region)
  whole_regions=$(paraview_cells "$work/two_whole.vtu" region)
  echo "  ParaView: cells by region $regions (the whole level: $whole_regions)"
  [ -n "$regions" ] && [ "$regions" = "$whole_regions" ] || failed=1
fi
# meshenc reads the 4 pieces back as one mesh: the points the pieces share
# merged, every vertex of level 0 there.
"$meshenc" "$work/mpi4/b.pvtu" -o "$work/again.dtm" --no-fields >"$work/again.out" 2>&1 || { cat "$work/again.out"; failed=1; }
vertices=$(grep -o '^[^:]*b.pvtu: [0-9]* points, [0-9]* merged' "$work/again.out" | awk '{print $2 - $4}')
expected=$(grep -o 'NumberOfPoints="[0-9]*"' "$work/whole.vtu" | grep -o '[0-9]*')
echo "meshenc reads b.pvtu: $vertices distinct points (level 0 has $expected)"
[ "$vertices" = "$expected" ] || failed=1
# A damaged stream decoded over those pieces: every rank fails, and the
# earlier run's pieces and .pvtu are left as they were (each rank's files
# staged, put in place only once every rank has its own).
cp -r "$work/mpi4" "$work/before4"
size=$(stat -c %s "$work/b.dtm")
cp "$work/b.dtm" "$work/damaged.dtm"
printf '\x5a' | dd of="$work/damaged.dtm" bs=1 seek=$((size * 95 / 100)) conv=notrunc status=none
if mpirun --oversubscribe "${as_root[@]}" -n 4 "$meshdec" "$work/damaged.dtm" -o "$work/mpi4/b.pvtu" 2>"$work/err"; then
  echo "a damaged stream decoded"; failed=1
fi
diff -r "$work/before4" "$work/mpi4" >/dev/null || { echo "a failed decode changed the earlier pieces:"; ls -l "$work/mpi4"; cat "$work/err"; failed=1; }
# Fewer pieces over them: the earlier run's others are named, not taken.
mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshdec" "$work/b.dtm" -o "$work/mpi4/b.pvtu" 2>"$work/err"
grep -q "b_2.vtu, .*b_3.vtu: not pieces of" "$work/err" || { echo "the earlier pieces not named:"; cat "$work/err"; failed=1; }
# A stream that is not bricked: a clear error and no file.
"$meshenc" "$data/bunny_10k.node" --no-fields -q -o "$work/plain.dtm"
mkdir -p "$work/plain"
if mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshdec" "$work/plain.dtm" -o "$work/plain/p.pvtu" 2>"$work/err"; then
  echo "a stream that is not bricked made pieces"; failed=1
fi
grep -q "bricked stream" "$work/err" || { cat "$work/err"; failed=1; }
# Every rank met that error alike: it is printed once, not once a rank.
[ "$(grep -c "meshdec: error" "$work/err")" -eq 1 ] || { echo "the error printed more than once:"; cat "$work/err"; failed=1; }
[ -z "$(ls "$work/plain")" ] || { echo "files left behind: $(ls "$work/plain")"; failed=1; }
# Under mpirun an output other than a .pvtu: refused (every rank would
# decode the level and write the same file), said once, no file.
if mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshdec" "$work/plain.dtm" -o "$work/plain/p.vtu" 2>"$work/err"; then
  echo "mpirun meshdec -o p.vtu decoded"; failed=1
fi
grep -q -- "-o X.pvtu" "$work/err" || { cat "$work/err"; failed=1; }
[ -z "$(ls "$work/plain")" ] || { echo "files left behind: $(ls "$work/plain")"; failed=1; }
[ $failed -eq 0 ] && echo "mpi_pieces: ok"
exit $failed
