#!/usr/bin/env bash
# bench/python.sh [BUILD_DIR] -- what the Python bindings add over the C++
# call: dtmesh.encode and dtmesh.decode on bunny_100k against the same calls
# in C++ (bench_hierarchy --peak-memory: encode with its .ele, box 256, Dmax
# 2, no fields; decode of that stream to the finest level's carved cells),
# each in a fresh process, three runs, the median. Writes bench/results/PYTHON.md.
# Needs BUILD_DIR/bench/bench_hierarchy and the package installed in
# BUILD_DIR/python-venv (scripts/test_python.sh install BUILD_DIR).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
bench=$build/bench/bench_hierarchy
python=$build/python-venv/bin/python
data=$build/bench-data
model=${PYTHON_MODEL:-bunny_100k}
[ -x "$python" ] || { echo "python.sh: run scripts/test_python.sh install $build first" >&2; exit 2; }
mkdir -p "$data"
for ext in node ele; do
  [ -s "$data/$model.$ext" ] || xz -dc "$root/data/$model.$ext.xz" > "$data/$model.$ext"
done
field() { sed -E "s/.*$1=([0-9.]+).*/\1/"; }
median() { sort -n | sed -n 2p; }
rows=""
for call in encode decode; do
  input=$data/$model.node
  [ $call = decode ] && input=$data/$model.dtm
  for side in cpp python; do
    runs=()
    for _ in 1 2 3; do
      if [ $side = cpp ]; then line=$("$bench" --peak-memory "$data/$model.node" $call)
      else line=$("$python" "$root/bench/python_bindings.py" "$input" $call); fi
      runs+=("$line")
    done
    seconds=$(printf '%s\n' "${runs[@]}" | field seconds | median)
    added=$(printf '%s\n' "${runs[@]}" | awk '{for(i=1;i<=NF;i++){split($i,a,"=");v[a[1]]=a[2]} print v["peak_rss_mib"]-v["loaded_rss_mib"]}' | median)
    peak=$(printf '%s\n' "${runs[@]}" | field peak_rss_mib | median)
    eval "${call}_${side}_s=$seconds ${call}_${side}_added=$added ${call}_${side}_peak=$peak"
  done
done
ratio() { awk -v a="$1" -v b="$2" 'BEGIN{printf "%.2fx", a/b}'; }
{
  echo "# What the Python bindings add ($model)"
  echo
  echo "Made by \`bench/python.sh $1\` on $(date -u +%Y-%m-%d) ($(nproc) cores): each call in a fresh process,"
  echo "the median of three runs. *Call* is the call alone (reading the input is outside it); *memory"
  echo "added* is the process's peak RSS minus its RSS once the input was in memory (a Python process"
  echo "starts with the interpreter and numpy: its whole peak is larger by that)."
  echo
  echo "| call | C++ call | Python call | Python / C++ | C++ memory added | Python memory added | C++ peak | Python peak |"
  echo "|---|---|---|---|---|---|---|---|"
  echo "| encode (points + .ele, box 256, Dmax 2) | ${encode_cpp_s} s | ${encode_python_s} s | $(ratio "$encode_python_s" "$encode_cpp_s") | ${encode_cpp_added} MiB | ${encode_python_added} MiB | ${encode_cpp_peak} MiB | ${encode_python_peak} MiB |"
  echo "| decode (the finest level) | ${decode_cpp_s} s | ${decode_python_s} s | $(ratio "$decode_python_s" "$decode_cpp_s") | ${decode_cpp_added} MiB | ${decode_python_added} MiB | ${decode_cpp_peak} MiB | ${decode_python_peak} MiB |"
  echo
  echo "C++: \`bench_hierarchy --peak-memory $model.node encode|decode\` (decode stops at the carved cells);"
  echo "Python: \`bench/python_bindings.py\` (decode also makes the numpy arrays: float64 points, each"
  echo "vertex's level, the boundary flags, the fields in their types)."
} > "$root/bench/results/PYTHON.md"
cat "$root/bench/results/PYTHON.md"
