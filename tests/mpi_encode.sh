#!/usr/bin/env bash
# tests/mpi_encode.sh MESHENC MESHDEC DATA_DIR -- `mpirun -n P meshenc
# --bricks` for P = 1, 2, 4 (oversubscribed: the machine may have fewer
# cores; as root, Open MPI wants --allow-run-as-root) writes byte for byte
# the stream one process writes, whose levels decode to the encoder's
# (meshdec --verify against the cell hashes); only rank 0 writes; an input
# that does not exist fails every rank, named once, and leaves no
# file; without --bricks, mpirun meshenc says what to add. The ranks answer
# each other's questions about the reference while they work (no block run
# again), or, asked to take MPI without threads, in their exchanges (blocks
# run again): the same bytes. With regions (a TetGen .ele's attribute, a
# gmsh part's materials made here by gmsh), and with cell data (that
# part's, given an $ElementData here), the same bytes too.
set -euo pipefail
meshenc=$1 meshdec=$2 data=$3
command -v mpirun >/dev/null || { echo "mpi_encode: mpirun missing (apt-get install openmpi-bin)"; exit 1; }
command -v gmsh >/dev/null || { echo "mpi_encode: gmsh missing (scripts/setup.sh --all)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
as_root=()
[ "$(id -u)" -eq 0 ] && as_root=(--allow-run-as-root)
# Blocks of about 1000 points: several per level, seams everywhere.
options=(--box 256 --dmax 2 --no-fields --bricks --brick-points 64 --block-points 1000 --hash-cells)
"$meshenc" "$data/bunny_10k.node" "${options[@]}" -q -o "$work/one.dtm"
"$meshdec" "$work/one.dtm" -o "$work/one.vtu" --verify
failed=0
for p in 1 2 4; do
  mkdir -p "$work/mpi$p"
  mpirun --oversubscribe "${as_root[@]}" -n "$p" "$meshenc" "$data/bunny_10k.node" "${options[@]}" \
    -o "$work/mpi$p/b.dtm" >"$work/report$p"
  same=no
  cmp -s "$work/one.dtm" "$work/mpi$p/b.dtm" && same=yes
  files=$(ls "$work/mpi$p" | wc -l)
  echo "mpirun -n $p meshenc: $(stat -c %s "$work/mpi$p/b.dtm") bytes, the same bytes as one process: $same; $files file(s) written"
  [ "$same" = yes ] && [ "$files" -eq 1 ] || failed=1
  # The ranks hold the reference in parts and answer each other's questions
  # while they work (Open MPI with threads): no block is built twice.
  if [ "$p" -gt 1 ]; then
    grep "reference in parts" "$work/report$p" || true
    grep -q "answered by the ranks while they worked" "$work/report$p" || { echo "no question answered at once"; failed=1; }
    if grep -q "each run again" "$work/report$p"; then echo "blocks run again"; failed=1; fi
  fi
done
# The .ele's tetrahedra sent to the ranks that hold them in pieces of 100
# (each rank sends and receives many, a piece to each rank at a time):
# the same bytes.
mkdir -p "$work/pieces"
DTM_MPI_PIECE=100 mpirun --oversubscribe "${as_root[@]}" -x DTM_MPI_PIECE -n 3 "$meshenc" \
  "$data/bunny_10k.node" "${options[@]}" -q -o "$work/pieces/b.dtm"
cmp -s "$work/one.dtm" "$work/pieces/b.dtm" || { echo "mpirun -n 3, the .ele sent in pieces: not the same bytes"; failed=1; }
# Ranks whose pieces differ in size refuse on every rank (a receiver sizes
# each piece by its own), said once, and write nothing.
if DTM_MPI_PIECE=1000 mpirun --oversubscribe "${as_root[@]}" -x DTM_MPI_PIECE -n 2 sh -c \
  '[ "$OMPI_COMM_WORLD_RANK" = 1 ] && export DTM_MPI_PIECE=2000; exec "$@"' sh "$meshenc" \
  "$data/bunny_10k.node" "${options[@]}" -q -o "$work/pieces/c.dtm" 2>"$work/err"; then
  echo "pieces of two sizes encoded"; failed=1
fi
[ "$(grep -c "bunny_10k.ele: MPI: the ranks' pieces differ" "$work/err")" -eq 1 ] || { echo "pieces of two sizes: not said once:"; cat "$work/err"; failed=1; }
[ ! -e "$work/pieces/c.dtm" ] || { echo "pieces of two sizes: a file written"; failed=1; }
# An MPI without threads (asked for as one): the ranks answer each other in
# their exchanges, blocks run again, and the bytes are the same.
mkdir -p "$work/funneled"
DTM_MPI_ONE_THREAD=1 mpirun --oversubscribe "${as_root[@]}" -x DTM_MPI_ONE_THREAD -n 2 "$meshenc" \
  "$data/bunny_10k.node" "${options[@]}" -o "$work/funneled/b.dtm" >"$work/report_funneled"
grep "reference in parts" "$work/report_funneled" || true
cmp -s "$work/one.dtm" "$work/funneled/b.dtm" || { echo "mpirun -n 2 without threads: not the same bytes"; failed=1; }
grep -q "each run again" "$work/report_funneled" || { echo "without threads, no block run again"; failed=1; }
# A missing input: every rank fails, naming it; nothing is written.
mkdir -p "$work/missing"
if mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshenc" "$work/nothing.node" "${options[@]}" -q \
  -o "$work/missing/b.dtm" 2>"$work/err"; then
  echo "a missing input encoded"; failed=1
fi
grep -q "nothing.node" "$work/err" || { cat "$work/err"; failed=1; }
[ "$(grep -c "meshenc: error:" "$work/err")" -eq 1 ] || { echo "a missing input: not said once:"; cat "$work/err"; failed=1; }
[ -z "$(ls "$work/missing")" ] || { echo "files left behind: $(ls "$work/missing")"; failed=1; }
# The .ele is read in parts, a range of its bytes on each rank: a line
# broken in the last rank's part fails every rank, naming the file and that
# line, and leaves no file.
cp "$data/bunny_10k.node" "$work/broken.node"
lines=$(wc -l < "$data/bunny_10k.ele")
bad=$((lines * 9 / 10))
awk -v bad="$bad" 'NR == bad { $5 = "x" } { print }' "$data/bunny_10k.ele" > "$work/broken.ele"
if mpirun --oversubscribe "${as_root[@]}" -n 3 "$meshenc" "$work/broken.node" "${options[@]}" -q \
  -o "$work/missing/b.dtm" 2>"$work/err"; then
  echo "a broken .ele encoded"; failed=1
fi
grep -q "broken.ele:$bad: expected a vertex index, found 'x'" "$work/err" || { echo "the broken line not named:"; cat "$work/err"; failed=1; }
[ -z "$(ls "$work/missing")" ] || { echo "files left behind: $(ls "$work/missing")"; failed=1; }
# Broken in the first rank's part, the tetrahedra sent in pieces of 100:
# every rank ends, the line is named once, no file is left.
bad=$((lines / 10))
awk -v bad="$bad" 'NR == bad { $5 = "x" } { print }' "$data/bunny_10k.ele" > "$work/broken.ele"
if DTM_MPI_PIECE=100 timeout 120 mpirun --oversubscribe "${as_root[@]}" -x DTM_MPI_PIECE -n 3 "$meshenc" \
  "$work/broken.node" "${options[@]}" -q -o "$work/missing/b.dtm" 2>"$work/err"; then
  echo "a broken .ele encoded"; failed=1
fi
[ "$(grep -c "broken.ele:$bad: expected a vertex index, found 'x'" "$work/err")" -eq 1 ] || { echo "the broken first part not named once:"; cat "$work/err"; failed=1; }
[ -z "$(ls "$work/missing")" ] || { echo "files left behind: $(ls "$work/missing")"; failed=1; }
# The .node is read in parts too, joined on every rank: with its boundary
# markers as a field, 3 ranks write what one process writes.
with_fields=(--box 256 --dmax 2 --bricks --brick-points 64 --block-points 1000)
"$meshenc" "$data/bunny_10k.node" "${with_fields[@]}" -q -o "$work/fields1.dtm"
mpirun --oversubscribe "${as_root[@]}" -n 3 "$meshenc" "$data/bunny_10k.node" "${with_fields[@]}" -q \
  -o "$work/fields3.dtm"
cmp -s "$work/fields1.dtm" "$work/fields3.dtm" || { echo "the .node's field read in parts: not the same bytes"; failed=1; }
# What no part can tell alone: a point past the header's count, a count
# the parts do not reach, an index out of sequence in another rank's part.
points=$(awk '!/^#/ && NF { print $1; exit }' "$data/bunny_10k.node")
first=$(grep -n -m1 -v '^#' "$data/bunny_10k.node" | cut -d: -f1)
awk -v h="$first" -v n=$((points - 1)) 'NR == h { $1 = n } { print }' "$data/bunny_10k.node" > "$work/extra.node"
awk -v h="$first" -v n=$((points + 5)) 'NR == h { $1 = n } { print }' "$data/bunny_10k.node" > "$work/short.node"
bad=$((first + points * 2 / 3))
awk -v bad="$bad" 'NR == bad { $1 = 5 } { print }' "$data/bunny_10k.node" > "$work/sequence.node"
for ext in extra short sequence; do cp "$data/bunny_10k.ele" "$work/$ext.ele"; done
expect_error() {  # expect_error NAME MESSAGE
  if mpirun --oversubscribe "${as_root[@]}" -n 3 "$meshenc" "$work/$1.node" "${options[@]}" -q \
    -o "$work/missing/n.dtm" 2>"$work/err"; then
    echo "$1.node encoded"; failed=1
  fi
  grep -q -- "$2" "$work/err" || { echo "$1.node: expected '$2':"; cat "$work/err"; failed=1; }
  # Every rank meets it; one prints it.
  [ "$(grep -c "meshenc: error:" "$work/err")" -eq 1 ] || { echo "$1.node: not said once:"; cat "$work/err"; failed=1; }
  [ -z "$(ls "$work/missing")" ] || { echo "files left behind: $(ls "$work/missing")"; failed=1; }
}
expect_error extra "extra.node:$((first + points)): unexpected data after the $((points - 1)) points"
expect_error short "short.node: file ends after $points of $((points + 5)) points"
expect_error sequence "sequence.node:$bad: point index 5 out of sequence"
# Ranks started with other commands (an option on one rank only, meshdec at
# another level, a --threads one rank cannot take) are refused before any
# work, said once, every rank
# exiting: they waited on each other forever, or wrote a stream the decoder
# refuses. Each rank's own --threads, -v and -q are its own: the same bytes.
"$meshenc" "$data/torus_288.node" --bricks -q -o "$work/agreed.dtm"
on_rank_2() {  # on_rank_2 TOOL EXTRA ARGS...: TOOL ARGS on 3 ranks, EXTRA added on rank 2
  cat > "$work/on_rank_2.sh" <<EOF
#!/bin/sh
if [ "\$OMPI_COMM_WORLD_RANK" = 2 ]; then exec "$1" "\$@" $2; else exec "$1" "\$@"; fi
EOF
  chmod +x "$work/on_rank_2.sh"
  shift 2
  timeout 120 mpirun --oversubscribe "${as_root[@]}" -n 3 "$work/on_rank_2.sh" "$@"
}
for case in "meshenc --no-face-tags" "meshdec --level 1" "meshenc --threads 0"; do
  tool=${case%% *} extra=${case#* }
  if [ $tool = meshenc ]; then
    on_rank_2 "$meshenc" "$extra" "$data/torus_288.node" --bricks -q -o "$work/missing/d.dtm" 2>"$work/err"
  else
    on_rank_2 "$meshdec" "$extra" "$work/agreed.dtm" -q -o "$work/missing/d.pvtu" 2>"$work/err"
  fi && { echo "$tool: ranks given other commands ran"; failed=1; }
  grep -q "error: the ranks were not given the same command.*rank 2 with '${extra%% *}'" "$work/err" ||
    { echo "$tool: ranks given other commands not refused as such:"; cat "$work/err"; failed=1; }
  [ "$(grep -c "error:" "$work/err")" -eq 1 ] || { echo "$tool: not said once:"; cat "$work/err"; failed=1; }
  [ -z "$(ls "$work/missing")" ] || { echo "files left behind: $(ls "$work/missing")"; failed=1; }
done
on_rank_2 "$meshenc" "--threads 1 -v" "$data/torus_288.node" --bricks -q -o "$work/threads.dtm" 2>/dev/null ||
  { echo "meshenc: a rank's own --threads and -v refused"; failed=1; }
cmp -s "$work/agreed.dtm" "$work/threads.dtm" || { echo "meshenc: a rank's own --threads: other bytes"; failed=1; }
# Regions (materials) on ranks: each rank holds the reference in parts a
# region at a time, and they answer which region holds a point; the same
# bytes as one process, with the same count of tetrahedra per region said.
# A TetGen .ele's region attribute (TetGen -A: bunny_10k cut in two at
# x = 0), read in parts and sent with each tetrahedron, and a gmsh part of
# two materials made here (each rank reading the file, keeping its share).
cp "$data/bunny_10k.node" "$work/halves.node"
awk 'FNR == NR { if ($1 ~ /^#/ || NF < 4) next; if (!h++) next; x[$1] = $2; next }
     $1 ~ /^#/ || NF == 0 { next }
     !e++ { print $1, $2, 1; next }
     { print $0, (x[$2] + x[$3] + x[$4] + x[$5] > 0 ? 2 : 1) }' "$work/halves.node" "$data/bunny_10k.ele" > "$work/halves.ele"
# A first attribute that is not an integer (TetGen's are real numbers):
# cell data on one process; the ranks, which read it as the region, say
# what to do instead of failing on a number.
cp "$data/bunny_10k.node" "$work/real.node"
awk '$1 ~ /^#/ || NF == 0 { next } !e++ { print $1, $2, 1; next } { print $0, 0.5 }' \
  "$data/bunny_10k.ele" > "$work/real.ele"
expect_error real "real.ele:.*give --no-regions"
# (The repository's part, data/two_materials.geo: an aluminium block with
# a steel pin, coarse.)
geo="$(cd "$(dirname "$0")/.." && pwd)/data/two_materials.geo"
gmsh "$geo" -3 -clscale 0.5 -format msh41 -o "$work/part.msh" >/dev/null
for input in halves.node part.msh; do
  "$meshenc" "$work/$input" "${options[@]}" -o "$work/one_$input.dtm" > "$work/said1"
  grep -q "regions (.*), 2: " "$work/said1" || { echo "$input: no regions:"; cat "$work/said1"; failed=1; }
  for p in 2 3; do
    mpirun --oversubscribe "${as_root[@]}" -n "$p" "$meshenc" "$work/$input" "${options[@]}" \
      -o "$work/mpi_$input.dtm" > "$work/said$p" 2>"$work/err"
    cmp -s "$work/one_$input.dtm" "$work/mpi_$input.dtm" || { echo "$input on $p ranks: not the same bytes"; failed=1; }
    [ "$(grep "regions (" "$work/said1")" = "$(grep "regions (" "$work/said$p")" ] ||
      { echo "$input on $p ranks: other region counts:"; grep "regions (" "$work/said1" "$work/said$p"; failed=1; }
    if grep -q "left out.*regions" "$work/err"; then echo "$input on $p ranks: regions left out:"; cat "$work/err"; failed=1; fi
  done
  "$meshdec" "$work/mpi_$input.dtm" -o "$work/regions.vtu" --verify -q || failed=1
  echo "$input: $(grep "regions (" "$work/said1"); on 2 and 3 ranks the same bytes"
done
# Cell data on ranks (format 16.0): the gmsh part with a pressure and a
# stress on every tetrahedron ($ElementData, added here). Every rank keeps
# every tetrahedron and its values (a cell's source may be any at its
# corners): the same bytes as one process, the same report of where the
# cells' values came from, and the arrays in the decoded level.
awk '{ print }
  $0 == "$Elements" { inel = 1; head = 1; next }
  $0 == "$EndElements" { inel = 0; next }
  inel && head { head = 0; next }
  inel && left == 0 { type = $3; left = $4; next }
  inel { left--; if (type == 4) tag[n++] = $1 }
  END {
    print "$ElementData\n1\n\"pressure\"\n1\n0\n3\n0\n1\n" n
    for (i = 0; i < n; i++) printf "%d %.17g\n", tag[i], tag[i] * 0.5 + 0.25
    print "$EndElementData\n$ElementData\n1\n\"stress\"\n1\n0\n3\n0\n3\n" n
    for (i = 0; i < n; i++) printf "%d %d %d %.17g\n", tag[i], tag[i] % 7, -tag[i], tag[i] / 8
    print "$EndElementData"
  }' "$work/part.msh" > "$work/cells.msh"
"$meshenc" "$work/cells.msh" "${options[@]}" -o "$work/cells1.dtm" > "$work/said1"
grep -q "cell data on level 0" "$work/said1" || { echo "cells.msh: no cell data:"; cat "$work/said1"; failed=1; }
for p in 2 3; do
  mpirun --oversubscribe "${as_root[@]}" -n "$p" "$meshenc" "$work/cells.msh" "${options[@]}" \
    -o "$work/cells$p.dtm" > "$work/said$p" 2>"$work/err"
  cmp -s "$work/cells1.dtm" "$work/cells$p.dtm" || { echo "cells.msh on $p ranks: not the same bytes"; failed=1; }
  [ "$(grep "cell data on level 0" "$work/said1")" = "$(grep "cell data on level 0" "$work/said$p")" ] ||
    { echo "cells.msh on $p ranks: another report:"; grep "cell data on level 0" "$work/said1" "$work/said$p"; failed=1; }
  if grep -q "left out.*cell arrays" "$work/err"; then echo "cells.msh on $p ranks: cell data left out:"; cat "$work/err"; failed=1; fi
done
"$meshdec" "$work/cells3.dtm" -o "$work/cells.vtu" --verify -q || failed=1
for name in pressure stress; do
  grep -q "Name=\"$name\"" "$work/cells.vtu" || { echo "cells.vtu: no cell array $name"; failed=1; }
done
echo "cells.msh: $(grep "cell data on level 0" "$work/said1" | sed 's/^ *//'); on 2 and 3 ranks the same bytes"
# A TetGen .face whose markers tag the boundary (2 and 3): read whole on
# every rank with the .ele, the same bytes as one process, the markers kept.
cp "$data/bunny_10k.node" "$work/fc.node"
cp "$data/bunny_10k.ele" "$work/fc.ele"
awk 'NR > 1 && $1 !~ /^#/ && NF >= 5 {
       v[0] = $2; v[1] = $3; v[2] = $4; v[3] = $5
       for (k = 0; k < 4; ++k) {
         n = 0
         for (j = 0; j < 4; ++j) if (j != k) f[n++] = v[j]
         if (f[0] + 0 > f[1] + 0) { t = f[0]; f[0] = f[1]; f[1] = t }
         if (f[1] + 0 > f[2] + 0) { t = f[1]; f[1] = f[2]; f[2] = t }
         if (f[0] + 0 > f[1] + 0) { t = f[0]; f[0] = f[1]; f[1] = t }
         key = f[0] " " f[1] " " f[2]; seen[key]++
       }
     }
     END { for (key in seen) if (seen[key] == 1) out[++count] = key
           print count, 1
           for (i = 1; i <= count; ++i) { split(out[i], a, " "); print i, out[i], (a[1] % 2) + 2 } }' \
  "$work/fc.ele" > "$work/fc.face"
"$meshenc" "$work/fc.node" "${options[@]}" -o "$work/fc1.dtm" > "$work/said1" 2>"$work/err"
grep -q "tagged faces" "$work/said1" || { echo "fc.face: no tagged faces:"; cat "$work/said1" "$work/err"; failed=1; }
mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshenc" "$work/fc.node" "${options[@]}" -q -o "$work/fc2.dtm" 2>"$work/err"
cmp -s "$work/fc1.dtm" "$work/fc2.dtm" || { echo "fc.face on 2 ranks: not the same bytes:"; cat "$work/err"; failed=1; }
if grep -q "boundary markers" "$work/err"; then echo "fc.face on 2 ranks: markers left out:"; cat "$work/err"; failed=1; fi
echo "fc.face's markers: on 2 ranks the same bytes as one process"
# -o - under mpirun: a rank's standard output is not mpirun's (Open MPI's
# own terminal): refused, said once.
if mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshenc" "$data/bunny_10k.node" "${options[@]}" -q -o - \
  >"$work/out.dtm" 2>"$work/err"; then
  echo "mpirun meshenc -o - ran"; failed=1
fi
[ "$(grep -c "under mpirun a rank's standard output" "$work/err")" -eq 1 ] || { echo "-o -: not said once:"; cat "$work/err"; failed=1; }
# Without --bricks: a clear error.
if mpirun --oversubscribe "${as_root[@]}" -n 2 "$meshenc" "$data/bunny_10k.node" --no-fields -q \
  -o "$work/missing/p.dtm" 2>"$work/err"; then
  echo "mpirun meshenc without --bricks encoded"; failed=1
fi
grep -q -- "--bricks" "$work/err" || { cat "$work/err"; failed=1; }
[ $failed -eq 0 ] && echo "mpi_encode: ok"
exit $failed
