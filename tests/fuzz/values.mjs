// Hostile values for the boundary fuzz layer, drawn from a seeded generator.

/** mulberry32: a small seeded PRNG (deterministic runs). */
export function rng(seed) {
  let a = seed >>> 0;
  const next = () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
  const int = (n) => Math.floor(next() * n);
  const pick = (xs) => xs[int(xs.length)];
  return { next, int, pick, chance: (p) => next() < p };
}

const thrower = (msg) => () => {
  throw new Error(msg);
};

/** A Proxy whose every trap throws. */
const trapProxy = (target) =>
  new Proxy(target, {
    get: thrower('get trap'),
    has: thrower('has trap'),
    ownKeys: thrower('ownKeys trap'),
    getOwnPropertyDescriptor: thrower('descriptor trap'),
    getPrototypeOf: thrower('prototype trap'),
  });

const revoked = () => {
  const r = Proxy.revocable({}, {});
  r.revoke();
  return r.proxy;
};

const deep = (n) => {
  let v = [0];
  for (let k = 0; k < n; k++) v = [v];
  return v;
};

const cyclic = () => {
  const o = { type: 'point', p: [0, 0, 0] };
  o.self = o;
  return o;
};

// Built once: large values are costly to make.
const HUGE_ARRAY = new Array(200001).fill(0);
const MANY_SUBARRAYS = Array.from({ length: 1000001 }, () => [0]);
const HUGE_POLYGON = Array.from({ length: 5000 }, (_, k) => [Math.cos(k / 800), Math.sin(k / 800), 0]);
const LONG_STRING = 'x'.repeat((1 << 20) + 1);

/** Numbers that break naive code. */
export const NUMBERS = [
  0, -0, 1, -1, 0.5, 3, NaN, Infinity, -Infinity, 1e308, -1e308, 1e-308, 5e-324, 2 ** 31, 2 ** 32, 2 ** 32 + 1,
  2 ** 53, -(2 ** 31), 1e154, 1e155, 1e6, 1e6 + 1, 1e9 + 1, 1e200, 0.001, 0.1, 0.1000001,
];

/** Anything a caller could pass. `r` is an rng. */
export function hostile(r) {
  switch (r.int(30)) {
    case 0: return undefined;
    case 1: return null;
    case 2: return r.pick([true, false]);
    case 3: case 4: case 5: return r.pick(NUMBERS);
    case 6: return r.pick(['', '0.001', 'lwr4', 'planar3', 'human-panda', 'ball', '__proto__', 'constructor', 'x'.repeat(300)]);
    case 7: return r.pick([Symbol('s'), 10n, () => 1, new Date(0), new Map(), /x/]);
    case 8: return r.pick([[], [NaN], [0.001], [1, 2], [0, 0, 0], [1e308, 0, 0], ['0', '0', '0'], [[0, 0, 0]]]);
    case 9: return r.pick([HUGE_ARRAY, MANY_SUBARRAYS, LONG_STRING, deep(100), deep(63)]);
    case 10: return r.pick([new Float64Array([0, 0, 0]), new Float32Array(3), new Int32Array([1, 2, 3]), new Float64Array(7), new DataView(new ArrayBuffer(8))]);
    case 11: return { get p() { throw new Error('getter'); }, type: 'point' };
    case 12: return trapProxy({});
    case 13: return trapProxy([0, 0, 0]);
    case 14: return revoked();
    case 15: return cyclic();
    case 16: return JSON.parse('{"__proto__": {"type": "point"}, "type": "point", "p": [0, 0, 0]}');
    case 17: return Object.create(null);
    case 18: return Object.assign(Object.create({ type: 'point', p: [0, 0, 0] }), {});
    case 19: return { type: 'polygon', vertices: HUGE_POLYGON };
    case 20: return { type: 'box', center: [0, 0, 0], halfExtents: [1, 1, r.pick([1e200, 1e6, 1e-300, 1e5])] };
    case 21: return { type: 'segment', a: [-1e154, 0, 0], b: [1e154, 0, 0] };
    case 22: return { type: r.pick(['cone', 'sphere', 'box', 'human']), radius: r.pick(NUMBERS) };
    case 23: return { valueOf: thrower('valueOf'), toString: thrower('toString') };
    case 24: return new Proxy([0, 0, 0], { get: (t, k) => (k === 'length' ? 2 ** 32 - 1 : t[k]) });
    default: return {};
  }
}

/** A copy of `value` with one leaf (or key) replaced by something hostile. */
export function mutate(r, value) {
  if (value === null || typeof value !== 'object') return hostile(r);
  const copy = structuredClone(value);
  const paths = [];
  const walk = (v, path) => {
    if (path.length > 6) return;
    if (v && typeof v === 'object') {
      for (const k of Object.keys(v)) {
        paths.push([...path, k]);
        walk(v[k], [...path, k]);
      }
    }
  };
  walk(copy, []);
  if (paths.length === 0) return hostile(r);
  const path = r.pick(paths);
  let parent = copy;
  for (const k of path.slice(0, -1)) parent = parent[k];
  const key = path[path.length - 1];
  switch (r.int(6)) {
    case 0: // an unknown key beside it
      parent[r.pick(['colour', 'extra', '__proto__', 'Type'])] = 1;
      break;
    case 1: // a throwing getter in its place
      Object.defineProperty(parent, key, { get: thrower('getter'), enumerable: true });
      break;
    case 2: // a number in its place, maybe huge
      parent[key] = r.pick(NUMBERS);
      break;
    case 3: // removed
      delete parent[key];
      break;
    default:
      parent[key] = hostile(r);
  }
  return copy;
}
