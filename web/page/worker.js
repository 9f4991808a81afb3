// The viewer's decoding thread: reads a .dtm from a URL (a streaming fetch)
// or a dropped File, feeds every chunk to the WebAssembly decoder as it
// arrives, and posts each level as soon as it is whole, its arrays
// transferred, never copied. The page's thread only draws, and nothing it
// does (making a WebGL context, building a large level's geometry) holds up
// the reading or the decoding.
//
// In:  one {url | file, maxVertices}.
// Out: {type: 'started'} at once, {type: 'header'},
//      {type: 'level'} per level, {type: 'progress', received, decoded}, and
//      one {type: 'end', status: 'done' | 'truncated' | 'error'}.
import createDtmDecoder from './dtm_decoder.mjs';
import { DecoderSession } from './decoder_session.js';

// Chunks are decoded in slices of at most this many bytes, so that a level
// is posted as soon as it is decoded, not after a large chunk's later levels.
const kSlice = 32768;

// The page makes its renderer once this thread runs (it needs the page's
// thread to start), while the decoder's module compiles here.
self.postMessage({ type: 'started' });
const decoderModule = createDtmDecoder();

self.onmessage = async (event) => {
  const { url, file, maxVertices } = event.data;
  let session = null, received = 0;
  try {
    // The first bytes travel while the decoder's module compiles.
    const [{ reader, total }, module] = await Promise.all([openStream(url, file), decoderModule]);
    session = new DecoderSession(module, { maxVertices });
    let headerSent = false;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      received += value.length;
      self.postMessage({ type: 'progress', received, decoded: session.bytesFed, total });
      for (let at = 0; at < value.length; at += kSlice) {
        const { levels, error } = session.feed(value.subarray(at, at + kSlice));
        if (!headerSent && session.header) {
          self.postMessage({ type: 'header', header: session.header });
          headerSent = true;
        }
        for (const level of levels) postLevel(level, session);
        if (error) {
          reader.cancel().catch(() => {});
          return end('error', error, session, received);
        }
      }
      self.postMessage({ type: 'progress', received, decoded: session.bytesFed, total });
    }
    const { status, message } = session.finish();
    // A task's turn, for the fetch's resource timing to be recorded.
    await new Promise((resolve) => setTimeout(resolve, 0));
    end(status, message, session, received, url);
  } catch (e) {
    // A failed fetch, a network error in the middle of the stream, no memory.
    end('error', String(e?.message ?? e), session, received);
  } finally {
    session?.dispose();
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
  level.regions = session.regions;
  level.decodedAt = performance.timeOrigin + performance.now();  // ms since 1970
  const buffers = [level.cells, level.neighbors, level.cellRegions, level.surface, level.surfaceRegions,
                   level.boundary, level.positions, ...level.values]
    .map((a) => a.buffer);
  self.postMessage(level, buffers);
}

// lastByteAt: when the network delivered the stream's last byte (ms since
// 1970, so that the page can put it on its own clock), from the fetch's
// resource timing: the reads above wait while a level is decoded.
function end(status, message, session, received, url) {
  const timing = url && performance.getEntriesByName(new URL(url, self.location.href).href).at(-1);
  const lastByteAt = timing && timing.responseEnd > 0 ? performance.timeOrigin + timing.responseEnd : null;
  self.postMessage({ type: 'end', status, message, received, decoded: session ? session.bytesFed : 0, lastByteAt });
}
