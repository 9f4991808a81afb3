// The streams the web tests decode, and the damaged and truncated copies
// they make of them, with what the native decoder says of each.
import { execFileSync } from 'node:child_process';
import { mkdirSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import { basename, join } from 'node:path';

// Every golden stream (tests/golden, all format versions) and every corpus
// stream web/test/make_streams.sh made.
export function allStreams(config) {
  const golden = join(config.source, 'tests', 'golden');
  const out = [];
  const older = ['v2', 'v3', 'v4', 'v5', 'v6', 'v14', 'v20', 'v21', 'v22'];
  for (const dir of [golden, ...older.map((v) => join(golden, v))])
    for (const name of readdirSync(dir).sort())
      if (name.endsWith('.dtm')) out.push({ name: `${basename(dir)}/${name}`, path: join(dir, name) });
  for (const name of readdirSync(config.streams).sort())
    if (name.endsWith('.dtm')) out.push({ name: `corpus/${name}`, path: join(config.streams, name) });
  return out;
}

// The native decoder's lines for a stream (web/level_summary.cpp): one JSON
// object per level, then {end, message}.
export function nativeSummary(config, path, chunk = 65536) {
  return execFileSync(config.levelSummary, [path, '--chunk', String(chunk)], { encoding: 'utf8' })
    .trim().split('\n').map((line) => JSON.parse(line));
}

// Copies of `stream` that end early or carry one flipped bit, written to
// `dir`: cut in the middle of its last layer, of a middle layer and of the
// header; a bit flipped in the middle of a middle layer and of the last one.
// `levels` are the native summaries (their stream_bytes give the layers).
export function brokenCopies(stream, levels, dir) {
  mkdirSync(dir, { recursive: true });
  const bytes = readFileSync(stream.path);
  const ends = levels.filter((l) => l.level !== undefined).map((l) => l.stream_bytes);
  const middle = Math.floor(ends.length / 2);
  const inside = (k) => Math.floor(((k ? ends[k - 1] : 0) + ends[k]) / 2);
  const copies = [
    { kind: 'truncated', what: 'inside the last layer', bytes: bytes.subarray(0, inside(ends.length - 1)) },
    { kind: 'truncated', what: 'inside a middle layer', bytes: bytes.subarray(0, inside(middle)) },
    { kind: 'truncated', what: 'inside the header', bytes: bytes.subarray(0, 10) },
  ];
  for (const k of [middle, ends.length - 1]) {
    const flipped = Uint8Array.from(bytes);
    flipped[inside(k)] ^= 0x10;
    copies.push({ kind: 'damaged', what: `a bit flipped in level ${levels[k].level}'s layer`, bytes: flipped,
                  wholeLevels: k });
  }
  return copies.map((c, i) => {
    const path = join(dir, `${basename(stream.path, '.dtm')}.${i}.${c.kind}.dtm`);
    writeFileSync(path, c.bytes);
    return { ...c, path, name: `${stream.name} (${c.kind}: ${c.what})` };
  });
}
