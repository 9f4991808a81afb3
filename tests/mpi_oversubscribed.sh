#!/usr/bin/env bash
# tests/mpi_oversubscribed.sh MESHENC MESHDEC DATA_DIR -- more ranks than
# cores, each told to use more threads than the machine has (--threads: 4
# times the cores), encoding with --bricks and decoding in pieces: both
# must end (ctest's deadline bounds this test; before the parallel
# insertion backed off, such runs made no progress, docs/ARCHITECTURE.md
# §5.9), the stream be byte for byte one process's, and the pieces' cells
# add up to the whole level's. The blocks are large enough (over 20,000
# points) for their tetrahedralizations to be built by several threads.
set -euo pipefail
meshenc=$1 meshdec=$2 data=$3
command -v mpirun >/dev/null || { echo "mpi_oversubscribed: mpirun missing (apt-get install openmpi-bin)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
as_root=()
[ "$(id -u)" -eq 0 ] && as_root=(--allow-run-as-root)
cores=$(nproc)
ranks=$((cores + 2))
threads=$((4 * cores))
options=(--box 256 --dmax 2 --no-fields --bricks --block-points 60000 --levels 1 -q)
"$meshenc" "$data/bunny_100k.node" "${options[@]}" -o "$work/one.dtm"
failed=0
start=$(date +%s)
mpirun --oversubscribe --bind-to none "${as_root[@]}" -n "$ranks" "$meshenc" "$data/bunny_100k.node" \
  "${options[@]}" --threads "$threads" -o "$work/mpi.dtm"
same=no
cmp -s "$work/one.dtm" "$work/mpi.dtm" && same=yes
echo "mpirun -n $ranks meshenc --threads $threads on $cores cores: $(($(date +%s) - start)) s, the same bytes as one process: $same"
[ "$same" = yes ] || failed=1
cells_of() { grep -oh 'NumberOfCells="[0-9]*"' "$@" | grep -o '[0-9]*' | awk '{s += $1} END {print s}'; }
"$meshdec" "$work/one.dtm" -o "$work/whole.vtu" -q
whole=$(cells_of "$work/whole.vtu")
mkdir -p "$work/pieces"
start=$(date +%s)
mpirun --oversubscribe --bind-to none "${as_root[@]}" -n "$ranks" "$meshdec" "$work/one.dtm" \
  -o "$work/pieces/b.pvtu" --threads "$threads" -q
sum=$(cells_of "$work/pieces"/b_*.vtu)
echo "mpirun -n $ranks meshdec -o b.pvtu --threads $threads: $(($(date +%s) - start)) s, $sum cells in the pieces, $whole in the level"
[ "$sum" -eq "$whole" ] || failed=1
[ $failed -eq 0 ] && echo "mpi_oversubscribed: ok"
exit $failed
