#!/usr/bin/env bash
# bench/surfaces.sh [BUILD_DIR] -- what a level's boundary surface costs in the
# formats web, AR and DCC tools take, written to bench/results/SURFACES.md: per
# corpus model (codec preset, --box 256 --dmax 2; the streams the web tests
# decode), level 0 and the coarsest level as .glb with Draco, .glb plain,
# Draco's .drc and binary .ply (float64, meshdec's), and the whole stream
# with every level's tetrahedral mesh for comparison.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
streams=$build/web-streams
work=$build/bench-surfaces
mkdir -p "$work"
"$root/web/test/make_streams.sh" "$build/tools/meshenc" "$streams" >/dev/null
out=$root/bench/results/SURFACES.md
size() { stat -c %s "$1"; }
{
  echo "# A level's surface as glTF 2.0, Draco and PLY"
  echo
  echo "Made by \`bench/surfaces.sh build\`: every corpus model of data/ encoded with the codec"
  echo "preset (\`--box 256 --dmax 2\`, its .ele as the reference solid where data/ has it),"
  echo "and \`meshdec --level K -o X.glb\` (Draco, positions quantized to the stream's grid step,"
  echo "normals 10 bits, colours 8 bits), \`--no-draco\` (plain float32 buffers), \`-o X.drc\` and"
  echo "\`-o X.ply\` (binary, float64 positions and the level of each vertex). Bytes; the"
  echo "stream holds every level's tetrahedral mesh and the values."
  echo
  echo "| model | level | triangles | .glb (Draco) | .glb (plain) | .drc | .ply (binary) | Draco / plain | whole .dtm stream |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  for stream in "$streams"/*.dtm; do
    model=$(basename "$stream" .dtm)
    levels=$("$build/tools/meshinfo" "$stream" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['level_count'])")
    for level in 0 $((levels - 1)); do
      base=$work/${model}_l$level
      note=$("$build/tools/meshdec" "$stream" --level "$level" -o "$base.glb" 2>&1)
      "$build/tools/meshdec" "$stream" --level "$level" --no-draco -q -o "${base}_plain.glb"
      "$build/tools/meshdec" "$stream" --level "$level" -q -o "$base.drc"
      "$build/tools/meshdec" "$stream" --level "$level" -q -o "$base.ply"
      triangles=$(echo "$note" | sed -n 's/.*boundary surface: [0-9]* vertices, \([0-9]*\) triangles.*/\1/p')
      draco=$(size "$base.glb"); plain=$(size "${base}_plain.glb")
      echo "| $model | $level | $triangles | $draco | $plain | $(size "$base.drc") | $(size "$base.ply") |" \
           "$(python3 -c "print(f'{$draco / $plain:.3f}')") | $(size "$stream") |"
    done
  done
} > "$out"
cat "$out"
