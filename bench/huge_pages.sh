#!/usr/bin/env bash
# bench/huge_pages.sh [BUILD_DIR] -- what asking glibc for transparent huge
# pages (tools/huge_pages.h) changes, on bunny_1m (--box 256 --dmax 2): each
# command run with it (the default) and with DTM_HUGE_PAGES=0, alternately,
# HUGE_RUNS times (default 3): one sequential CGAL construction
# (bench_hierarchy ... cgal, which asks as the tools do), level 0 decoded
# in-process from the default and the --exact stream (bench_hierarchy ...
# decode), and whole meshenc and meshdec processes (GNU time: wall, user,
# system). Medians. Writes bench/results/HUGE_PAGES.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
runs=${HUGE_RUNS:-3}
enc=$build/tools/meshenc
dec=$build/tools/meshdec
bench=$build/bench/bench_hierarchy
large=$build/bench-data
[ -s "$large/bunny_1m.ele" ] || "$root/data/make_large.sh" -o "$large" bunny_1m >&2
work=$build/huge-pages-data
mkdir -p "$work"
cd "$work"
for ext in node ele; do ln -sf "$large/bunny_1m.$ext" bunny_1m.$ext; done
"$enc" bunny_1m.node -q --box 256 --dmax 2 -o plain.dtm
"$enc" bunny_1m.node -q --box 256 --dmax 2 --exact -o exact.dtm
mode=$(cat /sys/kernel/mm/transparent_hugepage/enabled)
: > times.txt
for r in $(seq "$runs"); do
  for huge in 1 0; do
    export DTM_HUGE_PAGES=$huge
    echo "$huge cgal $("$bench" --peak-memory bunny_1m.node cgal | sed 's/.*seconds=\([0-9.]*\).*/\1/')" >> times.txt
    for kind in plain exact; do
      cp $kind.dtm bunny_1m.dtm
      echo "$huge decode_$kind $("$bench" --peak-memory bunny_1m.node decode | sed 's/.*seconds=\([0-9.]*\).*/\1/')" >> times.txt
    done
    /usr/bin/time -f "%e %U %S %M" -o t.txt "$enc" bunny_1m.node -q --box 256 --dmax 2 -o again.dtm
    cmp -s again.dtm plain.dtm || { echo "huge_pages.sh: the stream changed" >&2; exit 1; }
    echo "$huge meshenc $(cat t.txt)" >> times.txt
    /usr/bin/time -f "%e %U %S %M" -o t.txt "$dec" plain.dtm -q -o out.node
    echo "$huge meshdec $(cat t.txt)" >> times.txt
  done
done
unset DTM_HUGE_PAGES
rm -f bunny_1m.dtm again.dtm out.node out.ele t.txt
python3 - "$mode" "$runs" "$(git -C "$root" rev-parse --short HEAD)" > "$root/bench/results/HUGE_PAGES.md" <<'PY'
import statistics, sys
mode, runs, rev = sys.argv[1:]
rows = {}
for line in open("times.txt"):
    huge, what, *values = line.split()
    rows.setdefault((what, huge), []).append([float(v) for v in values])
def med(what, huge, i=0):
    return statistics.median(v[i] for v in rows[(what, huge)])
print("# Transparent huge pages: asked for, and not\n")
print(f"Made by `bench/huge_pages.sh` at {rev} on this project's 2-core machine (a VM; "
      f"/sys/kernel/mm/transparent_hugepage/enabled: `{mode}`), bunny_1m (975,953 vertices, "
      f"`--box 256 --dmax 2`). Each command {runs} times with the tools' default (glibc asked for huge pages: "
      "tools/huge_pages.h) and with `DTM_HUGE_PAGES=0`, alternately; medians. The streams are the same bytes either way.\n")
print("| run | huge pages | 4 KiB pages | x |")
print("|---|---:|---:|---:|")
for what, label in [("cgal", "one sequential CGAL construction (in-process)"),
                    ("decode_plain", "level 0 decoded in-process, default stream"),
                    ("decode_exact", "level 0 decoded in-process, --exact stream")]:
    a, b = med(what, "1"), med(what, "0")
    print(f"| {label} | {a:.2f} s | {b:.2f} s | {b / a:.2f} |")
for what in ["meshenc", "meshdec"]:
    a, b = med(what, "1"), med(what, "0")
    print(f"| {what} process, wall (user + system CPU) | {a:.2f} s ({med(what, '1', 1):.1f} + {med(what, '1', 2):.1f}) "
          f"| {b:.2f} s ({med(what, '0', 1):.1f} + {med(what, '0', 2):.1f}) | {b / a:.2f} |")
print(f"| meshenc peak | {med('meshenc', '1', 3) / 1024:.0f} MiB | {med('meshenc', '0', 3) / 1024:.0f} MiB | |")
print(f"| meshdec peak | {med('meshdec', '1', 3) / 1024:.0f} MiB | {med('meshdec', '0', 3) / 1024:.0f} MiB | |")
print()
for huge, name in [("1", "huge pages"), ("0", "4 KiB pages")]:
    c = med("cgal", huge)
    print(f"* Decode over one construction, both with {name}: default stream "
          f"{med('decode_plain', huge) / c:.2f}x, --exact {med('decode_exact', huge) / c:.2f}x.")
PY
cat "$root/bench/results/HUGE_PAGES.md"
