// Per-vertex colours for the three colour modes: the vertex's level, the
// level's boundary flag, or a value field on a colour ramp.

// A categorical palette, coarsest level first (Okabe and Ito's, safe for
// colour-blind eyes), repeated past eight levels.
const kLevelPalette = [
  [0.90, 0.62, 0.00], [0.34, 0.71, 0.91], [0.00, 0.62, 0.45], [0.94, 0.89, 0.26],
  [0.00, 0.45, 0.70], [0.84, 0.37, 0.00], [0.80, 0.47, 0.65], [0.60, 0.60, 0.60],
];
export const kPlain = [0.87, 0.80, 0.68];
const kBoundary = [0.84, 0.37, 0.00];
const kInterior = [0.34, 0.71, 0.91];

// Viridis at nine stops, linearly interpolated.
const kRamp = [
  [0.267, 0.005, 0.329], [0.283, 0.141, 0.458], [0.254, 0.265, 0.530], [0.207, 0.372, 0.553],
  [0.164, 0.471, 0.558], [0.128, 0.567, 0.551], [0.135, 0.659, 0.518], [0.478, 0.821, 0.318],
  [0.993, 0.906, 0.144],
];

export function rampColour(t) {
  const x = Math.min(1, Math.max(0, t)) * (kRamp.length - 1);
  const i = Math.min(kRamp.length - 2, Math.floor(x)), f = x - i;
  return [0, 1, 2].map((k) => kRamp[i][k] + f * (kRamp[i + 1][k] - kRamp[i][k]));
}

export const kRampCss = `linear-gradient(to right, ${kRamp
  .map((c) => `rgb(${c.map((v) => Math.round(255 * v)).join(',')})`)
  .join(', ')})`;

export function levelColour(level, coarsest) {
  return kLevelPalette[(coarsest - level) % kLevelPalette.length];
}

// Writes the colours of vertices [0, count) into `out` (3 floats each).
//   mode 'plain'    one colour
//   mode 'level'    vertexLevels[v] (the coarsest level holding v)
//   mode 'boundary' flags[v] (the shown level's boundary vertices)
//   mode 'field'    values (components per vertex; a vector's length),
//                   mapped from [range.min, range.max] onto the ramp
export function fillColours(out, count, mode, { vertexLevels, coarsest, flags, values, components, range } = {}) {
  for (let v = 0; v < count; ++v) {
    let c = kPlain;
    if (mode === 'level') c = levelColour(vertexLevels[v], coarsest);
    else if (mode === 'boundary') c = flags[v] ? kBoundary : kInterior;
    else if (mode === 'field') {
      const x = fieldMagnitude(values, components, v);
      c = Number.isFinite(x) ? rampColour((x - range.min) / (range.max - range.min || 1)) : [0.5, 0.5, 0.5];
    }
    out[3 * v] = c[0], out[3 * v + 1] = c[1], out[3 * v + 2] = c[2];
  }
}

// A scalar's value, or a vector's length.
export function fieldMagnitude(values, components, v) {
  if (components === 1) return values[v];
  let sum = 0;
  for (let k = 0; k < components; ++k) sum += values[components * v + k] ** 2;
  return Math.sqrt(sum);
}

export function fieldRange(values, components, count) {
  let min = Infinity, max = -Infinity;
  for (let v = 0; v < count; ++v) {
    const x = fieldMagnitude(values, components, v);
    if (Number.isFinite(x)) min = Math.min(min, x), max = Math.max(max, x);
  }
  return min <= max ? { min, max } : { min: 0, max: 1 };
}
