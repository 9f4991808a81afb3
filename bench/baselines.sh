#!/usr/bin/env bash
# bench/baselines.sh [-q "12 14 16"] [-c "10 4"] MODEL.node[.xz]
#
# The general-purpose coders bench/bitrate.sh sets beside the .dtm streams,
# measured on one TetGen model:
#   * Draco's point-cloud coder: the model's points, rounded to float32, as a
#     binary PLY of x y z, through
#       draco_encoder -point_cloud -i pts.ply -o pts.drc -qp Q -cl L
#     for every Q of -q and L of -c. Draco puts its own grid on the points
#     (one step = largest bounding-box extent / (2^Q - 1)).
#   * zstd -19 of the positions alone: float32 x y z per vertex, little endian,
#     in the .node's order.
#   * zstd -19 of the tetrahedral mesh, when MODEL.ele[.xz] lies beside the
#     .node: the same float32 positions, then four int32 (0-based) per tet.
#
# Prints one line per figure, sizes in bytes of the files the tools wrote:
#   drc Q L BYTES METHOD    METHOD = byte 8 of the .drc header: Draco's
#                           point-cloud method, 0 sequential, 1 kd-tree
#                           (Draco 1.5 picks the kd-tree for -cl 1..10)
#   meshzst BYTES           only with a .ele
#   ptszst BYTES
# bench/bitrate.sh keeps these lines as BUILD_DIR/bitrate-data/out/MODEL.baselines.
#
# Needs draco_encoder, zstd and python3 (standard library only):
#   apt-get install -y draco zstd python3
set -euo pipefail
qs="12 14 16"
levels="10 4"
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "q:c:h" opt; do
  case $opt in
    q) qs=$OPTARG ;;
    c) levels=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -eq 1 ] || usage
node=$1
[ -f "$node" ] || { echo "baselines.sh: $node: no such file" >&2; exit 2; }
for t in draco_encoder zstd python3; do
  command -v "$t" >/dev/null 2>&1 ||
    { echo "baselines.sh: $t missing; apt-get install -y draco zstd python3" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The model as binary files: pts.f32, pts.ply and, with a .ele, mesh.bin.
python3 - "$node" "$work" <<'PY'
import array, lzma, os, sys

node, work = sys.argv[1], sys.argv[2]

def numbers(path):
    """The rows of a TetGen file, comments and blank lines left out."""
    text = lzma.open(path, 'rt') if path.endswith('.xz') else open(path)
    with text:
        for line in text:
            fields = line.split('#', 1)[0].split()
            if fields:
                yield fields

rows = numbers(node)
count = int(next(rows)[0])
xyz = array.array('f')          # float32: the rounding Draco's PLY input imposes
base = None
for _ in range(count):
    r = next(rows)
    if base is None:
        base = int(r[0])
    xyz.extend(float(v) for v in r[1:4])
if sys.byteorder != 'little':
    xyz.byteswap()
positions = xyz.tobytes()
with open(os.path.join(work, 'pts.f32'), 'wb') as f:
    f.write(positions)
with open(os.path.join(work, 'pts.ply'), 'wb') as f:
    f.write(b'ply\nformat binary_little_endian 1.0\n'
            b'element vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n' % count)
    f.write(positions)

stem = node[:-3] if node.endswith('.xz') else node
stem = stem[:-len('.node')] if stem.endswith('.node') else stem
ele = next((stem + '.ele' + z for z in ('', '.xz') if os.path.exists(stem + '.ele' + z)), None)
if ele:
    rows = numbers(ele)
    tets = int(next(rows)[0])
    corners = array.array('i')
    for _ in range(tets):
        r = next(rows)
        corners.extend(int(v) - base for v in r[1:5])
    if corners and (min(corners) < 0 or max(corners) >= count):
        sys.exit('baselines.sh: %s names vertices outside %s' % (ele, node))
    if sys.byteorder != 'little':
        corners.byteswap()
    with open(os.path.join(work, 'mesh.bin'), 'wb') as f:
        f.write(positions)
        f.write(corners.tobytes())
PY

for q in $qs; do
  for l in $levels; do
    drc=$work/q${q}_cl$l.drc
    draco_encoder -point_cloud -i "$work/pts.ply" -o "$drc" -qp "$q" -cl "$l" >"$work/draco.log" 2>&1 ||
      { cat "$work/draco.log" >&2; echo "baselines.sh: draco_encoder failed on $node (-qp $q -cl $l)" >&2; exit 1; }
    echo "drc $q $l $(stat -c %s "$drc") $(od -An -tu1 -j8 -N1 "$drc" | tr -d ' ')"
  done
done
if [ -f "$work/mesh.bin" ]; then
  zstd -19 -q -f "$work/mesh.bin" -o "$work/mesh.bin.zst"
  echo "meshzst $(stat -c %s "$work/mesh.bin.zst")"
fi
zstd -19 -q -f "$work/pts.f32" -o "$work/pts.f32.zst"
echo "ptszst $(stat -c %s "$work/pts.f32.zst")"
