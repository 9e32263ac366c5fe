// The reach problem sets from JS, against crate/pkg-node: reachProblems
// returns plain problems whose scenarios a World runs as they are, the
// MotionBenchMaker set from its scene files, and refusals that name the
// field.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const MBM = new URL('../../crate/tests/data/mbm/', import.meta.url);
const mbmFile = (scene) => fs.readFileSync(new URL(`${scene}.json`, MBM), 'utf8');

/** The end effector's distance to the goal after `steps` steps of the problem's World. */
function distanceAfter(problem, steps) {
  const world = new sa.World(problem.scenario);
  try {
    for (let k = 0; k < steps; k++) world.step(problem.scenario.dt);
    const e = sa.forwardKinematics(problem.scenario.robot, world.q()).endEffector;
    const p = problem.goal.position;
    return Math.hypot(e[0][3] - p[0], e[1][3] - p[1], e[2][3] - p[2]);
  } finally {
    world.free();
  }
}

test('reachProblems("pr2"): NEO\'s 198 problems as plain data a World runs', () => {
  const problems = sa.reachProblems('pr2');
  assert.equal(problems.length, 198);
  const p = problems[0];
  assert.deepEqual(Object.keys(p).sort(), ['goal', 'goalQ', 'name', 'scenario']);
  assert.equal(p.name, 'pr2/bookshelf/0');
  assert.equal(p.goalQ.length, 7);
  assert.equal(p.scenario.task.type, 'goal');
  assert.deepEqual(p.scenario.task.position, p.goal.position);
  // The goal is the flange at goalQ: the arm's own kinematics say so.
  const e = sa.forwardKinematics(p.scenario.robot, p.goalQ).endEffector;
  for (let i = 0; i < 3; i++) assert.ok(Math.abs(e[i][3] - p.goal.position[i]) < 1e-9);
  // The scenario round-trips through JSON (the playground's file format) and runs.
  const again = { ...p, scenario: JSON.parse(JSON.stringify(p.scenario)) };
  const start = distanceAfter(again, 0);
  assert.ok(distanceAfter(again, 200) < start, 'the arm moves towards the goal');
  // The same problems every call.
  assert.deepEqual(sa.reachProblems('pr2')[197], problems[197]);
});

test('reachProblems("panda"): seeded random problems', () => {
  const problems = sa.reachProblems('panda');
  assert.equal(problems.length, 100);
  assert.ok(problems.every((p) => p.name.startsWith('panda/1/') && p.scenario.robot.preset === 'panda'));
});

test('reachProblems("mbm", files): MotionBenchMaker from its scene files, as text or objects', () => {
  const text = mbmFile('cage');
  const fromText = sa.reachProblems('mbm', text);
  assert.equal(fromText.length, 100);
  assert.deepEqual(sa.reachProblems('mbm', [JSON.parse(text)]), fromText);
  const p = fromText[0];
  assert.equal(p.name, 'mbm/cage/1');
  assert.equal(p.scenario.obstacles.length, 8);
  const e = sa.forwardKinematics('panda', p.goalQ).endEffector;
  for (let i = 0; i < 3; i++) assert.ok(Math.abs(e[i][3] - p.goal.position[i]) < 1e-9);
  // Cylinders become capsules.
  const table = sa.reachProblems('mbm', mbmFile('table_pick'));
  assert.ok(table[0].scenario.obstacles.some((o) => o.shape.type === 'capsule'));
  new sa.World(table[0].scenario).free();
});

test('reachProblems refuses what it cannot build, naming the field', () => {
  assert.throws(() => sa.reachProblems('ur5'), /^Error: set: unknown problem set "ur5" \(known: pr2, panda, mbm\)/);
  assert.throws(() => sa.reachProblems(), /^Error: set: expected a string/);
  assert.throws(() => sa.reachProblems(7), /^Error: set: /);
  assert.throws(() => sa.reachProblems('mbm'), /^Error: data: the MotionBenchMaker set is not built in/);
  assert.throws(() => sa.reachProblems('pr2', '[]'), /^Error: data: the "pr2" set is built in/);
  assert.throws(() => sa.reachProblems('mbm', 'not json'), /^Error: data: not JSON/);
  assert.throws(() => sa.reachProblems('mbm', [{ set: 'mbm' }]), /^Error: data\[0\]/);
  assert.throws(() => sa.reachProblems('mbm', { set: 'neo', problems: [] }), /^Error: data\.set: expected "mbm"/);
});
