#!/usr/bin/env bash
# bench/cell_data.sh [BUILD_DIR] -- what a simulation mesh's per-cell arrays
# cost (format 10.0: level 0's cells carry them), on the two-material gmsh
# part of bench/regions.sh (data/two_materials.geo, REGIONS_GMSH_SIZE,
# default 0.1: about 190k vertices, 1M tetrahedra; made here by Debian's
# gmsh). Its cells are given, as a solver's output would give them:
#   * stress (float64): a smooth field of the centroid, 2.9x larger in the
#     steel (a jump at the interface), and the same as float32;
#   * youngs_modulus (float64): the material's, constant per region;
#   * quality (float64): each tetrahedron's radius ratio, which changes from
#     cell to cell (no smooth field: the hard case);
# written as meshio writes a .vtu by default (zlib), with the regions and
# tagged triangles. Per array: the stream's bytes and bits per value,
# lossless and (stress) within 1e-3 of its range, against zstd -19 and xz -9
# of the same values stored raw in the input's element order; encode and
# decode time with and without them; the same in bricked layers (format
# 16.0, `--bricks`), on one process and on two MPI ranks, and what a box
# of level 0 reads there. Whole processes, GNU time. Writes bench/results/CELL_DATA.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
py=/usr/bin/python3
work=$build/regions-data
mkdir -p "$work"
cd "$work"
size=${REGIONS_GMSH_SIZE:-0.1}
sed "s/Mesh.CharacteristicLengthMax = .*/Mesh.CharacteristicLengthMax = $size;/" "$root/data/two_materials.geo" > gmsh_part.geo
[ -f gmsh_part.msh ] || gmsh -3 -nt 2 gmsh_part.geo -format msh41 -o gmsh_part.msh > gmsh.log

"$py" - <<'PY'
import meshio, numpy as np
mesh = meshio.read("gmsh_part.msh")
p = mesh.points
tetra = np.vstack([b.data for b in mesh.cells if b.type == "tetra"])
region = np.concatenate([mesh.cell_data["gmsh:physical"][i] for i, b in enumerate(mesh.cells) if b.type == "tetra"])
tri = np.vstack([b.data for b in mesh.cells if b.type == "triangle"])
tri_tag = np.concatenate([mesh.cell_data["gmsh:physical"][i] for i, b in enumerate(mesh.cells) if b.type == "triangle"])
c = p[tetra].mean(axis=1)
steel = region == 2
stress = 1.0e8 * (1 + 0.5 * np.sin(3 * c[:, 0]) * np.cos(2 * c[:, 1]) + 0.2 * c[:, 2]) * np.where(steel, 2.9, 1.0)
youngs = np.where(steel, 200e9, 70e9)
# The radius ratio 3 r_in / r_circ of each tetrahedron.
a, b, cc, d = (p[tetra[:, k]] for k in range(4))
vol = np.abs(np.einsum("ij,ij->i", b - a, np.cross(cc - a, d - a))) / 6
area = sum(np.linalg.norm(np.cross(y - x, z - x), axis=1) / 2 for x, y, z in ((a, b, cc), (a, b, d), (a, cc, d), (b, cc, d)))
r_in = 3 * vol / area
ab, ac, ad = b - a, cc - a, d - a
num = np.linalg.norm((ab ** 2).sum(1)[:, None] * np.cross(ac, ad) + (ac ** 2).sum(1)[:, None] * np.cross(ad, ab)
                     + (ad ** 2).sum(1)[:, None] * np.cross(ab, ac), axis=1)
r_circ = num / (12 * vol)
quality = 3 * r_in / r_circ
arrays = {"stress": stress, "stress32": stress.astype(np.float32), "youngs_modulus": youngs, "quality": quality}
cells = [("tetra", tetra), ("triangle", tri)]
cell_data = {"gmsh:physical": [region, tri_tag]}
for name, v in arrays.items():
    cell_data[name] = [v, np.zeros(len(tri), v.dtype)]
meshio.write("cells.vtu", meshio.Mesh(p, cells, cell_data=cell_data))
for name, v in arrays.items():
    v.tofile(name + ".raw")
np.save("range.npy", np.array([stress.min(), stress.max()]))
# A box around the middle, a fifth of the part's extent on each axis.
lo, hi = p.min(axis=0), p.max(axis=0)
mid, half = (lo + hi) / 2, (hi - lo) / 10
open("box.txt", "w").write(" ".join("%.6g" % v for v in list(mid - half) + list(mid + half)) + "\n")
# The lossy rows' baseline: the values a bound E lets a coder keep,
# round(v / 2E), as int32, raw.
error = 1e-3 * (stress.max() - stress.min())
np.round(stress / (2 * error)).astype(np.int32).tofile("stress_q.raw")
np.round(stress.astype(np.float32) / (2 * error)).astype(np.int32).tofile("stress32_q.raw")
PY
for a in stress stress32 youngs_modulus quality stress_q stress32_q; do
  zstd -q -19 -f $a.raw -o $a.raw.zst
  xz -9 -k -f -T1 $a.raw
done
error=$("$py" -c "import numpy as np; r = np.load('range.npy'); print('%.6g' % (1e-3 * (r[1] - r[0])))")

run() {  # NAME command...: "seconds peak_kib" into NAME.time
  local name=$1; shift
  /usr/bin/time -f "%e %M" -o "$name.time" "$@" > "$name.out" 2>&1
}
run cells.with "$enc" cells.vtu -o cells.with.dtm --report cells.with.json
run cells.lossy "$enc" cells.vtu -o cells.lossy.dtm --report cells.lossy.json --field-error stress=$error \
  --field-error stress32=$error
run cells.without "$enc" cells.vtu -o cells.without.dtm --report cells.without.json --no-cell-data
run cells.decode "$dec" cells.with.dtm -o cells.decoded.vtu -q
run cells.decode_without "$dec" cells.without.dtm -o cells.decoded_without.vtu -q
# In bricks (16.0; without the tagged faces, so that the bytes are the cell
# data's and the cells').
run bricks.with "$enc" cells.vtu --bricks -o bricks.with.dtm --report bricks.with.json --no-face-tags
run bricks.without "$enc" cells.vtu --bricks -o bricks.without.dtm --report bricks.without.json --no-cell-data \
  --no-face-tags
run bricks.decode "$dec" bricks.with.dtm -o bricks.decoded.vtu -q
run bricks.decode_without "$dec" bricks.without.dtm -o bricks.decoded_without.vtu -q
# A box, from streams of bricks of 256 points (what region reading wants;
# the default 2,048 makes level 0 about 24 chunks here).
run small.with "$enc" cells.vtu --bricks --brick-points 256 -o small.with.dtm --no-face-tags
run small.without "$enc" cells.vtu --bricks --brick-points 256 -o small.without.dtm --no-cell-data --no-face-tags
# On two MPI ranks (every rank keeps every tetrahedron and its values:
# a cell's source may be any at its corners): the bytes of one process.
as_root=()
[ "$(id -u)" -eq 0 ] && as_root=(--allow-run-as-root)
run mpi.with mpirun --oversubscribe "${as_root[@]}" -n 2 "$enc" cells.vtu --bricks -o mpi.with.dtm --no-face-tags
run mpi.without mpirun --oversubscribe "${as_root[@]}" -n 2 "$enc" cells.vtu --bricks -o mpi.without.dtm \
  --no-cell-data --no-face-tags
{ cmp -s bricks.with.dtm mpi.with.dtm && cmp -s bricks.without.dtm mpi.without.dtm && echo yes || echo no; } > mpi.same
read -r -a box < box.txt
run bricks.box "$dec" small.with.dtm --box "${box[@]}" -o bricks.box.vtu
run bricks.box_without "$dec" small.without.dtm --box "${box[@]}" -o bricks.box_without.vtu

"$py" - "$error" <<'PY'
import json, os, sys
error = float(sys.argv[1])
w = json.load(open("cells.with.json"))
l = json.load(open("cells.lossy.json"))
wo = json.load(open("cells.without.json"))
def time_of(name):
    s, kib = open(name + ".time").read().split()[-2:]
    return float(s), int(kib) / 1024
cells = w["level0_cells"]
inputs = int(os.path.getsize("youngs_modulus.raw") / 8)
out = ["# Cell data: what a simulation mesh's per-cell arrays cost", "",
       "Made by `bench/cell_data.sh` (the two-material gmsh part of bench/regions.sh, meshed here by "
       "Debian's gmsh 4.8.4; whole processes on this project's 2-core machine, one run each). The stream "
       "codes level 0's kept cells' values; zstd and xz compress the input's values raw in its element "
       "order (for a lossy row, round(v / 2E) as int32: what the bound lets any coder keep).", "",
       "%d vertices, %d input tetrahedra; level 0 has %d cells, %d of them input tetrahedra (their values "
       "exact), the others given the values of the input tetrahedron holding their centroid%s." % (
           w["input_points"], inputs, cells, w["cells_from_input"],
           "" if not w["cells_from_nearest"] else " (%d the nearest beside them)" % w["cells_from_nearest"]), "",
       "| array | mode | bytes | bits/value | zstd -19 | xz -9 | ours / better |",
       "|---|---|---:|---:|---:|---:|---:|"]
for report, mode in ((w, "lossless"), (l, "within %.4g (1e-3 of the range)" % error)):
    for f in report["cell_fields"]:
        if mode != "lossless" and not f["mode"] == "lossy":
            continue
        n = f["name"]
        base = n if mode == "lossless" else n + "_q"  # lossy: round(v / 2E) as int32
        bits = 8.0 * f["bytes"] / (cells * f["components"])
        zst = 8.0 * os.path.getsize(base + ".raw.zst") / inputs
        xz = 8.0 * os.path.getsize(base + ".raw.xz") / inputs
        ratio = "%.3f" % (bits / min(zst, xz)) if min(zst, xz) > 0.1 else "(both under 0.1 bit)"
        out.append("| %s (%s) | %s | %d | %.3g | %.3g | %.3g | %s |" % (n, f["type"], mode, f["bytes"], bits, zst, xz, ratio))
te, tw, td, tdw = time_of("cells.with"), time_of("cells.without"), time_of("cells.decode"), time_of("cells.decode_without")
cell_bytes = w["cell_value_bytes"] + w["cell_field_table_bytes"]
out += ["", "The whole stream: %d bytes with the four arrays (%d of them the arrays: %.1f%%), %d without "
        "(`--no-cell-data`); the .vtu with them, zlib: %d bytes." % (
            w["stream_bytes"], cell_bytes, 100.0 * cell_bytes / w["stream_bytes"], wo["stream_bytes"],
            os.path.getsize("cells.vtu")), "",
        "| | encode | decode to .vtu |", "|---|---:|---:|",
        "| with the arrays | %.2f s, %.0f MiB | %.2f s, %.0f MiB |" % (te[0], te[1], td[0], td[1]),
        "| without (`--no-cell-data`) | %.2f s, %.0f MiB | %.2f s, %.0f MiB |" % (tw[0], tw[1], tdw[0], tdw[1]), ""]
# In bricks: each of level 0's chunks codes its own cells' values.
b = json.load(open("bricks.with.json"))
bo = json.load(open("bricks.without.json"))
whole_bytes = {f["name"]: f["bytes"] for f in w["cell_fields"]}
out += ["## In bricked layers (format 16.0, `meshenc --bricks`)", "",
        "Each of level 0's chunks codes the values of the cells its brick owns, with only the chunk's "
        "earlier cells as neighbours (spec/FORMAT.md §3.5); level 0 has %d cells, %d of them input "
        "tetrahedra." % (b["level0_cells"], b["cells_from_input"]), "",
        "| array | bytes in bricks | bytes whole | bricks / whole |", "|---|---:|---:|---:|"]
for f in b["cell_fields"]:
    out.append("| %s (%s) | %d | %d | %.3f |" % (f["name"], f["type"], f["bytes"], whole_bytes[f["name"]],
                                                 f["bytes"] / whole_bytes[f["name"]]))
be, bw, bd, bdw = (time_of(n) for n in ("bricks.with", "bricks.without", "bricks.decode", "bricks.decode_without"))
def box_read(name):  # meshdec's "read X of Y bytes (P%)" line
    for line in open(name + ".out"):
        if " read " in line:
            return line.split(";")[-1].strip()
    return "?"
out += ["", "| | encode | decode to .vtu |", "|---|---:|---:|",
        "| bricks, with the arrays | %.2f s, %.0f MiB | %.2f s, %.0f MiB |" % (be[0], be[1], bd[0], bd[1]),
        "| bricks, without (`--no-cell-data`) | %.2f s, %.0f MiB | %.2f s, %.0f MiB |" % (bw[0], bw[1], bdw[0], bdw[1]),
        "| bricks on 2 MPI ranks, with the arrays | %.2f s, %.0f MiB | |" % time_of("mpi.with"),
        "| bricks on 2 MPI ranks, without | %.2f s, %.0f MiB | |" % time_of("mpi.without"),
        "", "On ranks (`mpirun -n 2 meshenc --bricks`, oversubscribed on this machine's 2 cores, a rank's peak "
        "the largest process's): the same bytes as one process: %s. Each rank reads the whole .vtu, and "
        "with cell data keeps every tetrahedron until level 1 is built and their values to the end (a cell's source may "
        "be any tetrahedron at its corners), so a rank's memory is about one process's." %
        open("mpi.same").read().strip(),
        "", "A box a fifth of the part's extent on each axis around its middle (`meshdec --box %s`), level 0 "
        "of streams in bricks of 256 points (`--brick-points 256`): with the arrays, %s; without, %s. (A "
        "chunk read only for its points, in the box's halo, is read without its cell values, which have "
        "their own checksum.)" % (
            open("box.txt").read().strip(), box_read("bricks.box"), box_read("bricks.box_without")), ""]
open(os.environ.get("CELL_DATA_OUT", "CELL_DATA.md"), "w").write("\n".join(out))
print("\n".join(out))
PY
cp CELL_DATA.md "$root/bench/results/CELL_DATA.md"
