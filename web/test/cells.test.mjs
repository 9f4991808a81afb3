// The page's cell views (web/page/cells.js) on the decoder's own levels:
// with every cell kept the kept cells' surface is the level's boundary
// surface; cut anywhere it is closed (every edge met once each way); the
// cells nearest the cut respect the cap and are the nearest; shrunken cells
// keep their centroids. By region, every triangle and shrunken cell takes
// its own cell's region's colour, and the regions' cells are the stream's.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { DecoderSession } from '../page/decoder_session.js';
import { centroidCoordinates, keptBelow, keptSurface, cellsNearest, flatTriangles, shrunkenCells }
  from '../page/cells.js';
import { regionColours } from '../page/colours.js';
import { loadDecoder, webTestConfig } from './load_decoder.mjs';
import { allStreams } from './streams.mjs';

const config = webTestConfig();
const decoder = await loadDecoder(config.dist);

function decodeLevels(path) {
  const session = new DecoderSession(decoder);
  const { levels, error } = session.feed(readFileSync(path));
  assert.equal(error, null);
  const positions = new Float32Array(3 * session.header.vertexCount);
  for (const l of levels) positions.set(l.positions, 3 * l.firstNew);
  const regions = session.regions;
  session.dispose();
  return { levels, positions, regions };
}

// Triangles as a sorted list of rotation-normalised strings.
function triangleSet(triangles) {
  const out = [];
  for (let t = 0; t < triangles.length; t += 3) {
    const tri = [triangles[t], triangles[t + 1], triangles[t + 2]];
    const k = tri.indexOf(Math.min(...tri));
    out.push([tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]].join(' '));
  }
  return out.sort();
}

// Every directed edge (a, b) of the triangles is matched by exactly one (b, a).
function assertClosed(triangles) {
  const count = new Map();
  for (let t = 0; t < triangles.length; t += 3)
    for (let k = 0; k < 3; ++k) {
      const key = `${triangles[t + k]} ${triangles[t + ((k + 1) % 3)]}`;
      count.set(key, (count.get(key) || 0) + 1);
    }
  for (const [key, n] of count) {
    const [a, b] = key.split(' ');
    assert.equal(count.get(`${b} ${a}`), n, `edge ${key} is not matched`);
  }
}

const streams = allStreams(config).filter((s) => /corpus\/(bunny|elephant|ct_torus)|^golden\/torus_288.dtm/.test(s.name));

for (const stream of streams) {
  test(`cell views of ${stream.name}`, () => {
    const { levels, positions } = decodeLevels(stream.path);
    for (const l of levels) {
      const everything = new Uint8Array(l.tetrahedra).fill(1);
      const whole = keptSurface(l.cells, l.neighbors, everything);
      assert.deepEqual(triangleSet(whole.triangles), triangleSet(l.surface), `level ${l.level}: surface`);
      assert.equal(whole.cutFaces.length, 0);
      assertClosed(l.surface);

      for (const axis of [0, 1, 2]) {
        const centroids = centroidCoordinates(l.cells, positions, axis);
        const sorted = Float32Array.from(centroids).sort();
        const threshold = sorted[Math.floor(sorted.length / 2)];
        const kept = keptBelow(centroids, threshold);
        const { triangles, cutFaces } = keptSurface(l.cells, l.neighbors, kept);
        assertClosed(triangles);
        assert.ok(cutFaces.length > 0, `level ${l.level}: a cut through the middle meets cells`);

        const cap = Math.floor(l.tetrahedra / 5);
        const chosen = cellsNearest(centroids, kept, threshold, cap);
        assert.equal(chosen.length, cap);
        let farthestChosen = 0, nearestLeft = Infinity, far = 0;
        const isChosen = new Uint8Array(l.tetrahedra);
        for (const c of chosen) isChosen[c] = 1, farthestChosen = Math.max(farthestChosen, threshold - centroids[c]);
        for (let c = 0; c < l.tetrahedra; ++c) {
          if (!kept[c]) continue;
          far = Math.max(far, threshold - centroids[c]);
          if (!isChosen[c]) nearestLeft = Math.min(nearestLeft, threshold - centroids[c]);
        }
        assert.ok(farthestChosen <= nearestLeft + far / 4000, 'the cells chosen are the nearest the cut');
        assert.equal(cellsNearest(centroids, kept, threshold, 1e9).length, kept.reduce((a, b) => a + b, 0));
      }

      const some = Uint32Array.from({ length: Math.min(50, l.tetrahedra) }, (_, i) => i);
      const colours = new Float32Array(positions.length).fill(0.5);
      const { position, colour } = shrunkenCells(l.cells, some, positions, colours, 0.5);
      assert.equal(position.length, 36 * some.length);
      assert.ok(colour.every((x) => x === 0.5));
      for (const [i, c] of some.entries())
        for (let axis = 0; axis < 3; ++axis) {
          let original = 0, shrunk = 0;
          for (let k = 0; k < 4; ++k) original += positions[3 * l.cells[4 * c + k] + axis] / 4;
          for (let k = 0; k < 12; ++k) shrunk += position[36 * i + 3 * k + axis] / 12;
          assert.ok(Math.abs(original - shrunk) <= 1e-3 * (1 + Math.abs(original)), 'the centroid stays');
        }
    }
  });
}

// The golden streams with regions: two materials, whole levels, and level 0
// as the input's own cells (--exact).
const regionStreams = allStreams(config).filter((s) => /^golden\/two_materials(_exact)?\.dtm$/.test(s.name));

test('there are streams with regions to colour', () => assert.equal(regionStreams.length, 2));

for (const stream of regionStreams) {
  test(`colour by region of ${stream.name}`, () => {
    const { levels, positions, regions } = decodeLevels(stream.path);
    const expected = JSON.parse(readFileSync(stream.path.replace(/\.dtm$/, '.expected.json'), 'utf8'));
    assert.deepEqual(regions.map((r) => r.name), ['aluminium', 'steel']);
    // Triangles with a value each, as sorted rotation-normalised strings.
    const keyed = (triangles, perTriangle) =>
      [...Array(triangles.length / 3).keys()].map((t) => {
        const tri = [triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]];
        const k = tri.indexOf(Math.min(...tri));
        return `${tri[k]} ${tri[(k + 1) % 3]} ${tri[(k + 2) % 3]} ${perTriangle(t)}`;
      }).sort();
    for (const l of levels) {
      // Each region's cells at this level are those the encoder counted.
      const cells = {};
      for (const r of l.cellRegions) {
        assert.ok(r >= 1 && r <= regions.length, `level ${l.level}: region ${r}`);
        const label = String(regions[r - 1].label);
        cells[label] = (cells[label] || 0) + 1;
      }
      const golden = expected.levels.find((x) => x.level === l.level);
      assert.deepEqual(cells, golden.region_cells, `level ${l.level}: cells per region`);
      assert.ok(Object.keys(cells).length === 2, `level ${l.level}: both regions have cells`);

      // The surface's faces carry their cells' regions.
      const everything = new Uint8Array(l.tetrahedra).fill(1);
      const whole = keptSurface(l.cells, l.neighbors, everything);
      assert.deepEqual(keyed(l.surface, (t) => l.surfaceRegions[t]),
                       keyed(whole.triangles, (t) => l.cellRegions[whole.triangleCells[t]]),
                       `level ${l.level}: the surface's regions`);

      // Drawn flat, every corner of a triangle has its position and its
      // region's colour.
      const colours = regionColours(l.surfaceRegions);
      const { position, colour } = flatTriangles(l.surface, positions, colours);
      assert.equal(position.length, 3 * l.surface.length);
      for (let k = 0; k < l.surface.length; ++k)
        for (let axis = 0; axis < 3; ++axis) {
          assert.equal(position[3 * k + axis], positions[3 * l.surface[k] + axis]);
          assert.equal(colour[3 * k + axis], colours[3 * Math.floor(k / 3) + axis]);
        }
      const distinct = new Set();
      for (let t = 0; t < colour.length; t += 9) distinct.add(colour.subarray(t, t + 3).join(' '));
      assert.equal(distinct.size, new Set(l.surfaceRegions).size, 'a colour per region on the surface');

      // A cut's triangles are its cells' faces; shrunken cells take their cells' colours.
      const centroids = centroidCoordinates(l.cells, positions, 0);
      const sorted = Float32Array.from(centroids).sort();
      const kept = keptBelow(centroids, sorted[Math.floor(sorted.length / 2)]);
      const cut = keptSurface(l.cells, l.neighbors, kept);
      for (let t = 0; t < cut.triangleCells.length; ++t) {
        const c = cut.triangleCells[t];
        assert.ok(kept[c]);
        const corners = new Set(l.cells.subarray(4 * c, 4 * c + 4));
        for (let k = 0; k < 3; ++k) assert.ok(corners.has(cut.triangles[3 * t + k]), 'a face of its cell');
      }
      const cellColours = regionColours(l.cellRegions);
      const some = Uint32Array.from({ length: l.tetrahedra }, (_, i) => i);
      const shrunk = shrunkenCells(l.cells, some, positions, new Float32Array(positions.length), 0.5, cellColours);
      for (const c of some)
        for (let k = 0; k < 12; ++k)
          for (let axis = 0; axis < 3; ++axis)
            assert.equal(shrunk.colour[36 * c + 3 * k + axis], cellColours[3 * c + axis]);
    }
  });
}
