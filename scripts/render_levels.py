#!/usr/bin/python3
"""Renders surfaces (PLY, OFF: meshdec's level surfaces, or an input's) side
by side into one PNG, without a display: a small z-buffer rasterizer over
numpy, flat shading, the same view for every panel.

    scripts/render_levels.py OUT.png [--azimuth DEG] [--elevation DEG] A.ply B.ply ...

Each panel is fitted to its own bounding box and labelled below by its file
name. Needs python3-meshio and python3-numpy (scripts/setup.sh).
"""
import argparse
import struct
import sys
import zlib

import meshio
import numpy as np

SIZE = 360
FONT = {  # 3x5 digits and a few letters for the labels
    "0": "111101101101111", "1": "010110010010111", "2": "111001111100111", "3": "111001111001111",
    "4": "101101111001001", "5": "111100111001111", "6": "111100111101111", "7": "111001001001001",
    "8": "111101111101111", "9": "111101111001111", "_": "000000000000111", "-": "000000111000000",
}


def rotation(azimuth, elevation):
    a, e = np.radians(azimuth), np.radians(elevation)
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, np.cos(e), -np.sin(e)], [0, np.sin(e), np.cos(e)]])
    # Looking along -y after the turn: x right, z up.
    return rx @ rz


def render(path, rot):
    mesh = meshio.read(path)
    tris = np.concatenate([c.data for c in mesh.cells if c.type == "triangle"])
    p = mesh.points[:, :3] @ rot.T
    lo, hi = p.min(axis=0), p.max(axis=0)
    scale = 0.9 * SIZE / max(hi[0] - lo[0], hi[2] - lo[2])
    centre = (lo + hi) / 2
    sx = (p[:, 0] - centre[0]) * scale + SIZE / 2
    sy = SIZE / 2 - (p[:, 2] - centre[2]) * scale
    depth = p[:, 1]
    image = np.full((SIZE, SIZE), -1.0)  # -1: background
    zbuf = np.full((SIZE, SIZE), np.inf)
    light = np.array([0.4, -0.8, 0.5])
    light /= np.linalg.norm(light)
    for t in tris:
        a, b, c = p[t]
        n = np.cross(b - a, c - a)
        norm = np.linalg.norm(n)
        if norm == 0:
            continue
        shade = 0.25 + 0.75 * abs(np.dot(n / norm, light))
        xs, ys = sx[t], sy[t]
        x0, x1 = max(int(np.floor(xs.min())), 0), min(int(np.ceil(xs.max())), SIZE - 1)
        y0, y1 = max(int(np.floor(ys.min())), 0), min(int(np.ceil(ys.max())), SIZE - 1)
        if x0 > x1 or y0 > y1:
            continue
        gx, gy = np.meshgrid(np.arange(x0, x1 + 1) + 0.5, np.arange(y0, y1 + 1) + 0.5)
        d = (ys[1] - ys[2]) * (xs[0] - xs[2]) + (xs[2] - xs[1]) * (ys[0] - ys[2])
        if d == 0:
            continue
        w0 = ((ys[1] - ys[2]) * (gx - xs[2]) + (xs[2] - xs[1]) * (gy - ys[2])) / d
        w1 = ((ys[2] - ys[0]) * (gx - xs[2]) + (xs[0] - xs[2]) * (gy - ys[2])) / d
        w2 = 1 - w0 - w1
        inside = (w0 >= 0) & (w1 >= 0) & (w2 >= 0)
        z = w0 * depth[t[0]] + w1 * depth[t[1]] + w2 * depth[t[2]]
        region = zbuf[y0:y1 + 1, x0:x1 + 1]
        closer = inside & (z < region)
        region[closer] = z[closer]
        image[y0:y1 + 1, x0:x1 + 1][closer] = shade
    return image, len(tris)


def label(image, text):
    x = 6
    for ch in text:
        glyph = FONT.get(ch)
        if glyph is None:
            x += 8
            continue
        for k, bit in enumerate(glyph):
            if bit == "1":
                r, c = divmod(k, 3)
                image[SIZE - 22 + 3 * r:SIZE - 19 + 3 * r, x + 3 * c:x + 3 * c + 3] = 0.001
        x += 12


def write_png(path, gray):
    rgb = np.stack([gray * 0.95, gray * 0.85, gray * 0.7], axis=-1)
    rgb[gray < 0] = 1.0
    data = (np.clip(rgb, 0, 1) * 255).astype(np.uint8)
    raw = b"".join(b"\x00" + row.tobytes() for row in data)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    h, w = data.shape[:2]
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("surfaces", nargs="+")
    ap.add_argument("--azimuth", type=float, default=30)
    ap.add_argument("--elevation", type=float, default=15)
    args = ap.parse_args()
    rot = rotation(args.azimuth, args.elevation)
    panels = []
    for path in args.surfaces:
        image, count = render(path, rot)
        label(image, str(count))
        panels.append(image)
        print(f"{path}: {count} triangles", file=sys.stderr)
    write_png(args.out, np.concatenate(panels, axis=1))


if __name__ == "__main__":
    main()
