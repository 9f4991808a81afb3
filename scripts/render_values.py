#!/usr/bin/python3
"""Renders one axial slice of a scalar volume beside the same slice of
decoded levels, into one PNG: what a viewer shows of a level's values, each
pixel linearly interpolated in the level's tetrahedron that holds it.

    scripts/render_values.py OUT.png VOLUME.nrrd --slice K --threshold T L0.vtu L2.vtu ...

The first panel is the volume's slice, voxels below T shown black; the others
are meshdec's .vtu of a level (its `value` point field), sampled at the same
voxel centres (x, y, K) in the volume's index space (meshdec writes voxel
centres at index x spacing). Pixels outside every carved tetrahedron are
black. Every panel shares the grey scale of the volume's selected values.
The grey scale spans the selected values' 1st to 99th percentile; the last
panel is the last level's absolute error, white at half that span. Needs python3-meshio and python3-numpy.
"""
import argparse
import gzip
import sys

import meshio
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from render_levels import write_png  # noqa: E402

ZOOM = 3


def read_nrrd(path):
    raw = open(path, "rb").read()
    header, data = raw.split(b"\n\n", 1)
    fields = dict(line.split(": ", 1) for line in header.decode().splitlines()[1:] if ": " in line)
    sizes = [int(s) for s in fields["sizes"].split()]
    kinds = {"uint16": "<u2", "short": "<i2", "int16": "<i2", "uchar": "u1", "uint8": "u1", "float": "<f4"}
    if fields.get("encoding") == "gzip":
        data = gzip.decompress(data)
    values = np.frombuffer(data, dtype=kinds[fields["type"]]).astype(np.float64)
    spacing = float(fields.get("spacings", "1 1 1").split()[0])
    return values.reshape(sizes[2], sizes[1], sizes[0]), spacing


def sample(mesh_path, shape, k, spacing):
    """The level's values at voxel centres (i, j, k), NaN outside its cells."""
    mesh = meshio.read(mesh_path)
    pts = mesh.points / spacing
    tets = np.concatenate([c.data for c in mesh.cells if c.type == "tetra"])
    values = mesh.point_data["value"].astype(np.float64)
    out = np.full(shape, np.nan)
    z = pts[tets][:, :, 2]
    for t in tets[(z.min(axis=1) <= k) & (z.max(axis=1) >= k)]:
        p = pts[t]
        i0, i1 = max(int(np.ceil(p[:, 0].min())), 0), min(int(np.floor(p[:, 0].max())), shape[1] - 1)
        j0, j1 = max(int(np.ceil(p[:, 1].min())), 0), min(int(np.floor(p[:, 1].max())), shape[0] - 1)
        if i0 > i1 or j0 > j1:
            continue
        m = (p[1:] - p[0]).T
        if abs(np.linalg.det(m)) < 1e-12:
            continue
        gi, gj = np.meshgrid(np.arange(i0, i1 + 1), np.arange(j0, j1 + 1))
        q = np.stack([gi.ravel(), gj.ravel(), np.full(gi.size, k)]) - p[0][:, None]
        lam = np.linalg.solve(m, q)
        bary = np.vstack([1 - lam.sum(axis=0), lam])
        inside = (bary >= -1e-9).all(axis=0)
        v = (values[t] @ bary)[inside]
        out[gj.ravel()[inside], gi.ravel()[inside]] = v
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("volume")
    ap.add_argument("levels", nargs="+")
    ap.add_argument("--slice", type=int, required=True)
    ap.add_argument("--threshold", type=float, required=True)
    args = ap.parse_args()
    volume, spacing = read_nrrd(args.volume)
    original = volume[args.slice].copy()
    selected = original >= args.threshold
    # The grey scale spans the selected values' 1st to 99th percentile.
    lo, hi = np.percentile(original[selected], [1, 99])

    def grey(a):
        g = np.clip((a - lo) / (hi - lo), 0, 1) * 0.9 + 0.1
        g[np.isnan(a)] = 0
        return g

    panels = [grey(np.where(selected, original, np.nan))]
    last = None
    for path in args.levels:
        level = sample(path, original.shape, args.slice, spacing)
        panels.append(grey(level))
        last = level
        err = np.abs(level - original)[selected & ~np.isnan(level)]
        print(f"{path}: slice {args.slice}, {np.count_nonzero(~np.isnan(level))} pixels inside, mean |error| "
              f"{err.mean():.2f}, largest {err.max():.0f} (values {lo:.0f}..{hi:.0f})", file=sys.stderr)
    error = np.abs(last - original)
    error[~selected | np.isnan(last)] = np.nan
    e = np.clip(error / ((hi - lo) / 2), 0, 1) * 0.9 + 0.1
    e[np.isnan(error)] = 0
    panels.append(e)
    # Cropped to the selected voxels and a margin; image rows run top to
    # bottom: flipped so that +y is up, zoomed, a white gap between panels.
    rows, cols = np.nonzero(selected)
    r0, r1 = max(rows.min() - 3, 0), min(rows.max() + 4, selected.shape[0])
    c0, c1 = max(cols.min() - 3, 0), min(cols.max() + 4, selected.shape[1])
    gap = -np.ones(((r1 - r0) * ZOOM, 6))
    row = np.concatenate(
        [x for p in panels for x in (np.kron(np.flipud(p[r0:r1, c0:c1]), np.ones((ZOOM, ZOOM))), gap)][:-1], axis=1)
    write_png(args.out, row)


if __name__ == "__main__":
    main()
