// A small OFF reader, for showing an input's own surface beside a decoded
// level (?surface=URL; the README's pictures). Triangulates polygons as fans.
export function parseOff(text) {
  const words = text.replace(/#[^\n]*/g, ' ').trim().split(/\s+/);
  let at = 0;
  const header = words[at++];
  if (!/^C?N?OFF$/.test(header)) throw new Error('not an OFF file');
  const vertexCount = Number(words[at++]), faceCount = Number(words[at++]);
  at++;  // edges
  if (!(vertexCount >= 0 && faceCount >= 0)) throw new Error('bad OFF counts');
  const positions = new Float32Array(3 * vertexCount);
  for (let i = 0; i < 3 * vertexCount; ++i) positions[i] = Number(words[at + Math.floor(i / 3) * 3 + (i % 3)]);
  at += 3 * vertexCount;
  const triangles = [];
  for (let f = 0; f < faceCount; ++f) {
    const n = Number(words[at++]);
    const face = words.slice(at, at + n).map(Number);
    at += n;
    for (let k = 1; k + 1 < n; ++k) triangles.push(face[0], face[k], face[k + 1]);
  }
  if (positions.some((x) => !Number.isFinite(x))) throw new Error('bad OFF coordinates');
  return { positions, triangles: new Uint32Array(triangles) };
}
