#!/usr/bin/env bash
# bench/levels.sh [BUILD_DIR] -- the codec's levels (meshenc's default
# preset) on the TetGen corpus of data/ (DTM_DATA overrides it), each model with its
# own tetrahedra as the reference solid, q = 14, --box 256 --dmax 2:
#   meshenc MODEL.node --box 256 --dmax 2 --no-fields -o MODEL.dtm --report MODEL.json -q
# and the paper's preset beside it (--preset paper). Writes bench/results/LEVELS.md
# (per model: levels, vertices per level, shape error both ways per level,
# quality per level, bits per vertex, the carving corrections' share, and
# the ratio to Draco's kd-tree coder at q = 14 from bench/results/bitrate.csv)
# and bench/results/levels.csv. LEVELS_MODELS="a b" runs a subset.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
vols=${DTM_DATA:-$root/data}
enc=$build/tools/meshenc
data=$build/levels-data
mkdir -p "$data"
MODELS=${LEVELS_MODELS:-"torus_10k bunny_10k elephant_10k fandisk_11k knot1_10k triceratops_10k hand_10k bunny_100k"}
start=$(date +%s)
for m in $MODELS; do
  for ext in node ele; do
    [ -f "$data/$m.$ext" ] || xz -dc "$vols/$m.$ext.xz" > "$data/$m.$ext"
  done
  for preset in codec paper; do
    /usr/bin/time -f "%e" -o "$data/$m.$preset.seconds" \
      "$enc" "$data/$m.node" --box 256 --dmax 2 --no-fields --preset $preset -o "$data/$m.$preset.dtm" \
      --report "$data/$m.$preset.json" -q
  done
done
python3 - "$root" "$data" "$(( $(date +%s) - start ))" $MODELS <<'PY'
import csv, json, sys, subprocess
root, data, seconds, models = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
# Draco's and MPEG G-PCC's points-only files at q = 14, as bench/bitrate.sh
# tabulates them (G-PCC: TMC13 v23's lossless octree from
# data/BASELINES.md; the codec is not on these machines).
gpcc, draco = {}, {}
for row in csv.DictReader(open(f"{root}/bench/results/bitrate.csv")):
    if row["q"] == "14":
        draco[row["model"]] = float(row["draco_kd_bpv"])
        if row.get("gpcc_bpv"):
            gpcc[row["model"]] = float(row["gpcc_bpv"])
commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
lines = ["# The codec's levels on the TetGen corpus", "",
         "Written by `bench/levels.sh` (do not edit by hand; rerun it). "
         f"Commit {commit}; run took {seconds} s on this machine (2 cores).", "",
         "Each model with its own tetrahedra as the reference solid, q = 14, `--box 256 --dmax 2` "
         "(D_max = 2, so the issue's bound 2 D_max = 4 and D_max / 2 = 1):", "",
         "```", "meshenc MODEL.node --box 256 --dmax 2 --no-fields [--preset paper] -o MODEL.dtm --report MODEL.json -q", "```", "",
         "Shape error, in input units: *to level* = from the reference's boundary vertices to the level's "
         "boundary surface; *to reference* = from the level's boundary surface (its vertices and its triangles' "
         "centroids) to the reference's boundary surface (max / mean). Quality = average over the level's cells of their smallest solid angle, "
         "and its ratio to level 0's. Draco = `draco_encoder -point_cloud` kd-tree at q = 14 "
         "(bench/results/bitrate.csv, the smaller of -cl 10 / -cl 4). G-PCC = MPEG's TMC13 v23 lossless "
         "octree at q = 14, the best of its variants (data/BASELINES.md through bench/results/bitrate.csv; not installed here). "
         "Level 0 vs input = the volume inside exactly one of level 0's solid and the input's tetrahedra, "
         "as a share of the input's volume (`level0_difference` in the report: shared tetrahedra cancel, the others "
         "are sampled at 400 uniform points each).", "",
         "## Summary", "",
         "| model | N | preset | levels | vertices per level | level 0 vs input: symmetric difference | max shape error (both ways) | worst mean | worst quality ratio | bits per vertex | carving share | Draco kd bpv | ratio | G-PCC bpv | ratio | encode (s) |",
         "|---|---:|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
def gpcc_text(m, bpv):
    return f"{gpcc[m]:.2f} | {bpv / gpcc[m]:.3f}" if m in gpcc else "- | -"
rows = []
detail = ["", "## Per level (codec preset)", ""]
for m in models:
    for preset in ("codec", "paper"):
        r = json.load(open(f"{data}/{m}.{preset}.json"))
        step = r["step"]
        levels = r["levels"]
        n = r["input_points"]
        bpv = 8 * r["stream_bytes"] / n
        carving = sum(l.get("carving_bytes", 0) for l in levels)
        q0 = levels[0]["avg_min_solid_angle"]
        max_err = max(max(l["max_boundary_error"], l.get("reference_max_error", 0)) for l in levels)
        worst_mean = max(l.get("reference_mean_error", 0) for l in levels)
        worst_q = min(l["avg_min_solid_angle"] / q0 for l in levels)
        seconds = open(f"{data}/{m}.{preset}.seconds").read().strip()
        d = draco.get(m)
        shown = [str(l["vertices"]) for l in levels]
        counts = ", ".join(shown if len(shown) <= 8 else shown[:5] + ["...", shown[-1]])
        diff = r.get("level0_difference")
        sym = f"{100 * diff['share']:.3f}%" if diff else "-"
        lines.append(f"| {m} | {n} | {preset} | {len(levels)} | {counts} | {sym} | "
                     f"{max_err:.2f} | {worst_mean:.2f} | {worst_q:.2f} | {bpv:.2f} | {100 * carving / r['stream_bytes']:.1f}% | "
                     f"{d:.2f} | {bpv / d:.3f} | {gpcc_text(m, bpv)} | {seconds} |" if d else
                     f"| {m} | {n} | {preset} | {len(levels)} | {counts} | {sym} | {max_err:.2f} | {worst_mean:.2f} | {worst_q:.2f} | {bpv:.2f} | {100 * carving / r['stream_bytes']:.1f}% | - | - | {gpcc_text(m, bpv)} | {seconds} |")
        rows.append(dict(model=m, preset=preset, N=n, levels=len(levels), bpv=round(bpv, 3),
                         level0_symmetric_difference=round(diff["share"], 7) if diff else "",
                         carving_bytes=carving, stream_bytes=r["stream_bytes"], max_shape_error=round(max_err, 4),
                         worst_mean_error=round(worst_mean, 4), worst_quality_ratio=round(worst_q, 4),
                         draco_bpv=d, ratio=round(bpv / d, 4) if d else "", encode_seconds=seconds))
        if preset == "codec":
            detail += [f"### {m}", "",
                       "| level | vertices | boundary | to level max / mean | to reference max / mean | quality | / level 0 | layer bytes | carving bytes |",
                       "|---:|---:|---:|---|---|---:|---:|---:|---:|"]
            for l in levels:
                detail.append(f"| {l['level']} | {l['vertices']} | {l['boundary_vertices']} | "
                              f"{l['max_boundary_error']:.2f} / {l['mean_boundary_error']:.2f} | "
                              f"{l.get('reference_max_error', 0):.2f} / {l.get('reference_mean_error', 0):.2f} | "
                              f"{l['avg_min_solid_angle']:.4f} | {l['avg_min_solid_angle'] / q0:.2f} | "
                              f"{l.get('layer_bytes', 0)} | {l.get('carving_bytes', 0)} |")
            detail.append("")
open(f"{root}/bench/results/LEVELS.md", "w").write("\n".join(lines + detail) + "\n")
with open(f"{root}/bench/results/levels.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
print(f"{root}/bench/results/LEVELS.md")
PY
