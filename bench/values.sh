#!/usr/bin/env bash
# bench/values.sh [BUILD_DIR] -- what .dtm streams spend on per-vertex values
# (spec/FORMAT.md §3.3), against zstd -19 and xz -9 of the same values stored
# raw in the input's order. Writes bench/results/VALUES.md,
# bench/results/values.csv and the rate-distortion plot docs/values_rd.png.
#
# Cases: data/ct_torus.nrrd (int16 CT numbers), data/fields/mri_s0.nrrd
# (a real 12-bit MRI in uint16), and bunny_10k and elephant_10k (their TetGen
# tetrahedra) carrying a smooth analytic field (three Gaussians) in float32 and
# float64 and a piecewise-constant label (int32): lossless, and the floats
# within E = S x their range for S from 1e-2 to 1e-5.
# Needs BUILD_DIR/bench/value_bits, zstd, xz, gnuplot, /usr/bin/python3 with numpy.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
case $build in /*) ;; *) build=$root/$build ;; esac
bin=$build/bench/value_bits
corpus=${DTM_DATA:-$root/data}
work=$build/values-data
[ -x "$bin" ] || { echo "values.sh: $bin not built" >&2; exit 2; }
for t in zstd xz gnuplot; do
  command -v $t >/dev/null ||
    { echo "values.sh: $t missing; apt-get install -y zstd xz-utils gnuplot-nox python3-numpy" >&2; exit 2; }
done
/usr/bin/python3 -c 'import numpy' 2>/dev/null ||
  { echo "values.sh: numpy missing; apt-get install -y python3-numpy" >&2; exit 2; }
mkdir -p "$work"
csv=$root/bench/results/values.csv
rm -f "$csv"
for m in bunny elephant; do
  for ext in node ele; do xz -dc "$corpus/${m}_10k.$ext.xz" > "$work/${m}_10k.$ext"; done
  # The fields, written as a VTU with the model's tetrahedra: three Gaussians of
  # width 0.15 x the largest extent (float32 and float64), and the label of the
  # Gaussian that dominates where it exceeds 0.2 (else 0).
  /usr/bin/python3 - "$work/${m}_10k" "$work/${m}_fields.vtu" <<'PY'
import sys
import numpy as np
def rows(path):
    r = [l.split() for l in open(path) if l.strip() and not l.startswith('#')]
    return r[1:int(r[0][0]) + 1]
nodes = rows(sys.argv[1] + '.node')
P = np.array([[float(r[1]), float(r[2]), float(r[3])] for r in nodes])
first = int(nodes[0][0])
T = np.array([[int(x) - first for x in r[1:5]] for r in rows(sys.argv[1] + '.ele')])
lo, hi = P.min(0), P.max(0); ext = (hi - lo).max()
centres = [lo + (hi - lo) * np.array(t) for t in ((0.3, 0.4, 0.5), (0.7, 0.6, 0.4), (0.5, 0.2, 0.7))]
g = np.array([a * np.exp(-((P - c) ** 2).sum(1) / (2 * (0.15 * ext) ** 2)) for c, a in zip(centres, (1.0, -0.7, 0.5))])
f = g.sum(0)
label = np.where(np.abs(g).max(0) > 0.2, np.abs(g).argmax(0) + 1, 0).astype(np.int32)
def array(kind, name, values):
    return f'<DataArray type="{kind}" Name="{name}" format="ascii">' + ' '.join(values) + '</DataArray>\n'
with open(sys.argv[2], 'w') as o:
    o.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">\n')
    o.write(f'<UnstructuredGrid><Piece NumberOfPoints="{len(P)}" NumberOfCells="{len(T)}">\n<PointData>\n')
    o.write(array('Float32', 'smooth_f32', [repr(float(v)) for v in f.astype(np.float32)]))
    o.write(array('Float64', 'smooth_f64', [repr(float(v)) for v in f]))
    o.write(array('Int32', 'label', [str(v) for v in label]))
    o.write('</PointData>\n<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">')
    o.write(' '.join(repr(float(x)) for x in P.ravel()) + '</DataArray></Points>\n<Cells>\n')
    o.write(array('Int64', 'connectivity', [str(x) for x in T.ravel()]))
    o.write(array('Int64', 'offsets', [str(4 * (i + 1)) for i in range(len(T))]))
    o.write(array('UInt8', 'types', ['10'] * len(T)))
    o.write('</Cells></Piece></UnstructuredGrid>\n</VTKFile>\n')
PY
done
# The report names files relative to the repository root, not where it was cloned.
run() { echo "\$ value_bits ${*//$root\//}"; "$bin" "$@" --csv "$csv" | sed "s|$root/||g"; echo; }
shares=1e-2,3e-3,1e-3,3e-4,1e-4,3e-5,1e-5
{
  echo "# Values in the stream: bits per value against zstd and xz"
  echo
  echo "Written by \`bench/values.sh\` (do not edit by hand; rerun it). Commit $(git -C "$root" rev-parse --short HEAD); $(date -u '+%Y-%m-%d %H:%M UTC')."
  echo "The rows are in bench/results/values.csv; the lossy ones are plotted in docs/values_rd.png."
  echo
  echo "Each field is encoded as meshenc encodes it (codec preset), alone with the positions; ours is the"
  echo "field's value sections over every layer (length words included) per value; the stream is decoded and"
  echo "every value checked, exact or within E. Baselines: zstd -19 and xz -9 of the raw values in the"
  echo "input's order (raster order, x fastest, for a volume) in their own type; for a lossy row, of"
  echo "round(v / 2E) as int32. Decoding cost: decoding the stream with the field to the finest mesh,"
  echo "against the same stream without it (best of 15 each, in turns). Issue 13's targets: lossless 16-bit scans at"
  echo "most 0.75x the better of zstd and xz; smooth floats within E = 1e-3 of the range at most 0.5x zstd;"
  echo "decoding the values at most 25% more than decoding the positions."
  echo
  echo '```'
  run "$corpus/ct_torus.nrrd" --threshold 0 --voxel-interior-step 2 --dmax 0.5
  run "$corpus/fields/mri_s0.nrrd" --threshold 150 --voxel-interior-step 2
  run "$work/bunny_fields.vtu" --box 256 --dmax 2 --error-shares $shares
  run "$work/elephant_fields.vtu" --box 256 --dmax 2 --error-shares $shares
  echo '```'
} > "$root/bench/results/VALUES.md"
# The rate-distortion plot: bits per value against E / range, ours and zstd -19 of round(v / 2E).
plot=$work/rd.dat
for m in bunny_fields elephant_fields; do
  for f in smooth_f32 smooth_f64; do
    echo "# $m $f"
    awk -F, -v m=$m -v f=$f '$1 == m && $2 == f && $5 == "lossy" { print $6, $9, $10 }' "$csv"
    printf '\n\n'
  done
done > "$plot"
gnuplot <<GP
set terminal pngcairo size 900,560 font ",11"
set output "$root/docs/values_rd.png"
set logscale x
set xrange [*:*] reverse
set xlabel "error bound E / the field's range (every decoded value within E)"
set ylabel "bits per value"
set key top left
set grid
set title "Lossy float fields: .dtm value sections against zstd -19 of round(v / 2E) (bench/values.sh)"
plot "$plot" index 0 using 1:2 with linespoints lw 2 title "bunny float32, ours", \
     "$plot" index 1 using 1:2 with linespoints lw 2 title "bunny float64, ours", \
     "$plot" index 2 using 1:2 with linespoints lw 2 title "elephant float32, ours", \
     "$plot" index 0 using 1:3 with linespoints dt 2 title "bunny, zstd -19", \
     "$plot" index 2 using 1:3 with linespoints dt 2 title "elephant, zstd -19"
GP
echo "$root/bench/results/VALUES.md $csv $root/docs/values_rd.png"
