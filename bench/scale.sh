#!/usr/bin/env bash
# bench/scale.sh [BUILD_DIR] -- how the encoder and the decoder grow with the
# mesh: TetGen bunnies of about 10k, 100k, 1M and 10M vertices, each encoded
# (meshenc, codec preset, its .ele as the reference solid) and decoded (to
# the finest mesh), whole processes, time and peak memory against one
# sequential CGAL construction of the same points (also a whole process:
# reading the .node, quantizing, building). Writes bench/results/SCALE.md, the
# rows in bench/results/scale.csv, and the log-log plot docs/scale.png.
#
# The models go to BUILD_DIR/bench-data/: bunny_10k and bunny_100k from the
# repository's data/, bunny_1m by data/make_large.sh (~70 s),
# bunny_10m by TetGen here (the same recipe, a 12.9x smaller volume bound:
# ~25 min and ~8 GB on one core), each only when absent.
#   SCALE_MODELS="bunny_10k bunny_100k"  measures only those
#   SCALE_PAPER=0                        leaves out the paper preset's rows
# Needs BUILD_DIR/tools/meshenc, BUILD_DIR/bench/bench_hierarchy, tetgen,
# xz, gnuplot (apt-get install -y tetgen xz-utils gnuplot-nox).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
corpus=$root/data
data=$build/bench-data
bench=$build/bench/bench_hierarchy
meshenc=$build/tools/meshenc
models=${SCALE_MODELS:-bunny_10k bunny_100k bunny_1m bunny_10m}
for t in "$bench" "$meshenc"; do [ -x "$t" ] || { echo "scale.sh: $t not built" >&2; exit 2; }; done
for t in tetgen xz gnuplot /usr/bin/time; do
  command -v "$t" >/dev/null || { echo "scale.sh: $t missing; apt-get install -y tetgen xz-utils gnuplot-nox time" >&2; exit 2; }
done
mkdir -p "$data"

# The models, made when absent (written under a temporary name first).
make_model() {
  local m=$1
  [ -s "$data/$m.node" ] && [ -s "$data/$m.ele" ] && return
  case $m in
    bunny_10k|bunny_100k)
      for ext in node ele; do xz -dc "$corpus/$m.$ext.xz" >"$data/$m.$ext.tmp" && mv "$data/$m.$ext.tmp" "$data/$m.$ext"; done ;;
    bunny_1m)
      echo "scale.sh: generating bunny_1m with make_large.sh (~70 s)" >&2
      "$corpus/make_large.sh" -o "$data" bunny_1m >&2 ;;
    bunny_10m)
      # make_large.sh's recipe for the bunny with a smaller volume bound.
      echo "scale.sh: generating bunny_10m with TetGen (~25 min, ~8 GB)" >&2
      local work; work=$(mktemp -d)
      cp "$corpus/surfaces/bunny.off" "$work/bunny_10m.off"
      (cd "$work" && tetgen -pq1.2a0.0000062Q bunny_10m.off >/dev/null)
      mv "$work/bunny_10m.1.node" "$data/bunny_10m.node"
      mv "$work/bunny_10m.1.ele" "$data/bunny_10m.ele"
      rm -rf "$work" ;;
    *) echo "scale.sh: unknown model $m" >&2; exit 2 ;;
  esac
}

commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
git -C "$root" diff --quiet HEAD -- core codec mesh common tools 2>/dev/null || commit+=" + uncommitted changes"
csv=$root/bench/results/scale.csv
echo "model,vertices,task,seconds,peak_mib" >"$csv"
# One whole process, timed: appends a row.
measure() {  # model vertices task command...
  local model=$1 vertices=$2 task=$3; shift 3
  local t; t=$(mktemp)
  /usr/bin/time -f "%e %M" -o "$t" "$@" >/dev/null 2>&1 || { echo "scale.sh: $task on $model failed: $*" >&2; cat "$t" >&2; exit 1; }
  read -r secs kib <"$t"; rm -f "$t"
  echo "$model,$vertices,$task,$secs,$(awk -v k="$kib" 'BEGIN { printf "%.0f", k / 1024 }')" >>"$csv"
  echo "scale.sh: $model $task: $secs s, $((kib / 1024)) MiB" >&2
}
for m in $models; do
  make_model "$m"
  n=$(awk '!/^#/ && NF { print $1; exit }' "$data/$m.node")
  measure "$m" "$n" construction "$bench" --peak-memory "$data/$m.node" cgal
  measure "$m" "$n" encode "$meshenc" "$data/$m.node" --box 256 --dmax 2 -q -o "$data/$m.dtm"
  # The decoder to the finest mesh, reading the stream from its file.
  measure "$m" "$n" decode "$bench" --peak-memory "$data/$m.node" decode
  if [ "${SCALE_PAPER:-1}" != 0 ] && [ "$n" -lt 5000000 ]; then
    measure "$m" "$n" encode_paper "$meshenc" "$data/$m.node" --box 256 --dmax 2 --preset paper -q -o "$data/$m.paper.dtm"
  fi
done

# The table and the plot, from the rows.
out=$root/bench/results/SCALE.md
python3 - "$csv" "$out" "$commit" <<'PY'
import csv, sys, collections, math, datetime
rows = list(csv.DictReader(open(sys.argv[1])))
by = collections.OrderedDict()
for r in rows:
    by.setdefault(r['model'], {})[r['task']] = r
    by[r['model']]['vertices'] = int(r['vertices'])
def cell(m, task, what):
    r = m.get(task)
    if not r: return '-'
    v = float(r[what]); c = float(m['construction'][what])
    return ('%.1f s' % v if what == 'seconds' else '%d MiB' % v) + ' = **%.2fx**' % (v / c)
lines = ['# How encoding and decoding grow with the mesh', '',
         'Written by `bench/scale.sh` (do not edit by hand; rerun it): %s, commit %s, %s.' % (
             datetime.datetime.utcnow().strftime('%Y-%m-%d %H:%M UTC'), sys.argv[3], 'this machine: 2 cores, 24 GiB'), '',
         'Whole processes, each measured by `/usr/bin/time` (wall time, peak resident memory). '
         '*One construction*: `bench_hierarchy --peak-memory MODEL.node cgal` reads the .node, quantizes it (q = 14 in '
         'a 256 box) and builds its Delaunay tetrahedralization with CGAL on one thread. *Encode*: `meshenc MODEL.node '
         '--box 256 --dmax 2 -q -o MODEL.dtm` (codec preset; it also reads the .ele, the reference solid, and writes the '
         'stream). *Decode*: `bench_hierarchy --peak-memory MODEL.node decode` reads that stream and decodes the finest '
         'level\'s mesh (no file written). *Paper*: `meshenc ... --preset paper` (not run at 10M). Ratios are to the '
         'construction of the same row.', '',
         '| model | vertices | one construction | encode | decode | encode, paper preset |',
         '|---|---:|---|---|---|---|']
for name, m in by.items():
    c = m['construction']
    lines.append('| %s | %s | %.1f s, %d MiB | %s; %s | %s; %s | %s |' % (
        name, format(m['vertices'], ','), float(c['seconds']), float(c['peak_mib']),
        cell(m, 'encode', 'seconds'), cell(m, 'encode', 'peak_mib'),
        cell(m, 'decode', 'seconds'), cell(m, 'decode', 'peak_mib'),
        cell(m, 'encode_paper', 'seconds')))
# Slopes of log time and log memory against log vertices, between the
# smallest and the largest model measured (1: linear).
def slope(task, what):
    pts = [(math.log(m['vertices']), math.log(float(m[task][what]))) for m in by.values() if task in m]
    if len(pts) < 2: return '-'
    (x0, y0), (x1, y1) = pts[0], pts[-1]
    return '%.2f' % ((y1 - y0) / (x1 - x0))
lines += ['', 'Growth (the slope of log time, log memory against log vertices, smallest to largest model): '
          'construction %s, %s; encode %s, %s; decode %s, %s; paper %s.' % (
              slope('construction', 'seconds'), slope('construction', 'peak_mib'), slope('encode', 'seconds'),
              slope('encode', 'peak_mib'), slope('decode', 'seconds'), slope('decode', 'peak_mib'),
              slope('encode_paper', 'seconds')), '', '![time and memory against vertices](../../docs/scale.png)', '']
open(sys.argv[2], 'w').write('\n'.join(lines))
# gnuplot data: vertices, then seconds and MiB per task.
with open(sys.argv[1] + '.dat', 'w') as f:
    for m in by.values():
        vals = [str(m['vertices'])]
        for t in ('construction', 'encode', 'decode', 'encode_paper'):
            vals += [m[t]['seconds'], m[t]['peak_mib']] if t in m else ['NaN', 'NaN']
        f.write(' '.join(vals) + '\n')
PY
gnuplot <<GP
set terminal pngcairo size 1100,460 font ",11"
set output "$root/docs/scale.png"
set multiplot layout 1,2
set logscale xy
set grid
set key top left
set xlabel "vertices"
set ylabel "seconds (whole process)"
plot "$csv.dat" u 1:2 w lp pt 7 t "one construction", "" u 1:4 w lp pt 5 t "encode (codec)", "" u 1:6 w lp pt 9 t "decode", "" u 1:8 w lp pt 11 t "encode (paper)"
set ylabel "peak memory (MiB)"
plot "$csv.dat" u 1:3 w lp pt 7 t "one construction", "" u 1:5 w lp pt 5 t "encode (codec)", "" u 1:7 w lp pt 9 t "decode"
unset multiplot
GP
rm -f "$csv.dat"
echo "scale.sh: wrote $out, $csv and docs/scale.png" >&2
