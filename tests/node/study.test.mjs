// Monte Carlo studies from JS, against crate/pkg-node: monteCarlo,
// monteCarloRuns in blocks merged by monteCarloMerge, bit-identity with the
// native library, and refusals that name the field.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

/** The `chattering` example shortened to 0.4 s (a noisy sphere between two
 * links), with the paper's repulsion, whose command follows the noise. */
function noisy(duration = 0.4) {
  const s = sa.exampleScenario('chattering');
  s.duration = duration;
  s.controller.avoidance = 'repulsion';
  return s;
}

// The report of the native library for this study (`monte-carlo --scenario
// chattering-0.4s.json --runs 6 --seed 2024 --rows`, built natively on every
// core; crate/tests/study_monte_carlo.rs pins the hash of the same report).
const NATIVE = {"runs": 6, "seed": 2024, "minClearance": {"min": 0.051624849957054006, "p01": 0.051625288636639226, "p05": 0.051627043354980105, "p50": 0.051644073113805616, "p95": 0.05164999957250365, "max": 0.05164999974223952, "mean": 0.051641103089826536, "outOfReach": 0}, "contactWhileMoving": {"count": 0, "p": 0.0, "low": 0.0, "high": 0.39033428790216534}, "stop": {"count": 6, "p": 1.0, "low": 0.6096657120978346, "high": 1.0}, "chattering": {"count": 6, "p": 1.0, "low": 0.6096657120978346, "high": 1.0}, "transitionTooSlow": {"count": 0, "p": 0.0, "low": 0.0, "high": 0.39033428790216534}, "switchesPerSecond": {"mean": 496.25, "max": 515.0}, "worstTransitionSlack": 90.5057940034923, "rows": [{"run": 0, "seed": 2024, "minClearance": 0.05164999645343185, "contactWhileMoving": false, "stopped": true, "chattering": true, "transitionTooSlow": false, "switches": 195, "switchesPerSecond": 487.5, "transitionSlack": null}, {"run": 1, "seed": 2024, "minClearance": 0.0516336235487584, "contactWhileMoving": false, "stopped": true, "chattering": true, "transitionTooSlow": false, "switches": 191, "switchesPerSecond": 477.5, "transitionSlack": 216.18284152112278}, {"run": 2, "seed": 2024, "minClearance": 0.05164999906329604, "contactWhileMoving": false, "stopped": true, "chattering": true, "transitionTooSlow": false, "switches": 199, "switchesPerSecond": 497.5, "transitionSlack": null}, {"run": 3, "seed": 2024, "minClearance": 0.05163814977417938, "contactWhileMoving": false, "stopped": true, "chattering": true, "transitionTooSlow": false, "switches": 206, "switchesPerSecond": 515.0, "transitionSlack": 200.53363400723322}, {"run": 4, "seed": 2024, "minClearance": 0.051624849957054006, "contactWhileMoving": false, "stopped": true, "chattering": true, "transitionTooSlow": false, "switches": 200, "switchesPerSecond": 500.0, "transitionSlack": 90.5057940034923}, {"run": 5, "seed": 2024, "minClearance": 0.05164999974223952, "contactWhileMoving": false, "stopped": true, "chattering": true, "transitionTooSlow": false, "switches": 200, "switchesPerSecond": 500.0, "transitionSlack": null}]};

test('monteCarlo gives, bit for bit, the native report', () => {
  const r = sa.monteCarlo(noisy(), { runs: 6, seed: 2024, rows: true });
  // strict deepEqual compares numbers with Object.is: the same bits
  assert.deepEqual(r, NATIVE);
  const q = r.minClearance;
  assert.ok(q.min <= q.p05 && q.p05 <= q.p50 && q.p50 <= q.p95 && q.p95 <= q.max);
  assert.equal(r.rows.length, 6);
  assert.equal(sa.monteCarlo(noisy(), { runs: 6, seed: 2024 }).rows, undefined);
});

test('blocks of runs merge into the report of the whole study, in any order', () => {
  const s = noisy();
  const blocks = [
    sa.monteCarloRuns(s, { seed: 2024, from: 4, count: 2 }),
    sa.monteCarloRuns(s, { seed: 2024, from: 0, count: 3 }),
    sa.monteCarloRuns(s, { seed: 2024, from: 3, count: 1 }),
  ];
  assert.deepEqual(blocks.map((b) => b.map((r) => r.run)), [[4, 5], [0, 1, 2], [3]]);
  const merged = sa.monteCarloMerge(blocks.flat(), { rows: true });
  assert.deepEqual(merged, NATIVE);
  const { rows: _rows, ...summary } = NATIVE;
  assert.deepEqual(sa.monteCarloMerge(blocks.flat()), summary);
  assert.throws(() => sa.monteCarloMerge(blocks[0]), /^Error: rows: run 0 is missing/);
  assert.throws(() => sa.monteCarloMerge([...blocks.flat(), blocks[2][0]]), /rows: run 3 appears twice/);
  const foreign = blocks.flat().map((r, k) => (k === 1 ? { ...r, seed: 7 } : r));
  assert.throws(() => sa.monteCarloMerge(foreign), /rows\[1\]\.seed: 7 differs/);
});

test('exact sensing gives one answer; another seed gives other runs', () => {
  const exact = noisy(0.2);
  exact.sensing = {};
  const r = sa.monteCarlo(exact, { runs: 4, seed: 3 });
  const q = r.minClearance;
  for (const v of [q.p01, q.p05, q.p50, q.p95, q.max, q.mean]) assert.equal(v, q.min);
  const a = sa.monteCarlo(noisy(), { runs: 6, seed: 1 });
  assert.notDeepEqual(a.minClearance, NATIVE.minClearance);
  assert.ok(a.minClearance.max - a.minClearance.min > 1e-6);
});

test('bad options and rows are refused with the field named', () => {
  const s = noisy(0.01);
  const cases = [
    [() => sa.monteCarlo(s, { runs: 0 }), /^Error: runs: must be in 1\.\.=10000/],
    [() => sa.monteCarlo(s, { runs: 10001 }), /^Error: runs: must be in 1\.\.=10000/],
    [() => sa.monteCarlo(s, { runs: 2.5 }), /^Error: runs: expected an integer/],
    [() => sa.monteCarlo(s, { runs: '2' }), /^Error: options\.runs: expected a number/],
    [() => sa.monteCarlo(s, { runs: 2, seed: NaN }), /^Error: options\.seed: not a finite number/],
    [() => sa.monteCarlo(s, { runs: 2, seed: -1 }), /^Error: seed: must be in 0\.\.=9007199254740991/],
    [() => sa.monteCarlo(s, { runs: 2, sed: 1 }), /^Error: options\.sed: unknown field/],
    [() => sa.monteCarlo(s), /^Error: options: missing/],
    [() => sa.monteCarlo(s, 3), /^Error: options: expected an object, got a number/],
    [() => sa.monteCarlo({ ...s, dt: -1 }, { runs: 1 }), /^Error: dt: must be > 0/],
    [() => sa.monteCarlo({ ...s, dt: 1e-6, duration: 2 }, { runs: 1 }), /^Error: duration: more than 1e6 steps/],
    [() => sa.monteCarloRuns(s, { count: 0 }), /^Error: count: must be in 1\.\.=10000/],
    [() => sa.monteCarloRuns(s, { count: 1, from: -2 }), /^Error: from: must be in 0/],
    [() => sa.monteCarloMerge('rows'), /^Error: rows: expected an array/],
    [() => sa.monteCarloMerge([]), /^Error: rows: no runs/],
    [() => sa.monteCarloMerge([{ run: 0 }]), /^Error: rows\[0\]\.seed: missing/],
    [() => sa.monteCarloMerge([], 4), /^Error: options: expected an object/],
  ];
  for (const [f, re] of cases) assert.throws(f, re);
});

test('a study draws each run\'s person from `vary`: reproducible with the seed, bad ranges refused naming the field', () => {
  const s = sa.exampleScenario('human-reach');
  s.duration = 1.6;
  s.obstacles[0].shape.vary = { height: [1.55, 1.95], speed: [0.8, 2.0] };
  const a = sa.monteCarlo(s, { runs: 6, seed: 5, rows: true });
  assert.deepEqual(sa.monteCarlo(s, { runs: 6, seed: 5, rows: true }), a);
  // The same report as the native library's (crate/tests/study_human.rs
  // pins its hash): the varied people reach the arm at different places.
  assert.ok(a.minClearance.max - a.minClearance.min > 1e-3, JSON.stringify(a.minClearance));
  const other = sa.monteCarlo(s, { runs: 6, seed: 6, rows: true });
  assert.notDeepEqual(other.rows.map((r) => r.minClearance), a.rows.map((r) => r.minClearance));
  const bad = structuredClone(s);
  bad.obstacles[0].shape.vary = { height: [1.9, 1.6] };
  assert.throws(() => sa.monteCarlo(bad, { runs: 2, seed: 1 }), /obstacles\[0\]\.shape\.vary\.height: expected \[min, max\]/);
  bad.obstacles[0].shape.vary = { clips: ['dance'] };
  assert.throws(() => sa.monteCarlo(bad, { runs: 2, seed: 1 }), /obstacles\[0\]\.shape\.vary\.clips\[0\]: unknown motion/);
});
