#!/usr/bin/env bash
# bench/mpi.sh [BUILD_DIR] -- encoding and decoding past one process: a
# model encoded with `meshenc --bricks` alone and under `mpirun -n P` for
# P = 1, 2, 4, and its finest level decoded alone (one .vtu) and under
# `mpirun -n P meshdec -o X.pvtu` (a piece per rank). Each rank's time and
# peak memory (GNU time), whether the stream is the same bytes for every P,
# and each rank's CPU time with their sum against one process's (what the
# ranks' sharing of the work costs). Oversubscribed: this machine has 2
# cores, so P = 4 shows memory and CPU, not speed. Writes
# bench/results/MPI.md (bunny_10m), or MPI_<model>.md for another model.
#   MPI_MODEL=bunny_1m  (default bunny_10m: bench/scale.sh makes it)
#   MPI_RANKS="1 2 4"
#   MPI_REUSE=1         keeps a finished single-process encode (one.dtm, enc1.0)
#   MPI_DECODE=0        encodes only (the table then has no decode rows)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
data=$build/bench-data
model=${MPI_MODEL:-bunny_10m}
ranks=${MPI_RANKS:-1 2 4}
meshenc=$build/tools/meshenc
meshdec=$build/tools/meshdec
for t in "$meshenc" "$meshdec"; do [ -x "$t" ] || { echo "mpi.sh: $t not built" >&2; exit 2; }; done
[ -s "$data/$model.node" ] || { echo "mpi.sh: $data/$model.node missing (bench/scale.sh makes it)" >&2; exit 2; }
command -v mpirun >/dev/null || { echo "mpi.sh: mpirun missing (apt-get install openmpi-bin)" >&2; exit 2; }
as_root=()
[ "$(id -u)" -eq 0 ] && as_root=(--allow-run-as-root)
out=$data/mpi
if [ "${MPI_REUSE:-0}" != 1 ] || [ ! -s "$out/one.dtm" ] || [ ! -s "$out/enc1.0" ]; then
  rm -rf "$out"
fi
mkdir -p "$out"
report=$root/bench/results/MPI.md
[ "$model" = bunny_10m ] || report=$root/bench/results/MPI_$model.md
options=(--box 256 --dmax 2 --no-fields --bricks -q)

# "| seconds | CPU seconds (their sum, x ALONE's) | peak GB |", per rank,
# from GNU time's files NAME.RANK ("SECONDS PEAK_KB USER SYSTEM").
ranks_of() {
  for f in "$1".*; do cat "$f"; done | awk -v alone="${2:-0}" '
    {t = t (t ? " / " : "") $1; m = m (m ? " / " : "") sprintf("%.2f", $2 / 1048576)
     c = c (c ? " / " : "") sprintf("%.1f", $3 + $4); sum += $3 + $4}
    END {x = alone > 0 ? sprintf(", %.2fx", sum / alone) : ""
         print "| " t " | " c " (" sprintf("%.1f", sum) x ") | " m " |"}'
}
cpu_of() { awk '{s += $3 + $4} END {print s}' "$1".*; }
timed() {  # NAME command...: one process
  local name=$1; shift
  /usr/bin/time -f "%e %M %U %S" -o "$out/$name.0" "$@"
}
timed_ranks() {  # NAME P command...: P ranks, each timed
  local name=$1 p=$2; shift 2
  # --bind-to none: Open MPI would bind each of 1 or 2 ranks to one core,
  # leaving the other idle; the ranks' own threads share both cores.
  mpirun --oversubscribe --bind-to none "${as_root[@]}" -n "$p" sh -c \
    '/usr/bin/time -f "%e %M %U %S" -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$out/$name" "$@"
}

if [ ! -s "$out/enc1.0" ]; then
  echo "mpi.sh: $model alone" >&2
  timed enc1 "$meshenc" "$data/$model.node" "${options[@]}" -o "$out/one.dtm"
fi
{
  echo "# Encoding and decoding on MPI ranks"
  echo
  echo "\`bench/mpi.sh\` at $(git -C "$root" rev-parse --short HEAD) ($(date -u +%Y-%m-%d)), $model"
  echo "($(grep -v "^ *#" "$data/$model.node" | head -1 | awk '{print $1}') points), \`meshenc --box 256 --dmax 2 --no-fields --bricks\`"
  echo "(blocks of 2^18 points, bricks of 2,048), a 2-core machine: 4 ranks are oversubscribed."
  echo "Time, CPU time (user + system) and peak memory of each rank (GNU time), in rank order;"
  echo "the ranks' CPU summed, and that sum against the process alone's."
  echo
  echo "| run | ranks | stream | seconds per rank | CPU seconds per rank (sum) | peak GB per rank |"
  echo "|---|---:|---|---|---|---|"
  echo "| meshenc alone | 1 | $(stat -c %s "$out/one.dtm") bytes $(ranks_of "$out/enc1")"
} >"$report"
enc_alone=$(cpu_of "$out/enc1")
for p in $ranks; do
  echo "mpi.sh: mpirun -n $p meshenc" >&2
  timed_ranks "enc_mpi$p" "$p" "$meshenc" "$data/$model.node" "${options[@]}" -o "$out/mpi$p.dtm"
  same="differs"
  cmp -s "$out/one.dtm" "$out/mpi$p.dtm" && same="the same bytes"
  echo "| mpirun meshenc | $p | $same $(ranks_of "$out/enc_mpi$p" "$enc_alone")" >>"$report"
done
if [ "${MPI_DECODE:-1}" = 0 ]; then
  echo "mpi.sh: wrote $report (no decodes: MPI_DECODE=0)" >&2
  exit 0
fi
echo "mpi.sh: meshdec alone" >&2
timed dec1 "$meshdec" "$out/one.dtm" -o "$out/one.vtu" -q
echo "| meshdec -o X.vtu (level 0, whole) | 1 | | $(ranks_of "$out/dec1" | cut -c3-)" >>"$report"
dec_alone=$(cpu_of "$out/dec1")
rm -f "$out/one.vtu"
for p in $ranks; do
  echo "mpi.sh: mpirun -n $p meshdec" >&2
  mkdir -p "$out/pieces$p"
  timed_ranks "dec_mpi$p" "$p" "$meshdec" "$out/one.dtm" -o "$out/pieces$p/b.pvtu" -q
  echo "| mpirun meshdec -o X.pvtu (level 0 in pieces) | $p | | $(ranks_of "$out/dec_mpi$p" "$dec_alone" | cut -c3-)" >>"$report"
  rm -rf "$out/pieces$p"
done
echo "mpi.sh: wrote $report" >&2
