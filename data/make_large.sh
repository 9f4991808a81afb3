#!/usr/bin/env bash
# data/make_large.sh -- rebuild the corpus's volume point sets and tetrahedral
# meshes, deterministically, from data/surfaces/*.off and data/gen_torus.py.
#
# Usage:  data/make_large.sh [-o OUTDIR] [NAME...|all]
#   NAME defaults to bunny_1m, the bunny of about a million vertices (975,953
#   vertices, 5,667,069 tets) that the repository does not store (its .node
#   alone is ~19 MB even under xz -9); "all" rebuilds every volume of the corpus.
#   OUTDIR defaults to build/bench-data under the repository root, where
#   bench/run.sh, bench/scale.sh, bench/bitrate.sh and bench/bricks.sh look for
#   bunny_1m. The script writes OUTDIR/NAME.node (TetGen format, 0-based, one
#   boundary marker column: 1 = on the boundary surface, 0 = interior) and
#   OUTDIR/NAME.ele (TetGen format, 0-based), uncompressed, and checks both
#   against data/SHA256SUMS.uncompressed.
#
# Needs Debian 12's `tetgen` (TetGen 1.5.0, package 1.5.0-5) and python3 (the
# standard library only): apt-get install -y tetgen python3.
# TetGen's output is the same for the same binary. The command line and the
# input file name are written into a comment of each output file, so both are
# fixed below. Another TetGen build may mesh differently (still validly): the
# script then prints MISMATCH and exits 1, keeping the files.
# bunny_1m on one core: about 70 s and 1 GB of memory.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=$(cd "$HERE/.." && pwd)/build/bench-data
if [ "${1:-}" = "-o" ]; then OUT=$2; shift 2; fi
NAMES=("$@"); [ ${#NAMES[@]} -gt 0 ] || NAMES=(bunny_1m)

# name | source | tetgen switches (checksums: SHA256SUMS.uncompressed)
RECIPES=$(cat <<'EOF'
bunny_10k        surfaces/bunny.off        pq1.2Ya0.00562
bunny_100k       surfaces/bunny.off        pq1.2a0.002
bunny_1m         surfaces/bunny.off        pq1.2a0.00008
elephant_10k     surfaces/elephant.off     pq1.2Ya1.23e-06
fandisk_11k      surfaces/fandisk.off      pq1.2Y
knot1_10k        surfaces/knot1.off        pq1.2Ya2.72e-06
triceratops_10k  surfaces/triceratops.off  pq1.2Ya0.00364
hand_10k         surfaces/hand.off         pq1.2Ya4.19e-06
torus_288        gen_torus:small           pYi
torus_10k        gen_torus:large           pYi
torus_288_grid   gen_torus:small:--grid    none
EOF
)
SUMS="$HERE/SHA256SUMS.uncompressed"
if [ "${NAMES[0]}" = all ]; then NAMES=($(awk '{print $1}' <<<"$RECIPES")); fi
command -v python3 >/dev/null || { echo "need python3" >&2; exit 2; }
mkdir -p "$OUT"; OUT=$(cd "$OUT" && pwd)
TMP=$(mktemp -d); trap 'rm -rf "$TMP"' EXIT
rc=0
for NAME in "${NAMES[@]}"; do
  line=$(awk -v n="$NAME" '$1==n' <<<"$RECIPES")
  [ -n "$line" ] || { echo "unknown volume: $NAME" >&2; exit 2; }
  read -r _ SRC SW <<<"$line"
  W="$TMP/$NAME"; mkdir -p "$W"; cd "$W"
  if [ "$SW" != none ]; then command -v tetgen >/dev/null || { echo "need tetgen (apt-get install tetgen)" >&2; exit 2; }; fi
  case $SRC in
    gen_torus:*)
      IFS=: read -r _ KIND FLAG <<<"$SRC"
      python3 "$HERE/gen_torus.py" "$KIND" "$NAME" ${FLAG:+"$FLAG"} >/dev/null
      if [ "$SW" != none ]; then
        tetgen -"$SW"Q "$NAME.off" >/dev/null
        # gen_torus.py's NAME.node already has markers and the same vertex order as TetGen's output
        python3 - "$NAME" <<'PYEOF'
import sys
n = sys.argv[1]
def body(fn):
    L = [l.split('#')[0].split() for l in open(fn)]
    L = [l for l in L if l]
    return [tuple(float(x) for x in r[1:4]) for r in L[1:1 + int(L[0][0])]]
if body(n + '.node') != body(n + '.1.node'):
    sys.exit('TetGen changed the vertex set of ' + n)
PYEOF
        { sed '$d' "$NAME.1.ele"; echo "# $NAME: tetrahedra by \`tetgen -${SW}Q $NAME.off\` (constrained Delaunay, no Steiner points); indices into $NAME.node"; } > "$OUT/$NAME.ele"
      fi
      cp "$NAME.node" "$OUT/$NAME.node"
      ;;
    *)
      cp "$HERE/$SRC" "$NAME.off"
      START=$(date +%s)
      tetgen -"$SW"Q "$NAME.off" >/dev/null
      echo "$NAME: tetgen -${SW}Q took $(( $(date +%s) - START )) s" >&2
      python3 - "$NAME" "$SW" "$SRC" "$OUT" <<'PYEOF'
import sys
name, sw, src, out = sys.argv[1:5]
def rows(fn):
    with open(fn) as f:
        for line in f:
            s = line.split('#')[0].split()
            if s: yield s
face = rows(name + '.1.face'); m = int(next(face)[0])
bnd = set()
for k in range(m):
    bnd.update(int(x) for x in next(face)[1:4])
with open(name + '.1.node') as f, open(out + '/' + name + '.node', 'w') as fo:
    fo.write('# %s: vertices of `tetgen -%sQ %s.off` (TetGen 1.5.0), %s = %s\n' % (name, sw, name, name, src))
    fo.write('# last column: boundary marker, 1 = on the boundary surface, 0 = interior\n')
    hdr = None
    for line in f:
        s = line.split()
        if not s or s[0].startswith('#'): continue
        if hdr is None:
            hdr = s; n = int(s[0]); fo.write('%d  3  0  1\n' % n); continue
        i = int(s[0]); fo.write('%s  %s  %s  %s  %d\n' % (s[0], s[1], s[2], s[3], 1 if i in bnd else 0))
with open(name + '.1.ele') as f, open(out + '/' + name + '.ele', 'w') as fo:
    for line in f:
        if line.startswith('#'): continue
        fo.write(line)
    fo.write('# %s: tetrahedra of `tetgen -%sQ %s.off` (TetGen 1.5.0), indices into %s.node\n' % (name, sw, name, name))
print('%s: %d vertices, %d boundary' % (name, n, len(bnd)), file=sys.stderr)
PYEOF
      ;;
  esac
  cd "$OUT"
  for f in "$NAME.node" "$NAME.ele"; do
    [ -f "$f" ] || continue
    got=$(sha256sum "$f" | awk '{print $1}')
    want=$(awk -v f="$f" '$2==f {print $1}' "$SUMS" 2>/dev/null || true)
    if [ -z "$want" ]; then echo "$f: $got (no recorded sha256)"
    elif [ "$got" = "$want" ]; then echo "$f: OK"
    else echo "$f: MISMATCH (got $got, recorded $want)"; rc=1; fi
  done
done
exit $rc
