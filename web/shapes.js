// Obstacle shapes as plain objects of the JS contract: move (the library's),
// scale and rotate about the reference point (the library's), and a new
// shape of each palette type sized for the arm.

/** The obstacle types the panel offers, in the order of the keys 1 … 0. */
export const PALETTE = ['point', 'segment', 'sphere', 'capsule', 'plane', 'rectangle', 'disk', 'polygon', 'box', 'human'];

export const add = (a, b) => a.map((x, k) => x + b[k]);
export const sub = (a, b) => a.map((x, k) => x - b[k]);
export const mul = (a, s) => a.map((x) => x * s);
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const len = (a) => Math.hypot(...a);
export const isPoint = (p) => Array.isArray(p) && p.length === 3 && p.every((x) => typeof x === 'number');

/** Applies `f` to every point of a shape (recursing into composite parts). */
function mapPoints(shape, f) {
  const out = { ...shape };
  for (const key of ['p', 'a', 'b', 'center', 'position']) if (isPoint(out[key])) out[key] = f(out[key]);
  for (const key of ['vertices', 'points']) if (Array.isArray(out[key])) out[key] = out[key].map((p) => (isPoint(p) ? f(p) : p));
  if (Array.isArray(out.parts)) out.parts = out.parts.map((part) => mapPoints(part, f));
  return out;
}

/**
 * The library (the wasm module) that defines where a figure is and how it
 * moves (`referencePoint`, `translateShape`); the page sets it once loaded.
 */
let library = null;

/** Hands the loaded wasm module to the shape helpers. */
export function useLibrary(wasm) {
  library = wasm;
}

function lib() {
  if (!library) throw new Error('the library is not loaded yet');
  return library;
}

/** The shape moved by `delta` (m), as the library moves obstacles. */
/** A human with its `side` hand moved by `delta` from rest: only that arm changes (the library's two-link solution). */
export function moveHumanHand(shape, side, delta) {
  return lib().moveHumanHand(shape, side, delta);
}

/** A recorded keypoint track (JSON or CSV text) as `{ shape, report }`: a human replaying it. */
export function importTrack(text, options) {
  return lib().importTrack(text, options);
}

/** The motions of the human library (docs/scenarios.md). */
export const HUMAN_MOTIONS = ['reach', 'wave', 'walk', 'bend', 'stepBack'];

export function translateShape(shape, delta) {
  return lib().translateShape(shape, delta);
}

/**
 * The figure's reference point (the library's: the centre, the middle of a
 * segment, a plane's point closest to the origin, a human's floor point).
 */
export function shapeCenter(shape) {
  return lib().referencePoint(shape);
}

/** The shape scaled by `s` about its centre. */
export function scaleShape(shape, s) {
  const c = shapeCenter(shape);
  const out = mapPoints(shape, (p) => add(c, mul(sub(p, c), s)));
  for (const key of ['radius', 'height', 'scale']) {
    if (typeof out[key] === 'number') out[key] *= s;
    else if (Array.isArray(out[key])) out[key] = out[key].map((r) => r * s);
  }
  if (Array.isArray(out.halfExtents)) out.halfExtents = out.halfExtents.map((r) => r * s);
  if (Array.isArray(out.parts)) out.parts = out.parts.map((p) => ({ ...p, ...(typeof p.radius === 'number' ? { radius: p.radius * s } : {}) }));
  return out;
}

function rotate(v, axis, angle) {
  const [x, y, z] = axis;
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  const d = dot(axis, v);
  return [
    v[0] * c + (y * v[2] - z * v[1]) * s + x * d * (1 - c),
    v[1] * c + (z * v[0] - x * v[2]) * s + y * d * (1 - c),
    v[2] * c + (x * v[1] - y * v[0]) * s + z * d * (1 - c),
  ];
}

function quatMul(a, b) {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = b;
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}

/** The shape rotated by `angle` (rad) about the world `axis` through its centre. */
export function rotateShape(shape, axis, angle) {
  const c = shapeCenter(shape);
  const out = mapPoints(shape, (p) => add(c, rotate(sub(p, c), axis, angle)));
  if (isPoint(shape.normal)) out.normal = rotate(shape.normal, axis, angle);
  if (shape.type === 'plane') out.offset = -dot(out.normal, c);
  if (Array.isArray(shape.axes)) out.axes = shape.axes.map((a) => rotate(a, axis, angle));
  if (shape.type === 'human' && Math.abs(axis[2]) > 0.99) out.heading = (shape.heading ?? 0) + Math.sign(axis[2]) * angle;
  if (shape.type === 'box') {
    const q = [...mul(axis, Math.sin(angle / 2)), Math.cos(angle / 2)];
    out.rotation = quatMul(q, shape.rotation ?? [0, 0, 0, 1]);
  }
  return out;
}

/** A new shape of `type` around `c` (m), sized for an arm of reach `r` (m). */
export function defaultShape(type, c, r) {
  const s = Math.max(0.04, 0.12 * r);
  switch (type) {
    case 'point': return { type, p: c };
    case 'segment': return { type, a: add(c, [0, -s, 0]), b: add(c, [0, s, 0]) };
    case 'sphere': return { type, center: c, radius: 0.6 * s };
    case 'capsule': return { type, a: add(c, [0, -s, 0]), b: add(c, [0, s, 0]), radius: 0.4 * s };
    case 'plane': { const n = [-1, 0, 0]; return { type, normal: n, offset: -dot(n, c) }; }
    case 'rectangle': return { type, center: c, axes: [[1, 0, 0], [0, 1, 0]], halfExtents: [s, 0.6 * s] };
    case 'disk': return { type, center: c, normal: [0, 0, 1], radius: 0.8 * s };
    case 'polygon': return { type, vertices: [0, 1, 2, 3, 4].map((k) => add(c, [s * Math.cos(k * 1.2566), s * Math.sin(k * 1.2566), 0])) };
    case 'box': return { type, center: c, halfExtents: [0.6 * s, 0.8 * s, 0.5 * s], rotation: [0, 0, 0, 1] };
    case 'human': return { type, position: [c[0], c[1], 0], heading: Math.atan2(-c[1], -c[0]), height: 1.75 };
    default: throw new Error(`unknown obstacle type ${type}`);
  }
}
