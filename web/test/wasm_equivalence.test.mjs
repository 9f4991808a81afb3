// The WebAssembly decoder gives the same levels as the native one: for every
// level of every golden and corpus stream, the same vertices in the same
// order, the same carved cells, surface, boundary flags and values (hashes
// of each, web/level_summary.cpp), fed in the same chunks; and truncated or
// damaged copies end the same way, with the same message.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { DecoderSession } from '../page/decoder_session.js';
import { loadDecoder, webTestConfig } from './load_decoder.mjs';
import { allStreams, brokenCopies, nativeSummary } from './streams.mjs';

const config = webTestConfig();
const decoder = await loadDecoder(config.dist);

function wasmSummary(path, chunk) {
  const bytes = readFileSync(path);
  const session = new DecoderSession(decoder, { summaries: true, maxVertices: 30e6 });
  const lines = [];
  try {
    for (let at = 0; at < bytes.length; at += chunk) {
      const { levels, error } = session.feed(bytes.subarray(at, at + chunk));
      for (const level of levels) lines.push(JSON.parse(level.summary));
      if (error) break;
    }
    lines.push(JSON.parse(session.endSummary()));
  } finally {
    session.dispose();
  }
  return lines;
}

const streams = allStreams(config);
test('there are golden and corpus streams to compare', () => {
  assert.ok(streams.filter((s) => s.name.startsWith('corpus/')).length >= 7, 'corpus streams missing');
  assert.ok(streams.length >= 20);
});

for (const stream of streams) {
  test(`same levels natively and in WebAssembly: ${stream.name}`, () => {
    for (const chunk of [997, 1 << 20]) {
      const native = nativeSummary(config, stream.path, chunk);
      assert.equal(native.at(-1).end, 'done', `native: ${native.at(-1).message}`);
      assert.deepEqual(wasmSummary(stream.path, chunk), native, `chunks of ${chunk} bytes`);
    }
  });
}

for (const stream of streams.filter((s) => /corpus\/(bunny|ct_torus)|^golden\/torus_288.dtm/.test(s.name))) {
  const native = nativeSummary(config, stream.path);
  for (const copy of brokenCopies(stream, native, join(config.artifacts, 'broken'))) {
    test(`same end natively and in WebAssembly: ${copy.name}`, () => {
      const expected = nativeSummary(config, copy.path, 997);
      assert.equal(expected.at(-1).end, copy.kind === 'truncated' ? 'truncated' : 'error');
      assert.deepEqual(wasmSummary(copy.path, 997), expected);
    });
  }
}
