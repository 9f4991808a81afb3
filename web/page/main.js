// The .dtm viewer page: streams a stream into the decoder's worker, keeps
// every level it completes, and draws the one chosen (the newest, unless the
// slider says otherwise). Its state is public, for tests and for pages that
// embed it:
//   window.dtmViewer = {status: 'idle' | 'loading' | 'done' | 'truncated' | 'error',
//                       levels: [{level, vertices, tetrahedra, bytes}], error, ...}
// and a 'dtmviewer' event is dispatched on window whenever it changes.
//
// URL parameters: stream=URL (the .dtm to load), level=K (show level K once it
// arrives), colour=plain|level|boundary|region|FIELD (field:FIELD for a field
// named as one of the others), view=surface|cut|cells,
// cut=x|y|z:FRACTION, edges=1, camera=AZIMUTH,ELEVATION (degrees),
// maxVertices=N, ui=0 (the canvas alone), surface=URL.off (draw an OFF surface
// instead of a stream: the input beside its levels in the README's pictures).
import { centroidCoordinates, keptBelow, keptSurface, cellsNearest, flatTriangles, shrunkenCells, triangleEdges }
  from './cells.js';
import { fillColours, fieldRange, kRampCss, regionColours, regionCss } from './colours.js';
import { parseOff } from './off.js';
import { LevelScene } from './scene.js';

const params = new URLSearchParams(location.search);
const $ = (id) => document.getElementById(id);
const kMaxShrunkenCells = 200_000;
const kMaxEdges = 3_000_000;

const state = {
  status: 'idle',
  levels: [],
  error: null,
  source: null,
  received: 0,    // bytes arrived
  decoded: 0,     // bytes the decoder has gone through
  total: null,    // the stream's length, when the server says it
  header: null,
  fields: [],
  regions: [],     // [{label, name}] with regions (materials), else empty
  shown: null,     // the level drawn, or null
  cellsShown: 0,   // in the 'cells' view: how many shrunken cells are drawn
  trianglesDrawn: 0,
  rendered: null,  // the level of the last frame drawn
  frames: 0,
  // ms since navigation: start, renderer (made), header, firstLevel,
  // firstPicture, lastByte, end; per level, decoded[level] (in the worker)
  // and drawn[level] (first on the screen)
  timings: { decoded: {}, drawn: {} },
};
window.dtmViewer = state;

// Everything decoded so far, for the levels received (coarsest first).
let store = null;
let worker = null;
// The most vertices a level may have: the decoder refuses a level above it,
// so the buffers hold at most this many, whatever a header claims.
const maxVertices = Number(params.get('maxVertices')) || 3_000_000;
// Room for the stream's vertices: its header's count, which a damaged or
// hostile stream may inflate, bounded by what can be shown.
let capacity = 0;
let followNewest = true;
const view = {
  colour: params.get('colour') || 'plain',
  mode: params.get('view') || 'surface',
  axis: 'xyz'.indexOf((params.get('cut') || 'x:0.5').split(':')[0]),
  cut: Number((params.get('cut') || 'x:0.5').split(':')[1] ?? 0.5),
  edges: params.get('edges') === '1',
  camera: (params.get('camera') || '0,0').split(',').map(Number),
};
// (A value that is not a number, cut=y:abc or camera=abc, takes the default:
// NaN drew nothing and said nothing.)
if (view.axis < 0) view.axis = 0;
if (!Number.isFinite(view.cut)) view.cut = 0.5;
view.cut = Math.min(1, Math.max(0, view.cut));
if (view.camera.length !== 2 || !view.camera.every(Number.isFinite)) view.camera = [0, 0];

// The renderer, made once the decoder's worker runs (or at once when there is
// no stream to load): a WebGL context and its shaders keep this thread busy
// for a while (most of a second on a software renderer), and the worker needs
// this thread to start.
let scene = null;
function ensureScene() {
  scene ??= new LevelScene($('canvas'), () => {
    state.rendered = state.shown;
    state.frames += 1;
    if (state.shown !== null) {
      state.timings.firstPicture ??= performance.now();
      state.timings.drawn[state.shown] ??= performance.now();
    }
    publish();
  });
  state.timings.renderer ??= performance.now();
  return scene;
}

function publish() {
  window.dispatchEvent(new CustomEvent('dtmviewer', { detail: state }));
}

// Loads a stream in the decoder's worker: `request` is {url} or {file}.
function start(source, request) {
  worker?.terminate();
  store = null;
  followNewest = true;
  if (scene) scene.framed = false;  // the next model gets its own camera
  Object.assign(state, {
    status: 'loading', levels: [], error: null, source, received: 0, decoded: 0, total: null, header: null,
    fields: [], regions: [], shown: null, rendered: null, timings: { start: performance.now(), decoded: {}, drawn: {} },
  });
  const load = (worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' }));
  load.onmessage = (event) => { if (worker === load) receive(event.data); };
  load.onerror = (event) => {
    event.preventDefault();
    if (worker === load) finish('error', `the decoder stopped: ${event.message || 'worker error'}`);
  };
  load.postMessage({ ...request, maxVertices });
  updateOverlay();
  publish();
}

function receive(message) {
  if (message.type === 'started') {
    ensureScene();  // the worker runs: time to make the renderer
    return;
  } else if (message.type === 'progress') {
    state.received = message.received;
    state.decoded = message.decoded;
    state.total = message.total;
  } else if (message.type === 'header') {
    state.header = message.header;
    state.timings.header = performance.now();
    capacity = Math.min(message.header.vertexCount, maxVertices);
    ensureScene().allocate(capacity);
    store = { levels: [], vertexLevels: new Uint16Array(capacity), values: null };
  } else if (message.type === 'level') {
    addLevel(message);
  } else if (message.type === 'end') {
    state.received = message.received;
    state.decoded = message.decoded;
    if (message.lastByteAt) state.timings.lastByte = message.lastByteAt - performance.timeOrigin;
    finish(message.status, message.status === 'done' ? null : message.message);
    return;
  }
  updateOverlay();
  publish();
}

function addLevel(m) {
  // (The decoder stops before a level above maxVertices, and at the
  // header's count: a level beyond the room is a decoder's fault.)
  if (m.vertices > capacity) throw new Error(`level ${m.level}: ${m.vertices} vertices, room for ${capacity}`);
  if (!store.values) {
    state.fields = m.fields;
    state.regions = m.regions;
    store.values = m.fields.map((f) => new Float32Array(capacity * f.components));
    addColourChoices(m.fields, m.regions);
  }
  state.timings.decoded[m.level] = m.decodedAt - performance.timeOrigin;
  scene.addPositions(m.firstNew, m.positions);
  store.vertexLevels.fill(m.level, m.firstNew, m.vertices);
  m.fields.forEach((f, i) => store.values[i].set(m.values[i], m.firstNew * f.components));
  store.levels.push({
    level: m.level, vertices: m.vertices, tetrahedra: m.tetrahedra, bytes: m.streamBytes,
    cells: m.cells, neighbors: m.neighbors, surface: m.surface, boundary: m.boundary, centroids: null,
    cellRegions: m.cellRegions, surfaceRegions: m.surfaceRegions,
  });
  state.levels.push({ level: m.level, vertices: m.vertices, tetrahedra: m.tetrahedra, bytes: m.streamBytes });
  if (state.timings.firstLevel === undefined) state.timings.firstLevel = performance.now();
  if (!scene.framed) frameOn(m.positions);

  const slider = $('level');
  slider.max = String(store.levels.length - 1);
  const wanted = params.get('level');
  if (wanted !== null) {
    if (Number(wanted) === m.level) show(store.levels.length - 1);
  } else if (followNewest) {
    slider.value = slider.max;
    show(store.levels.length - 1);
  }
}

function finish(status, error) {
  state.status = status;
  state.error = error;
  state.timings.end = performance.now();
  worker?.terminate();
  worker = null;
  // A level asked for (level=K) that never came: show the finest there is.
  if (state.shown === null && store?.levels.length) show(store.levels.length - 1);
  updateOverlay();
  publish();
}

function frameOn(positions) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; ++i) {
    min[i % 3] = Math.min(min[i % 3], positions[i]);
    max[i % 3] = Math.max(max[i % 3], positions[i]);
  }
  scene.frame({ x: min[0], y: min[1], z: min[2] }, { x: max[0], y: max[1], z: max[2] }, ...view.camera);
}

// Draws store.levels[index] as the view asks.
function show(index) {
  const l = store.levels[index];
  if (!l) return;
  state.shown = l.level;
  $('level').value = String(index);
  // By region, every triangle takes its cell's colour: the triangles are
  // drawn with positions of their own, not over the shared buffers.
  const byRegion = colour(l) === 'region';
  const positions = scene.positions;
  if (view.mode === 'surface') {
    if (byRegion) {
      const soup = flatTriangles(l.surface, positions, regionColours(l.surfaceRegions));
      scene.showSoup(soup, view.edges ? capped(triangleEdges(l.surface)) : null, true);
    } else {
      scene.showTriangles(l.surface, view.edges ? capped(triangleEdges(l.surface)) : null);
    }
    state.trianglesDrawn = l.surface.length / 3;
  } else {
    l.centroids ??= [0, 1, 2].map((axis) => centroidCoordinates(l.cells, positions, axis));
    const centroids = l.centroids[view.axis];
    const threshold = cutThreshold(centroids);
    const kept = keptBelow(centroids, threshold);
    if (view.mode === 'cut') {
      const { triangles, cutFaces, triangleCells } = keptSurface(l.cells, l.neighbors, kept);
      const edges = capped(triangleEdges(view.edges ? triangles : cutFaces));
      if (byRegion) {
        const regions = triangleCells.map((c) => l.cellRegions[c]);
        scene.showSoup(flatTriangles(triangles, positions, regionColours(regions)), edges, true);
      } else {
        scene.showTriangles(triangles, edges);
      }
      state.trianglesDrawn = triangles.length / 3;
    } else {
      const chosen = cellsNearest(centroids, kept, threshold, kMaxShrunkenCells);
      const cellColours = byRegion ? regionColours(l.cellRegions) : null;
      const soup = shrunkenCells(l.cells, chosen, positions, scene.colours, 0.75, cellColours);
      scene.showSoup(soup, view.edges ? capped(triangleEdges(sequence(soup.position.length / 3))) : null);
      state.cellsShown = chosen.length;
      state.trianglesDrawn = 4 * chosen.length;
    }
  }
  updateOverlay();
  publish();
}

function sequence(n) {
  const out = new Uint32Array(n);
  for (let i = 0; i < n; ++i) out[i] = i;
  return out;
}

function capped(edges) {
  return edges.length / 2 <= kMaxEdges ? edges : null;
}

// The cut plane's coordinate: view.cut of the way across the level's cells.
function cutThreshold(centroids) {
  let min = Infinity, max = -Infinity;
  for (const c of centroids) min = Math.min(min, c), max = Math.max(max, c);
  return min + view.cut * (max - min);
}

// Colours the shown level's vertices as view.colour asks, sets the legend,
// and returns the mode drawn: 'region' (the triangles take their cells'
// colours), 'field', 'level', 'boundary' or 'plain'.
function colour(l) {
  const coarsest = store.levels[0].level;
  const options = { vertexLevels: store.vertexLevels, coarsest, flags: l.boundary };
  let mode = view.colour;
  const f = state.fields.findIndex((field) => `field:${field.name}` === view.colour);
  const named = state.fields.findIndex((field) => field.name === view.colour);
  if (mode === 'region' && state.regions.length > 0) {
    regionLegend(l);
    legend(null);
    return 'region';  // (the triangles carry their own colours: the vertices' are not drawn)
  }
  regionLegend(null);
  const field = f >= 0 ? f : ['plain', 'level', 'boundary'].includes(mode) ? -1 : named;
  if (field >= 0) {
    mode = 'field';
    options.values = store.values[field];
    options.components = state.fields[field].components;
    options.range = fieldRange(options.values, options.components, l.vertices);
    const name = state.fields[field].name;
    legend(state.fields[field].components > 1 ? `|${name}|` : name,
           formatValue(options.range.min), formatValue(options.range.max));
  } else if (mode === 'level') {
    legend('level', String(coarsest), '0');
  } else {
    legend(null);
    if (!['plain', 'boundary'].includes(mode)) mode = 'plain';
  }
  fillColours(scene.colours, l.vertices, mode, options);
  scene.coloursChanged(l.vertices);
  return mode;
}

// The regions' colours, names and cells at the shown level, or none.
function regionLegend(l) {
  const list = $('regions');
  list.hidden = !l;
  if (!l) return;
  const cells = new Array(state.regions.length).fill(0);
  for (const r of l.cellRegions) if (r > 0) ++cells[r - 1];
  list.replaceChildren(...state.regions.map((region, r) => {
    const item = document.createElement('span');
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = regionCss(r);
    const name = region.name ? `${region.name} (${region.label})` : `region ${region.label}`;
    item.append(swatch, `${name}: ${number(cells[r])} tetrahedra`);
    return item;
  }));
}

// The ramp's legend, or none.
function legend(name, low, high) {
  $('legend').hidden = !name;
  if (!name) return;
  $('legend-bar').style.background = kRampCss;
  $('legend-name').textContent = name;
  $('legend-min').textContent = low;
  $('legend-max').textContent = high;
}

function formatValue(x) {
  return Math.abs(x) >= 1e5 || (Math.abs(x) < 1e-3 && x !== 0) ? x.toExponential(3) : String(Number(x.toPrecision(5)));
}

// The colour menu: the three fixed choices, by region where the stream has
// regions, then the fields (a field named as a fixed choice is field:NAME).
function addColourChoices(fields, regions) {
  const select = $('colour');
  while (select.options.length > 3) select.remove(3);  // an earlier stream's
  const add = (value, text) => {
    const option = document.createElement('option');
    option.value = value;
    option.textContent = text;
    select.append(option);
  };
  if (regions.length > 0) add('region', `by region (${regions.length})`);
  const fixed = ['plain', 'level', 'boundary', 'region'];
  for (const f of fields)
    add(fixed.includes(f.name) ? `field:${f.name}` : f.name,
        `${f.name} (${f.type}${f.components > 1 ? ` x${f.components}` : ''})`);
  select.value = view.colour;
  if (select.value !== view.colour) select.value = 'plain';
}

function number(n) {
  return n.toLocaleString('en-US');
}
function bytesText(n) {
  return n < 1e3 ? `${n} B` : n < 1e6 ? `${(n / 1e3).toFixed(1)} KB` : `${(n / 1e6).toFixed(2)} MB`;
}

function updateOverlay() {
  const s = state;
  const total = s.total ? ` of ${bytesText(s.total)}` : '';
  const levelCount = s.header ? s.header.levelCount : '?';
  const words = {
    idle: 'drop a .dtm file here, or open one',
    loading: `loading: ${bytesText(s.received)}${total} received` +
      (s.decoded < s.received ? ` (${bytesText(s.decoded)} decoded)` : '') + `, ${s.levels.length} of ${levelCount} levels`,
    done: `done: ${bytesText(s.received)}, all ${s.levels.length} levels`,
    truncated: `truncated: ${bytesText(s.received)}, ${s.levels.length} of ${levelCount} whole levels (${s.error})`,
    error: `error: ${s.error}`,
  };
  $('status').textContent = `${s.source ? s.source + ': ' : ''}${words[s.status]}`;
  $('status').className = s.status;
  const l = store?.levels.find((x) => x.level === s.shown);
  $('figures').textContent = l
    ? `level ${l.level} · ${number(l.vertices)} vertices · ${number(l.tetrahedra)} tetrahedra · ` +
      `${bytesText(l.bytes)} · ${(8 * l.bytes / l.vertices).toFixed(2)} bits/vertex` +
      (view.mode === 'cells' && s.cellsShown < l.tetrahedra ? ` · ${number(s.cellsShown)} cells nearest the cut shown` : '')
    : '';
  $('level-label').textContent = l ? `level ${l.level}` : '';
}

// The controls.
$('level').addEventListener('input', (e) => {
  const index = Number(e.target.value);
  followNewest = index === store.levels.length - 1;
  show(index);
});
$('colour').addEventListener('change', (e) => { view.colour = e.target.value; redraw(); });
$('mode').addEventListener('change', (e) => { view.mode = e.target.value; syncControls(); redraw(); });
$('axis').addEventListener('change', (e) => { view.axis = Number(e.target.value); redraw(); });
$('cut').addEventListener('input', (e) => { view.cut = Number(e.target.value) / 100; redraw(); });
$('edges').addEventListener('change', (e) => { view.edges = e.target.checked; redraw(); });
$('open').addEventListener('change', (e) => { if (e.target.files[0]) openFile(e.target.files[0]); });

function redraw() {
  if (!store) return;
  const index = store.levels.findIndex((l) => l.level === state.shown);
  if (index >= 0) show(index);
}

function syncControls() {
  $('mode').value = view.mode;
  $('colour').value = view.colour;
  $('axis').value = String(view.axis);
  $('cut').value = String(Math.round(view.cut * 100));
  $('edges').checked = view.edges;
  $('cut-controls').hidden = view.mode === 'surface';
}

function openFile(file) {
  start(file.name, { file });
}

// Drag and drop a local file anywhere on the page.
document.addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
document.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
document.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  const file = e.dataTransfer?.files?.[0];
  if (file) openFile(file);
});

async function showSurface(url) {
  state.source = url;
  state.status = 'loading';
  try {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    const { positions, triangles } = parseOff(await response.text());
    scene.allocate(positions.length / 3);
    scene.addPositions(0, positions);
    frameOn(positions);
    const vertices = positions.length / 3;
    fillColours(scene.colours, vertices, 'plain');
    scene.coloursChanged(vertices);
    scene.showTriangles(triangles, view.edges ? triangleEdges(triangles) : null);
    state.trianglesDrawn = triangles.length / 3;
    state.shown = 'surface';
    state.status = 'done';
  } catch (e) {
    state.status = 'error';
    state.error = String(e.message || e);
  }
  updateOverlay();
  publish();
}

if (params.get('ui') === '0') document.body.classList.add('bare');
syncControls();
if (params.get('stream') && !params.get('surface')) {
  start(params.get('stream').split('/').pop(), { url: params.get('stream') });
} else {
  ensureScene();
  if (params.get('surface')) showSurface(params.get('surface'));
  else updateOverlay();
}
