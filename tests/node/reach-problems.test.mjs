// reachProblems(set) (package/reach-node.js over package/problems/): the
// counts, equality with Rust's reach::problems(set) (the fixture written by
// crate/tests/reach_problem_files.rs, run by the cargo tests before this
// one), input validation, and a problem's scenario run in a World
// (crate/pkg-node).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';
import { reachProblems } from '../../package/reach-node.js';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const COUNTS = { pr2: 198, panda: 100, mbm: 700 };
// Cargo's target directory (CARGO_TARGET_DIR when set, as cargo resolves it
// from the repository's root), whose tmp/ the Rust test writes to.
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const target = path.resolve(root, process.env.CARGO_TARGET_DIR ?? 'target');
const fixture = (set) => path.join(target, 'tmp', 'reach-problems', `${set}.json`);

for (const [set, count] of Object.entries(COUNTS)) {
  test(`reachProblems('${set}'): ${count} problems, the same as the native set`, () => {
    const problems = reachProblems(set);
    assert.equal(problems.length, count);
    assert.ok(
      fs.existsSync(fixture(set)),
      'the native fixture is written by `cargo test -p skeleton-avoidance --test reach_problem_files`',
    );
    assert.deepEqual(problems, JSON.parse(fs.readFileSync(fixture(set), 'utf8')));
    for (const p of problems) {
      assert.equal(p.goal.position.length, 3, p.name);
      assert.equal(p.goal.orientation.length, 4, p.name);
    }
  });

  test(`reachProblems('${set}'): the last problem loads into a World and steps`, () => {
    // Its own q0 and obstacles over the set's base.
    const p = reachProblems(set).at(-1);
    const world = new sa.World(p.scenario);
    try {
      for (let k = 0; k < 20; k++) world.step(p.scenario.dt);
      assert.equal(world.time, 20 * p.scenario.dt);
      const q = world.q();
      assert.equal(q.length, p.scenario.q0.length);
      assert.ok([...q].every(Number.isFinite));
    } finally {
      world.free();
    }
  });
}

test('reachProblems returns fresh objects: a caller editing one changes no later call', () => {
  const a = reachProblems('panda');
  a[0].scenario.obstacles.push({ id: 'x' });
  a[0].goal.position[0] = 99;
  const b = reachProblems('panda');
  assert.notEqual(b[0].goal.position[0], 99);
  assert.notDeepEqual(b[0].scenario.obstacles.at(-1), { id: 'x' });
});

test('reachProblems refuses an unknown set or a wrong file, naming the field', () => {
  assert.throws(() => reachProblems('x'), { message: "set: unknown problem set 'x' (pr2, panda, mbm)" });
  assert.throws(() => reachProblems(), { message: 'set: unknown problem set undefined (pr2, panda, mbm)' });
  assert.throws(() => reachProblems(7), { message: 'set: unknown problem set 7 (pr2, panda, mbm)' });
  assert.throws(() => reachProblems('pr2', { set: 'mbm', base: {}, problems: [] }), /^Error: data: not the 'pr2' problem file/);
  assert.throws(() => reachProblems('pr2', { set: 'pr2', base: {}, problems: [1] }), /^Error: data\.problems\[0\]: not a problem/);
  assert.deepEqual(reachProblems('pr2', { set: 'pr2', base: {}, problems: [] }), []);
});
