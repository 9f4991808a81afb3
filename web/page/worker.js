// The viewer's decoding thread: reads a .dtm from a URL (a streaming fetch)
// or a dropped File, feeds every chunk to the WebAssembly decoder as it
// arrives, and posts each level as soon as it is whole, its arrays
// transferred, never copied. The page's thread only draws.
//
// Messages out: {type: 'header'}, {type: 'level'}, {type: 'progress'} after
// every chunk, and one {type: 'end', status: 'done' | 'truncated' | 'error'}.
import createDtmDecoder from './dtm_decoder.mjs';
import { DecoderSession } from './decoder_session.js';

const decoderModule = createDtmDecoder();

self.onmessage = async (event) => {
  const { url, file, maxVertices } = event.data;
  let session = null;
  const started = performance.now();
  try {
    session = new DecoderSession(await decoderModule, { maxVertices });
    const { reader, total } = await openStream(url, file);
    post({ type: 'progress', received: 0, total });
    let headerSent = false;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      const { levels, error } = session.feed(value);
      if (!headerSent && session.header) {
        post({ type: 'header', header: session.header });
        headerSent = true;
      }
      for (const level of levels) postLevel(level, session);
      post({ type: 'progress', received: session.bytesFed, total });
      if (error) {
        reader.cancel().catch(() => {});
        return end({ status: 'error', message: error }, session, started);
      }
    }
    end(session.finish(), session, started);
  } catch (e) {
    // A failed fetch, a network error mid-stream, a trap in the decoder.
    post({ type: 'end', status: 'error', message: String(e && e.message ? e.message : e),
           received: session ? session.bytesFed : 0, seconds: (performance.now() - started) / 1000 });
  } finally {
    if (session) session.dispose();
  }
};

async function openStream(url, file) {
  if (file) return { reader: file.stream().getReader(), total: file.size };
  const response = await fetch(url, { cache: 'no-store' });
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status} ${response.statusText}`);
  if (!response.body) throw new Error(`${url}: the response has no body`);
  const length = Number(response.headers.get('Content-Length'));
  return { reader: response.body.getReader(), total: Number.isFinite(length) && length > 0 ? length : null };
}

function postLevel(level, session) {
  level.type = 'level';
  level.fields = session.fields;
  level.received = session.bytesFed;
  const buffers = [level.cells, level.neighbors, level.surface, level.boundary, level.positions, ...level.values]
    .map((a) => a.buffer);
  self.postMessage(level, buffers);
}

function end({ status, message }, session, started) {
  post({ type: 'end', status, message, received: session.bytesFed, seconds: (performance.now() - started) / 1000 });
}

function post(message) {
  self.postMessage(message);
}
