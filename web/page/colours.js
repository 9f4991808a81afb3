// Per-vertex colours for the three colour modes: the vertex's level, the
// level's boundary flag, or a value field on a colour ramp; and a colour per
// region (material), which the page gives each cell.

export const kPlain = [0.85, 0.74, 0.58];
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

// Levels on the ramp: the coarsest dark, level 0 (the finest) bright, so that
// a region's colour says how late its vertices arrive.
export function levelColour(level, coarsest) {
  return rampColour(coarsest > 0 ? (coarsest - level) / coarsest : 1);
}

// sRGB to linear: three.js takes vertex colours as linear light.
const kToLinear = (c) => c.map((x) => (x <= 0.04045 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4));

// Regions' colours: Okabe and Ito's eight, told apart by most eyes, the
// background's grey left out; past them, hues a golden angle apart.
const kRegionColours = [
  [0.902, 0.624, 0.000], [0.337, 0.706, 0.914], [0.000, 0.620, 0.451], [0.941, 0.894, 0.259],
  [0.000, 0.447, 0.698], [0.835, 0.369, 0.000], [0.800, 0.475, 0.655],
];

// The colour of region index r (0 the stream's first region), sRGB.
export function regionColour(r) {
  if (r < kRegionColours.length) return kRegionColours[r];
  const hue = ((r - kRegionColours.length) * 137.508 + 20) % 360;
  return hslToRgb(hue, 0.6, 0.5 + 0.1 * (r % 3 - 1));
}

export function regionCss(r) {
  return `rgb(${regionColour(r).map((v) => Math.round(255 * v)).join(',')})`;
}

function hslToRgb(h, s, l) {
  const a = s * Math.min(l, 1 - l);
  const f = (n) => {
    const k = (n + h / 30) % 12;
    return l - a * Math.max(-1, Math.min(k - 3, 9 - k, 1));
  };
  return [f(0), f(8), f(4)];
}

// Per item (a triangle or a cell), the linear colour of its region, from
// `regions` (1 + the region's index, as the decoder gives it; 0 none):
// 3 floats each.
export function regionColours(regions) {
  const table = [kToLinear([0.6, 0.6, 0.6])];
  const out = new Float32Array(3 * regions.length);
  for (let i = 0; i < regions.length; ++i) {
    const r = regions[i];
    while (table.length <= r) table.push(kToLinear(regionColour(table.length - 1)));
    out[3 * i] = table[r][0], out[3 * i + 1] = table[r][1], out[3 * i + 2] = table[r][2];
  }
  return out;
}

// Writes the colours of vertices [0, count) into `out` (3 floats each, linear).
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
    c = kToLinear(c);
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
