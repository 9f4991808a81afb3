// Loads the WebAssembly decoder the page uses (build-wasm/dist/dtm_decoder.mjs)
// into node. Emscripten 3.1.6 writes its node branch for CommonJS: an ES
// module sees no `require` or `__dirname`, so they are provided, and the
// wasm bytes are handed over rather than looked up.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

export async function loadDecoder(dist) {
  globalThis.require ??= createRequire(import.meta.url);
  globalThis.__dirname ??= dist;
  const { default: createDtmDecoder } = await import(pathToFileURL(join(dist, 'dtm_decoder.mjs')).href);
  return createDtmDecoder({ wasmBinary: readFileSync(join(dist, 'dtm_decoder.wasm')) });
}

// Where the tests find what they need, from the environment ctest sets
// (web/test/tests.cmake).
export function webTestConfig() {
  const need = (name) => {
    const value = process.env[name];
    if (!value) throw new Error(`${name} is not set: run the web tests through ctest (web/test/tests.cmake)`);
    return value;
  };
  return {
    dist: need('DTM_WEB_DIST'),
    levelSummary: need('DTM_LEVEL_SUMMARY'),
    streams: need('DTM_WEB_STREAMS'),
    source: need('DTM_SOURCE_DIR'),
    artifacts: need('DTM_WEB_ARTIFACTS'),
    meshdec: process.env.DTM_MESHDEC,
    meshinfo: process.env.DTM_MESHINFO,
  };
}
