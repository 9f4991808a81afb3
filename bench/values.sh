#!/usr/bin/env bash
# bench/values.sh [BUILD_DIR] -- the per-vertex value coder (codec/value_coder.h,
# not in the stream yet) on issue 13's cases, against zstd -19 and xz -9 of
# the same values stored raw in the input's order. Writes bench/VALUES.md.
#
# Cases: data/ct_torus.nrrd (int16 CT numbers), ../shared/data/fields/mri_s0.nrrd
# (a real 12-bit MRI in uint16), and bunny_10k carrying a smooth float32
# field (three Gaussians), lossless and within E = 1e-3 of its range.
# Needs BUILD_DIR/bench/value_bits, zstd, xz, /usr/bin/python3 with numpy.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
case $build in /*) ;; *) build=$root/$build ;; esac
bin=$build/bench/value_bits
shared=${DTM_SHARED:-$root/../shared}
work=$build/values-data
[ -x "$bin" ] || { echo "values.sh: $bin not built" >&2; exit 2; }
for t in zstd xz; do
  command -v $t >/dev/null || { echo "values.sh: $t missing; apt-get install -y zstd xz-utils python3-numpy" >&2; exit 2; }
done
/usr/bin/python3 -c 'import numpy' 2>/dev/null ||
  { echo "values.sh: numpy missing; apt-get install -y python3-numpy" >&2; exit 2; }
mkdir -p "$work"
for ext in node ele; do xz -dc "$root/data/bunny_10k.$ext.xz" > "$work/bunny_10k.$ext"; done
# The smooth field: three Gaussians of width 0.15 x the largest extent, float32.
/usr/bin/python3 - "$work/bunny_10k.node" "$work/bunny_field.node" <<'PY'
import sys
import numpy as np
rows = [l.split() for l in open(sys.argv[1]) if l.strip() and not l.startswith('#')]
n = int(rows[0][0]); rows = rows[1:n + 1]
P = np.array([[float(r[1]), float(r[2]), float(r[3])] for r in rows])
lo, hi = P.min(0), P.max(0); ext = (hi - lo).max()
centres = [lo + (hi - lo) * np.array(t) for t in ((0.3, 0.4, 0.5), (0.7, 0.6, 0.4), (0.5, 0.2, 0.7))]
f = sum(a * np.exp(-((P - c) ** 2).sum(1) / (2 * (0.15 * ext) ** 2)) for c, a in zip(centres, (1.0, -0.7, 0.5)))
f = f.astype(np.float32)
with open(sys.argv[2], 'w') as o:
    o.write(f"{n} 3 1 0\n")
    for i, r in enumerate(rows): o.write(f"{r[0]} {r[1]} {r[2]} {r[3]} {float(f[i])!r}\n")
PY
cp "$work/bunny_10k.ele" "$work/bunny_field.ele"
run() { echo "\$ value_bits $*"; "$bin" "$@"; echo; }
{
  echo "# The value coder on issue 13's cases"
  echo
  echo "Written by \`bench/values.sh\` (do not edit by hand; rerun it). Commit $(git -C "$root" rev-parse --short HEAD); $(date -u '+%Y-%m-%d %H:%M UTC')."
  echo
  echo "Positions are encoded as meshenc does (codec preset), the stream decoded for the decoder's order and"
  echo "layers, and each field coded layer by layer in that order, then decoded and compared (value_bits stops"
  echo "if a value differs). Baselines: zstd -19 and xz -9 of the raw values in the input's order (raster"
  echo "order, x fastest, for a volume); for the lossy case, of round(v / 2E) as int32. Issue 13's targets:"
  echo "lossless 16-bit scans at most 0.75x the better of zstd and xz; smooth floats within E = 1e-3 of the"
  echo "range at most 0.5x zstd; decoding the values at most 25% more than decoding the positions."
  echo
  echo '```'
  run "$root/data/ct_torus.nrrd" --threshold 0 --voxel-interior-step 2 --dmax 0.5
  run "$shared/data/fields/mri_s0.nrrd" --threshold 150 --voxel-interior-step 2
  run "$work/bunny_field.node" --box 256 --dmax 2 --raw-type f32
  run "$work/bunny_field.node" --box 256 --dmax 2 --raw-type f32 --error-share 1e-3
  echo '```'
} > "$root/bench/VALUES.md"
echo "$root/bench/VALUES.md"
