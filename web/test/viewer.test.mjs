// The viewer page in a real browser (Debian's chromium through Playwright):
// it shows every level of golden and corpus streams with the native
// decoder's counts, ends a truncated stream on its last whole level and says
// so, shows a damaged stream's error without crashing, draws levels as a
// throttled stream arrives, opens dropped and chosen files, and draws every
// view. Screenshots go to build/web-artifacts/ (kept by CI as artifacts).
import { after, before, test } from 'node:test';
import { execFileSync } from 'node:child_process';
import assert from 'node:assert/strict';
import { existsSync, mkdirSync, readFileSync } from 'node:fs';
import { basename, join } from 'node:path';
import { webTestConfig } from './load_decoder.mjs';
import { allStreams, brokenCopies, nativeSummary } from './streams.mjs';
import { drawnShare, launchBrowser, openPage, pixelShare, serve, waitForEnd } from './browser.mjs';
import { composePicture, levelPanels } from './pictures.mjs';

const config = webTestConfig();
const shots = join(config.artifacts, 'screenshots');
mkdirSync(shots, { recursive: true });
const streams = allStreams(config);
const corpus = (name) => streams.find((s) => s.name === `corpus/${name}.dtm`);
let browser;

before(async () => { browser = await launchBrowser(); });
after(async () => { await browser?.close(); });

// Loads `stream` (a path) in a fresh page; returns the page, its final state
// and the server (closed by the caller through done()).
async function load(stream, { query = '', rate, size } = {}) {
  const server = await serve(config, stream, rate);
  const page = await openPage(browser, size);
  await page.goto(`${server.url}?stream=stream.dtm${query}`);
  const state = await waitForEnd(page);
  return { page, state, server, done: async () => { await page.close(); server.close(); } };
}

// The page's levels against the native decoder's, level by level.
function expectNativeLevels(state, native, name) {
  const expected = native.filter((l) => l.level !== undefined)
    .map((l) => ({ level: l.level, vertices: l.vertices, tetrahedra: l.tetrahedra, bytes: l.stream_bytes }));
  assert.deepEqual(state.levels, expected, `${name}: the page's levels`);
}

test('WebGL 2 draws in headless chromium', async () => {
  const page = await openPage(browser);
  await page.setContent('<canvas id="c"></canvas>');
  const renderer = await page.evaluate(() => {
    const gl = document.getElementById('c').getContext('webgl2');
    const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
    return gl ? (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : 'unknown renderer') : null;
  });
  assert.ok(renderer, 'no WebGL 2 context');
  console.log(`WebGL renderer: ${renderer}`);
  await page.close();
});

const shown = streams.filter((s) => /^golden\/[^/]+\.dtm$/.test(s.name) ||
                                    /corpus\/(bunny_10k|elephant_10k|ct_torus)/.test(s.name));
for (const stream of shown) {
  test(`every level of ${stream.name}, with meshdec's counts`, async () => {
    const { page, state, done } = await load(stream.path);
    try {
      assert.equal(state.status, 'done', state.error);
      expectNativeLevels(state, nativeSummary(config, stream.path), stream.name);
      assert.equal(state.received, readFileSync(stream.path).length);
      // ... and meshinfo's: vertices, tetrahedra, and each layer's bytes.
      const info = JSON.parse(execFileSync(config.meshinfo, [stream.path, '--json', '--stats'], { encoding: 'utf8' }));
      assert.deepEqual(state.levels.map((l) => [l.level, l.vertices, l.tetrahedra]),
                       info.levels.map((l) => [l.level, l.vertices, l.tetrahedra]));
      state.levels.forEach((l, i) => {
        if (i > 0) assert.equal(l.bytes - state.levels[i - 1].bytes, info.levels[i].layer_bytes);
      });
      assert.equal(state.levels.at(-1).bytes, info.bytes);
      assert.equal(state.shown, 0, 'the finest level is shown');
      assert.ok(await drawnShare(page) > 0.02, 'the level is drawn');
      const overlay = await page.textContent('#figures');
      assert.match(overlay, new RegExp(`level 0 · ${state.levels.at(-1).vertices.toLocaleString('en-US')} vertices`));
      assert.deepEqual(page.problems, []);
      await page.screenshot({ path: join(shots, `${basename(stream.path, '.dtm')}.png`) });
    } finally {
      await done();
    }
  });
}

for (const stream of [corpus('bunny_10k'), corpus('ct_torus')]) {
  const native = nativeSummary(config, stream.path);
  for (const copy of brokenCopies(stream, native, join(config.artifacts, 'broken-pages'))) {
    test(`${copy.name}: ends as the native decoder does`, async () => {
      const expected = nativeSummary(config, copy.path);
      const { page, state, done } = await load(copy.path);
      try {
        const end = expected.at(-1);
        assert.equal(state.status, end.end);
        assert.equal(state.error, end.message);
        expectNativeLevels(state, expected, copy.name);
        if (copy.kind === 'truncated' && state.levels.length > 0) {
          assert.match(state.error, /ends (after level|inside)/);
          assert.equal(state.shown, state.levels.at(-1).level, 'the last whole level is shown');
        }
        if (copy.kind === 'damaged') {
          assert.match(state.error, /^level \d+ at byte \d+: /, 'the error names the level and the byte');
          assert.equal(state.levels.length, copy.wholeLevels, 'the levels before the damage stand');
        }
        assert.match(await page.textContent('#status'), new RegExp(`^stream.dtm: ${end.end}`));
        assert.deepEqual(page.problems, []);
        await page.screenshot({ path: join(shots, `${basename(copy.path, '.dtm')}.png`) });
      } finally {
        await done();
      }
    });
  }
}

// A header whose vertex count is 2^32 - 1 (its checksum made anew): the page
// made room for the claim (a typed array of 12 GB: an exception, nothing
// drawn); it holds room for maxVertices at most, draws the levels before the
// decoder finds the count false, and says so.
test('a header claiming 4 billion vertices costs no more than maxVertices', async () => {
  const out = join(config.artifacts, 'broken-pages', 'claims_4g_vertices.dtm');
  mkdirSync(join(config.artifacts, 'broken-pages'), { recursive: true });
  execFileSync('python3', ['-c', `
import ctypes, struct, sys
xxh = ctypes.CDLL('libxxhash.so.0')
xxh.XXH3_64bits.restype = ctypes.c_uint64
xxh.XXH3_64bits.argtypes = [ctypes.c_char_p, ctypes.c_size_t]
b = bytearray(open(sys.argv[1], 'rb').read())
b[16:20] = struct.pack('<I', 0xFFFFFFFF)
b[52:56] = struct.pack('<I', xxh.XXH3_64bits(bytes(b[:52]), 52) & 0xFFFFFFFF)
open(sys.argv[2], 'wb').write(b)`, corpus('bunny_10k').path, out]);
  const { page, state, done } = await load(out);
  try {
    assert.equal(state.status, 'error');
    assert.match(state.error, /vertex count differs from the header/);
    assert.ok(state.levels.length >= 1, 'the levels before level 0 are drawn');
    assert.equal(state.shown, state.levels.at(-1).level);
    assert.deepEqual(page.problems, []);
  } finally {
    await done();
  }
});

test('a stream that is not there is an error, not a hang', async () => {
  const server = await serve(config);
  const page = await openPage(browser);
  try {
    await page.goto(`${server.url}?stream=missing.dtm`);
    const state = await waitForEnd(page);
    assert.equal(state.status, 'error');
    assert.match(state.error, /missing\.dtm: HTTP 404/);
    assert.deepEqual(state.levels, []);
  } finally {
    await page.close();
    server.close();
  }
});

test('levels are drawn as a throttled stream arrives', async () => {
  const stream = corpus('bunny_10k');
  // 8 KB/s: about 5 s for the stream, several times what making the renderer
  // takes on a busy machine with software rendering.
  const server = await serve(config, stream.path, '8KB/s');
  const page = await openPage(browser);
  try {
    // Every change of the state, with its time.
    await page.addInitScript(() => {
      window.dtmLog = [];
      window.addEventListener('dtmviewer', (e) => window.dtmLog.push(
        { t: performance.now(), levels: e.detail.levels.length, rendered: e.detail.rendered, received: e.detail.received }));
    });
    await page.goto(`${server.url}?stream=stream.dtm`);
    const state = await waitForEnd(page);
    const log = await page.evaluate(() => window.dtmLog);
    assert.equal(state.status, 'done');
    const firstLevel = log.find((e) => e.levels >= 1);
    assert.ok(firstLevel.received < state.received / 4, `the coarsest level came after ${firstLevel.received} of ${state.received} bytes`);
    // The viewer draws the newest level it holds: when one chunk of the
    // throttled stream completes two small levels, the finer one is drawn
    // first. What a user sees is a picture soon after the first level arrives.
    const firstDrawn = log.find((e) => e.rendered !== null);
    assert.ok(firstDrawn, 'a level was drawn');
    assert.ok(firstDrawn.received < state.received / 2, `the first picture came after ${firstDrawn.received} of ${state.received} bytes`);
    assert.ok(state.timings.firstPicture < state.timings.lastByte - 1000, 'the first picture came well before the last byte');
    // The levels were added one at a time (the slider grew a step at a time).
    const counts = new Set(log.map((e) => e.levels));
    for (let n = 1; n <= state.levels.length; ++n) assert.ok(counts.has(n), `${n} levels were shown at some point`);
    assert.deepEqual(page.problems, []);
  } finally {
    await page.close();
    server.close();
  }
});

test('a file opened from disk or dropped on the page is decoded', async () => {
  const stream = corpus('elephant_10k');
  const native = nativeSummary(config, stream.path);
  const server = await serve(config);
  const page = await openPage(browser);
  try {
    await page.goto(server.url);
    assert.equal(await page.evaluate(() => window.dtmViewer.status), 'idle');
    await page.setInputFiles('#open', stream.path);
    let state = await waitForEnd(page);
    assert.equal(state.status, 'done');
    assert.equal(state.source, 'elephant_10k.dtm');
    expectNativeLevels(state, native, 'opened');

    const bytes = [...readFileSync(corpus('bunny_10k').path)];
    await page.evaluate((data) => {
      const transfer = new DataTransfer();
      transfer.items.add(new File([new Uint8Array(data)], 'dropped.dtm'));
      document.dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, bubbles: true, cancelable: true }));
    }, bytes);
    await page.waitForFunction(() => window.dtmViewer.source === 'dropped.dtm');
    state = await waitForEnd(page);
    assert.equal(state.status, 'done');
    expectNativeLevels(state, nativeSummary(config, corpus('bunny_10k').path), 'dropped');
    assert.deepEqual(page.problems, []);
  } finally {
    await page.close();
    server.close();
  }
});

test('every view and colour draws, and the slider steps through the levels', async () => {
  const { page, state, done } = await load(corpus('ct_torus').path);
  try {
    assert.equal(state.status, 'done');
    const draw = async (name, change) => {
      const frames = await page.evaluate(() => window.dtmViewer.frames);
      await page.evaluate(change);
      await page.waitForFunction((f) => window.dtmViewer.frames > f, frames);
      const share = await drawnShare(page);
      assert.ok(share > 0.01, `${name}: ${share} of the canvas drawn`);
      await page.screenshot({ path: join(shots, `ct_torus_${name}.png`) });
      return share;
    };
    const select = (id, value) => `{ const e = document.getElementById('${id}'); e.value = '${value}';
                                      e.dispatchEvent(new Event(e.tagName === 'INPUT' ? 'input' : 'change')); }`;
    await draw('level_colours', select('colour', 'level'));
    await draw('boundary_colours', select('colour', 'boundary'));
    await draw('field_value', select('colour', 'value'));
    assert.equal(await page.isVisible('#legend'), true, 'a field has its legend');
    const surface = await drawnShare(page);
    await draw('cut', select('mode', 'cut'));
    await draw('cut_y', select('axis', '1'));
    const cut = await draw('cut_y_20', select('cut', '20'));
    assert.ok(cut < surface, 'a cut at 20% hides most of the solid');
    await draw('cells', select('mode', 'cells'));
    await draw('cells_edges', `{ const e = document.getElementById('edges'); e.checked = true; e.dispatchEvent(new Event('change')); }`);
    await draw('coarsest', select('level', '0'));
    const now = await page.evaluate(() => window.dtmViewer);
    assert.equal(now.shown, state.levels[0].level);
    assert.equal(now.rendered, now.shown);
    assert.match(await page.textContent('#figures'), new RegExp(`level ${now.shown} · ${state.levels[0].vertices} vertices`));
    assert.deepEqual(page.problems, []);
  } finally {
    await done();
  }
});

// Materials: coloured by region, the surface, a cut and shrunken cells show
// both of the two_materials part's regions in their colours, and the legend
// names them with the encoder's counts of their cells at the level shown.
test('a picture of materials: colour by region shows each in its colour, named', async () => {
  const stream = streams.find((s) => s.name === 'golden/two_materials.dtm');
  const expected = JSON.parse(readFileSync(stream.path.replace(/\.dtm$/, '.expected.json'), 'utf8'));
  const { page, state, done } = await load(stream.path, { query: '&colour=region&view=cut&cut=x:0.5&camera=60,20' });
  try {
    assert.equal(state.status, 'done', state.error);
    assert.deepEqual(state.regions, [{ label: 1, name: 'aluminium' }, { label: 2, name: 'steel' }]);
    assert.equal(await page.inputValue('#colour'), 'region');
    // Pixels nearest each region's colour (orange, sky blue), on the drawing.
    const shares = async () => [
      await pixelShare(page, (r, g, b) => r > b + 60 && g > b),
      await pixelShare(page, (r, g, b) => !(r > b + 60 && g > b) && b > r + 40 && b >= g),
    ];
    const legendFor = (level) => expected.levels.find((l) => l.level === level).region_cells;
    const draw = async (name, change) => {
      const frames = await page.evaluate(() => window.dtmViewer.frames);
      if (change) {
        await page.evaluate(change);
        await page.waitForFunction((f) => window.dtmViewer.frames > f, frames);
      }
      const [orange, blue] = await shares();
      await page.screenshot({ path: join(shots, `two_materials_region_${name}.png`) });
      const shown = await page.evaluate(() => window.dtmViewer.shown);
      const cells = legendFor(shown);
      const legend = await page.textContent('#regions');
      assert.ok(await page.isVisible('#regions'), `${name}: the regions' legend`);
      assert.match(legend, new RegExp(`aluminium \\(1\\): ${cells['1'].toLocaleString('en-US')} tetrahedra`), legend);
      assert.match(legend, new RegExp(`steel \\(2\\): ${cells['2'].toLocaleString('en-US')} tetrahedra`), legend);
      return { orange, blue };
    };
    const select = (id, value) => `{ const e = document.getElementById('${id}'); e.value = '${value}';
                                      e.dispatchEvent(new Event(e.tagName === 'INPUT' ? 'input' : 'change')); }`;
    const cut = await draw('cut');
    // docs/VIEWER.md's picture (scripts/web_pictures.sh), and the artifacts'.
    const out = process.env.DTM_UPDATE_PICTURES ? join(config.source, 'docs') : shots;
    await page.screenshot({ path: join(out, 'viewer_regions.png') });
    assert.ok(cut.orange > 0.01 && cut.blue > 0.005, `a cut shows both materials: ${JSON.stringify(cut)}`);
    const cells = await draw('cells', select('mode', 'cells'));
    assert.ok(cells.orange > 0.005 && cells.blue > 0.002, `shrunken cells of both: ${JSON.stringify(cells)}`);
    await draw('surface', select('mode', 'surface'));
    await draw('coarsest', select('level', '0'));
    const frames = await page.evaluate(() => window.dtmViewer.frames);
    await page.evaluate(select('colour', 'plain'));
    await page.waitForFunction((f) => window.dtmViewer.frames > f, frames);
    assert.equal(await page.isVisible('#regions'), false, 'no regions legend when not colouring by region');
    const plain = await shares();
    assert.ok(plain[1] < 0.001, `plain has no region colour: ${plain}`);
    assert.deepEqual(page.problems, []);
  } finally {
    await done();
  }
});

// The README's pictures (docs/viewer_*.png): written to the artifacts on every
// run, and over the committed ones with DTM_UPDATE_PICTURES=1
// (scripts/web_pictures.sh). The input's surface comes from data/surfaces.
test('pictures of every level beside the input surface', async () => {
  const surfaces = join(config.source, 'data', 'surfaces');
  const out = process.env.DTM_UPDATE_PICTURES ? join(config.source, 'docs') : shots;
  for (const [model, camera] of [['bunny', '0,0'], ['elephant', '-30,10']]) {
    const surface = join(surfaces, `${model}.off`);
    const panels = await levelPanels(browser, config, {
      stream: corpus(`${model}_10k`).path, surface: existsSync(surface) ? surface : null, camera });
    assert.ok(panels.length >= 5);
    await composePicture(browser, `${model}_10k.dtm in the viewer: the input's surface, then every level, finest first`,
                         panels, join(out, `viewer_${model}_levels.png`));
  }
});

test('a picture of the views: levels, a cut, shrunken cells', async () => {
  const out = process.env.DTM_UPDATE_PICTURES ? join(config.source, 'docs') : shots;
  const stream = corpus('bunny_10k').path;
  const server = await serve(config, stream);
  const page = await openPage(browser, { width: 300, height: 300 });
  const panels = [];
  try {
    for (const [query, caption] of [
      ['colour=level', ['colour by level', 'coarsest dark, finest bright']],
      ['colour=level&view=cut&cut=z:0.5&edges=1', ['cut through the cells', 'the tetrahedra behind a plane, whole']],
      ['colour=boundary&view=cells&cut=z:0.5', ['shrunken cells', 'boundary vertices orange, interior ones blue']],
      ['view=cut&cut=z:0.5&edges=1&level=3', ['level 3, cut', '1,021 vertices: fewer, larger cells']],
    ]) {
      await page.goto(`${server.url}?stream=stream.dtm&ui=0&camera=0,0&${query}`);
      const state = await waitForEnd(page);
      assert.equal(state.status, 'done');
      assert.ok(await drawnShare(page) > 0.02, query);
      panels.push({ png: await page.screenshot(), caption });
    }
    assert.deepEqual(page.problems, []);
  } finally {
    await page.close();
    server.close();
  }
  await composePicture(browser, 'bunny_10k.dtm: what the viewer shows of the tetrahedra', panels, join(out, 'viewer_views.png'));
});
