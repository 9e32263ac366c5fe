// `npm run soak`: millions of control steps of the `human-panda` example in
// one World, natively and in wasm, with no non-finite number and flat memory.
// Not part of `npm test` (it takes several minutes).
//
//   node scripts/soak.mjs [--native-steps N] [--wasm-steps N] [--only native|wasm]
//
// Native: `cargo run --release --example soak` (crate/examples/soak.rs), 10⁷
// steps by default, resident memory from /proc. Wasm: the Node build
// (crate/pkg-node), 10⁶ steps by default, the size of the module's
// `WebAssembly.Memory` buffer. Both loop the person's walk there and back so
// that the avoidance keeps working, and both fail (exit status 1) on a
// non-finite number or memory that grows in the second half of the run.
//
// A World keeps its event log up to 20 000 events by design (the native run
// reaches that cap after about 1.3 M steps; the wasm run would need about
// 2.4 M), so the wasm run restarts the scene with `reset()` every
// `--wasm-cycle` steps (default 250 000): each cycle must then end with the
// memory the first one needed.
import path from 'node:path';
import { createRequire } from 'node:module';
import { repo, run } from './lib.mjs';
import { buildWasm } from './build.mjs';

const option = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const nativeSteps = Number(option('--native-steps', 1e7));
const wasmSteps = Number(option('--wasm-steps', 1e6));
const wasmCycle = Number(option('--wasm-cycle', 250000));
const only = option('--only', null);

/** Where a non-finite number hides in `v`, or null. */
function nonFinite(v, where = 'state') {
  if (typeof v === 'number') return Number.isFinite(v) ? null : `${where} = ${v}`;
  if (v && typeof v === 'object') {
    for (const [k, x] of Object.entries(v)) {
      const bad = nonFinite(x, Array.isArray(v) ? `${where}[${k}]` : `${where}.${k}`);
      if (bad) return bad;
    }
  }
  return null;
}

/** Loads crate/pkg-node and returns it with the module's memory. */
function loadWasm() {
  let memory = null;
  const Instance = WebAssembly.Instance;
  // The generated loader keeps its instance private: catch its memory here.
  WebAssembly.Instance = function (module, imports) {
    const instance = new Instance(module, imports);
    memory ??= instance.exports.memory;
    return instance;
  };
  try {
    const require = createRequire(import.meta.url);
    const sa = require(path.join(repo, 'crate', 'pkg-node', 'skeleton_avoidance.js'));
    return { sa, memory };
  } finally {
    WebAssembly.Instance = Instance;
  }
}

function soakWasm(steps) {
  const { sa, memory } = loadWasm();
  if (!memory) throw new Error('soak: the wasm module exports no memory');
  const s = sa.exampleScenario('human-panda');
  const person = s.obstacles.find((o) => o.id === 'person');
  const { points, times } = person.motion;
  const [t0, t1] = [times[0], times.at(-1)];
  person.motion = { type: 'waypoints', points: [points[0], points.at(-1), points[0]], times: [t0, t1, 2 * t1 - t0], loop: true };
  const world = new sa.World(s);
  console.log(`soak (wasm): human-panda, person walking to and fro, ${steps} steps of ${s.dt} s, reset every ${wasmCycle}`);

  const perCall = 1000;
  const calls = Math.ceil(steps / perCall);
  const tenth = Math.max(1, Math.round(calls / 10));
  const marks = [{ step: 0, bytes: memory.buffer.byteLength, heap: process.memoryUsage().heapUsed, t: 0 }];
  const t0ms = performance.now();
  let cursor = 0;
  let done = 0;
  let events = 0;
  for (let c = 1; c <= calls; c++) {
    const n = Math.min(perCall, steps - done);
    world.advance(s.dt, n);
    done += n;
    if (done % wasmCycle === 0) {
      events += world.eventCount;
      world.reset();
      cursor = 0;
    }
    const state = world.state(cursor);
    cursor = world.eventCount;
    const bad = nonFinite(state);
    if (bad) throw new Error(`soak (wasm): step ${done} (t = ${state.t} s): ${bad}`);
    if (c % tenth === 0 || c === calls) {
      marks.push({ step: done, bytes: memory.buffer.byteLength, heap: process.memoryUsage().heapUsed, t: (performance.now() - t0ms) / 1000 });
    }
  }
  const secs = (performance.now() - t0ms) / 1000;
  console.log(`${'step'.padStart(12)}  ${'wasm memory (bytes)'.padStart(20)}  ${'JS heap (MB)'.padStart(12)}  ${'time (s)'.padStart(9)}`);
  for (const m of marks) {
    console.log(`${String(m.step).padStart(12)}  ${String(m.bytes).padStart(20)}  ${(m.heap / 1e6).toFixed(1).padStart(12)}  ${m.t.toFixed(1).padStart(9)}`);
  }
  events += world.eventCount;
  world.free();
  const [start, middle, end] = [marks[0], marks[Math.floor(marks.length / 2)], marks.at(-1)];
  console.log(
    `soak (wasm): ${steps} steps in ${secs.toFixed(1)} s (${Math.round(steps / secs)} steps/s), simulated ` +
      `${(steps * s.dt).toFixed(0)} s, ${events} events, no non-finite number`,
  );
  console.log(`soak (wasm): WebAssembly.Memory start ${start.bytes} B, middle ${middle.bytes} B, end ${end.bytes} B`);
  if (end.bytes > middle.bytes) throw new Error(`soak (wasm): the wasm memory grew by ${end.bytes - middle.bytes} B in the second half`);
}

let failed = false;
if (only !== 'wasm') {
  const status = run('cargo', ['run', '--release', '--example', 'soak', '--', String(nativeSteps)]);
  if (status !== 0) {
    console.error('soak (native): FAILED');
    failed = true;
  }
}
if (only !== 'native') {
  if (buildWasm('node') !== 0) process.exit(1);
  try {
    soakWasm(wasmSteps);
  } catch (e) {
    console.error(e.message);
    failed = true;
  }
}
process.exit(failed ? 1 : 0);
