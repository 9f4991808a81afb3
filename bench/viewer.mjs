// The viewer's figures (bench/viewer.sh runs this): WebAssembly decoding
// against native on one stream, in node and in chromium; time to the first
// picture on a throttled stream against waiting for the whole file; the
// page's download size. Writes a Markdown report.
//
//   node bench/viewer.mjs STREAM.dtm OUT.md   (environment as web/test/tests.cmake sets it)
import { execFileSync } from 'node:child_process';
import { readdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { basename, join } from 'node:path';
import { gzipSync } from 'node:zlib';
import { DecoderSession } from '../web/page/decoder_session.js';
import { launchBrowser, openPage, serve, waitForEnd } from '../web/test/browser.mjs';
import { loadDecoder, webTestConfig } from '../web/test/load_decoder.mjs';

const [streamPath, outPath] = process.argv.slice(2);
const config = webTestConfig();
const bytes = readFileSync(streamPath);
const runs = Number(process.env.DTM_BENCH_RUNS || 5);
const decoder = await loadDecoder(config.dist);
const log = (...a) => console.error('viewer bench:', ...a);

function nativeSeconds(mode) {
  return JSON.parse(execFileSync(config.levelSummary, [streamPath, mode, '1'], { encoding: 'utf8' })).seconds;
}

function wasmFinestSeconds() {
  const at = decoder._malloc(bytes.length);
  decoder.HEAPU8.set(bytes, at);
  const start = performance.now();
  const tetrahedra = decoder._dtm_decode_finest(at, bytes.length);
  const seconds = (performance.now() - start) / 1000;
  decoder._free(at);
  if (tetrahedra < 0) throw new Error('the WebAssembly decoder failed');
  return seconds;
}

function wasmLevelsSeconds() {
  const start = performance.now();
  const session = new DecoderSession(decoder);
  const { error } = session.feed(bytes);
  session.dispose();
  if (error) throw new Error(error);
  return (performance.now() - start) / 1000;
}

// Best of `runs`, native and WebAssembly taken in turns, so that both see the
// same machine.
function bestInTurns(pairs) {
  const best = pairs.map(() => Infinity);
  for (let r = 0; r < runs; ++r) pairs.forEach((f, i) => { best[i] = Math.min(best[i], f()); });
  return best;
}

log(`decoding ${basename(streamPath)} ${runs} times each way`);
const [nativeFinest, wasmFinest, nativeLevels, wasmLevels] = bestInTurns([
  () => nativeSeconds('--time-finest'), wasmFinestSeconds, () => nativeSeconds('--time-levels'), wasmLevelsSeconds]);

const browser = await launchBrowser();
const browserVersion = browser.version();

// The same decode to the finest mesh inside chromium's page (its main thread).
async function chromiumFinestSeconds() {
  const server = await serve(config, streamPath);
  const page = await openPage(browser);
  try {
    await page.goto(`${server.url}index.html?ui=0`);
    return await page.evaluate(async (runs) => {
      const { default: create } = await import('./dtm_decoder.mjs');
      const m = await create();
      const data = new Uint8Array(await (await fetch('stream.dtm')).arrayBuffer());
      const at = m._malloc(data.length);
      m.HEAPU8.set(data, at);
      let best = Infinity;
      for (let r = 0; r < runs; ++r) {
        const start = performance.now();
        if (m._dtm_decode_finest(at, data.length) < 0) throw new Error('decode failed');
        best = Math.min(best, (performance.now() - start) / 1000);
      }
      return best;
    }, runs);
  } finally {
    await page.close();
    server.close();
  }
}
log('decoding in chromium');
const chromiumFinest = await chromiumFinestSeconds();

// Loads the page on a throttled stream; times since navigation, in ms.
async function throttled(rate, throttleAll) {
  const server = await serve(config, streamPath, rate, throttleAll ? ['--throttle-all'] : []);
  const page = await openPage(browser);
  try {
    await page.goto(`${server.url}?stream=stream.dtm`);
    const state = await waitForEnd(page, 600_000);
    if (state.status !== 'done') throw new Error(`${rate}: ${state.status}: ${state.error}`);
    return { rate, throttleAll, levels: state.levels.length, ...state.timings };
  } finally {
    await page.close();
    server.close();
  }
}
const median = (xs) => [...xs].sort((x, y) => x - y)[Math.floor(xs.length / 2)];
log('a first load, to warm the browser up');
await throttled('1MB/s', false);
const loads = [];
for (const [rate, all] of [['1MB/s', false], ['100KB/s', false], ['1MB/s', true]]) {
  log(`loading the page 3 times at ${rate}${all ? ', page files throttled too' : ''}`);
  const tries = [];
  for (let i = 0; i < 3; ++i) tries.push(await throttled(rate, all));
  const finest = (t) => t.decoded[0], coarsest = (t) => t.decoded[Math.max(...Object.keys(t.decoded).map(Number))];
  const pick = (f) => median(tries.map(f));
  loads.push({
    rate, throttleAll: all, renderer: pick((t) => t.renderer), firstDecoded: pick(coarsest),
    firstPicture: pick((t) => t.firstPicture), lastByte: pick((t) => t.lastByte), finestDecoded: pick(finest),
    finestDrawn: pick((t) => t.drawn[0]),
  });
}
await browser.close();

const files = readdirSync(config.dist).filter((f) => statSync(join(config.dist, f)).isFile() && !f.endsWith('.log'));
const sizes = files.map((f) => {
  const data = readFileSync(join(config.dist, f));
  return { f, raw: data.length, gzip: gzipSync(data, { level: 9 }).length };
});
const total = sizes.reduce((a, s) => ({ raw: a.raw + s.raw, gzip: a.gzip + s.gzip }), { raw: 0, gzip: 0 });

const ms = (x) => `${Math.round(x)}`;
const kb = (x) => (x / 1000).toFixed(1);
const report = `# The viewer: WebAssembly decoding, time to the first picture, download size

Made by \`bench/viewer.sh build\` on ${new Date().toISOString().slice(0, 10)} (2 cores, shared machine; Debian's
emscripten 3.1.6, node ${process.version}, chromium ${browserVersion}), on
\`${basename(streamPath)}\` (${bytes.length.toLocaleString('en-US')} bytes). Ratios are measured in one run,
best of ${runs}, native and WebAssembly in turns.

## Decoding: WebAssembly against native

| what | native (s) | WebAssembly in node (s) | ratio | WebAssembly in chromium (s) | ratio |
|---|---:|---:|---:|---:|---:|
| to the finest mesh (one batch, as meshdec) | ${nativeFinest.toFixed(3)} | ${wasmFinest.toFixed(3)} | **${(wasmFinest / nativeFinest).toFixed(2)}x** | ${chromiumFinest.toFixed(3)} | **${(chromiumFinest / nativeFinest).toFixed(2)}x** |
| every level's view, as the page makes them | ${nativeLevels.toFixed(3)} | ${wasmLevels.toFixed(3)} | ${(wasmLevels / nativeLevels).toFixed(2)}x | - | - |

Target: at most 2.5x native to the finest level.

## Time to the first picture

Milliseconds from navigation, the median of 3 loads (after one to warm the
browser up): the renderer made (a WebGL context and its shaders, on the
page's thread), the coarsest level decoded (in the worker), on the screen;
the whole stream received (the fetch's resource timing); the finest level
decoded, on the screen. scripts/serve.py throttles the stream; "throttled
too" throttles the page's files as well, each request at that rate, as on a
first visit; otherwise they come at full speed, as from a cache. Chromium
draws with SwiftShader, on the CPU, here.

| rate | page files | renderer made | coarsest level decoded | first picture | whole stream received | finest level decoded | finest level drawn |
|---|---|---:|---:|---:|---:|---:|---:|
${loads.map((l) => `| ${l.rate} | ${l.throttleAll ? 'throttled too' : 'full speed'} | ${ms(l.renderer)} | ${ms(l.firstDecoded)} | **${ms(l.firstPicture)}** | **${ms(l.lastByte)}** | ${ms(l.finestDecoded)} | ${ms(l.finestDrawn)} |`).join('\n')}

## The page's download size

| file | bytes | gzip -9 |
|---|---:|---:|
${sizes.map((s) => `| ${s.f} | ${s.raw.toLocaleString('en-US')} | ${s.gzip.toLocaleString('en-US')} |`).join('\n')}
| **total** | **${total.raw.toLocaleString('en-US')}** (${kb(total.raw)} KB) | **${total.gzip.toLocaleString('en-US')}** (${kb(total.gzip)} KB) |
`;
writeFileSync(outPath, report);
console.log(report);
