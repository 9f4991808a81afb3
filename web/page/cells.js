// What the viewer draws of a level's tetrahedra, computed from its carved
// cells and their neighbours (web/level_view.h): the surface of the cells on
// one side of a cut plane, and shrunken cells. Pure functions on typed
// arrays, so that node tests run them on the decoder's own output.

// The faces of a positively oriented tetrahedron (a, b, c, d), by the vertex
// they are opposite, each turned so that its right-hand normal points out
// (mesh/topology.cpp's boundary_triangles uses the same table).
export const kOutwardFaces = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

// Per cell, its centroid's coordinate on `axis` (0, 1, 2).
export function centroidCoordinates(cells, positions, axis) {
  const n = cells.length / 4;
  const out = new Float32Array(n);
  for (let c = 0; c < n; ++c) {
    let sum = 0;
    for (let k = 0; k < 4; ++k) sum += positions[3 * cells[4 * c + k] + axis];
    out[c] = sum / 4;
  }
  return out;
}

// Per cell, 1 if its centroid is at or below `threshold` on the axis.
export function keptBelow(centroids, threshold) {
  const kept = new Uint8Array(centroids.length);
  for (let c = 0; c < centroids.length; ++c) kept[c] = centroids[c] <= threshold ? 1 : 0;
  return kept;
}

// The faces of the kept cells whose other side is not a kept cell: the
// level's boundary on the kept side and the cut through its interior
// ("crinkle" cut: whole cells, no sliced ones). With every cell kept it is
// the level's boundary surface. `cutFaces` receives the faces that are
// interior to the level (across them is a carved cell the cut removed), and
// `triangleCells` each triangle's cell.
export function keptSurface(cells, neighbors, kept) {
  let count = 0, cut = 0;
  const n = kept.length;
  for (let c = 0; c < n; ++c) {
    if (!kept[c]) continue;
    for (let i = 0; i < 4; ++i) {
      const other = neighbors[4 * c + i];
      if (other < 0) ++count;
      else if (!kept[other]) ++count, ++cut;
    }
  }
  const triangles = new Uint32Array(3 * count);
  const triangleCells = new Uint32Array(count);
  const cutFaces = new Uint32Array(3 * cut);
  let t = 0, u = 0;
  for (let c = 0; c < n; ++c) {
    if (!kept[c]) continue;
    for (let i = 0; i < 4; ++i) {
      const other = neighbors[4 * c + i];
      if (other >= 0 && kept[other]) continue;
      const f = kOutwardFaces[i];
      triangleCells[t / 3] = c;
      for (let k = 0; k < 3; ++k) triangles[t++] = cells[4 * c + f[k]];
      if (other >= 0) for (let k = 0; k < 3; ++k) cutFaces[u++] = cells[4 * c + f[k]];
    }
  }
  return { triangles, cutFaces, triangleCells };
}

// Triangles (indices into `positions`) as non-indexed arrays for a
// BufferGeometry, each with one colour (`triangleColours`, 3 floats each):
// a colour per cell, where the shared buffers hold one per vertex.
export function flatTriangles(triangles, positions, triangleColours) {
  const position = new Float32Array(3 * triangles.length);
  const colour = new Float32Array(3 * triangles.length);
  for (let k = 0; k < triangles.length; ++k) {
    const v = triangles[k], t = Math.floor(k / 3);
    for (let axis = 0; axis < 3; ++axis) {
      position[3 * k + axis] = positions[3 * v + axis];
      colour[3 * k + axis] = triangleColours[3 * t + axis];
    }
  }
  return { position, colour };
}

// min(cap, kept cells) kept cells, those whose centroid is nearest
// `threshold` (the cut plane) first, to within 1/4096 of the farthest
// distance. Linear: a histogram of distances finds the cut-off bin instead of
// a sort; the bins below it are taken whole, the cut-off bin in cell order.
export function cellsNearest(centroids, kept, threshold, cap) {
  const n = centroids.length, bins = 4096;
  let far = 0;
  for (let c = 0; c < n; ++c) if (kept[c]) far = Math.max(far, Math.abs(threshold - centroids[c]));
  const scale = (bins - 1) / (far || 1);
  const binOf = (c) => Math.floor(Math.abs(threshold - centroids[c]) * scale);
  const histogram = new Uint32Array(bins);
  for (let c = 0; c < n; ++c) if (kept[c]) ++histogram[binOf(c)];
  let cutBin = 0, below = 0;
  while (cutBin < bins && below + histogram[cutBin] <= cap) below += histogram[cutBin++];
  const out = new Uint32Array(Math.min(cap, below + (cutBin < bins ? histogram[cutBin] : 0)));
  let k = 0, extra = out.length - below;
  for (let c = 0; c < n; ++c) {
    if (!kept[c]) continue;
    const b = binOf(c);
    if (b < cutBin || (b === cutBin && extra > 0 && extra--)) out[k++] = c;
  }
  return out;
}

// Every chosen cell as four triangles shrunk towards its centroid by
// `factor` (1: touching its neighbours), each corner with its vertex's colour
// (`colours`, 3 floats a vertex), or with its cell's where `cellColours`
// (3 floats a cell) is given: non-indexed arrays for a BufferGeometry.
export function shrunkenCells(cells, chosen, positions, colours, factor, cellColours = null) {
  const position = new Float32Array(chosen.length * 36);
  const colour = new Float32Array(chosen.length * 36);
  let w = 0;
  const corner = [0, 0, 0, 0];
  for (const c of chosen) {
    let cx = 0, cy = 0, cz = 0;
    for (let k = 0; k < 4; ++k) {
      const v = (corner[k] = cells[4 * c + k]);
      cx += positions[3 * v];
      cy += positions[3 * v + 1];
      cz += positions[3 * v + 2];
    }
    cx /= 4, cy /= 4, cz /= 4;
    for (const f of kOutwardFaces)
      for (const k of f) {
        const v = corner[k];
        position[w] = cx + factor * (positions[3 * v] - cx);
        position[w + 1] = cy + factor * (positions[3 * v + 1] - cy);
        position[w + 2] = cz + factor * (positions[3 * v + 2] - cz);
        const from = cellColours ?? colours, at = cellColours ? 3 * c : 3 * v;
        colour[w] = from[at];
        colour[w + 1] = from[at + 1];
        colour[w + 2] = from[at + 2];
        w += 3;
      }
  }
  return { position, colour };
}

// The edges of triangles (3 indices each) as line segments (2 each).
export function triangleEdges(triangles) {
  const out = new Uint32Array(2 * triangles.length);
  for (let t = 0, w = 0; t < triangles.length; t += 3) {
    out[w++] = triangles[t], out[w++] = triangles[t + 1];
    out[w++] = triangles[t + 1], out[w++] = triangles[t + 2];
    out[w++] = triangles[t + 2], out[w++] = triangles[t];
  }
  return out;
}
