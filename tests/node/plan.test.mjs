// planPath(scenario, goalQ, options?) and the `joints` task (crate/pkg-node):
// a PR2 problem the reactive controller leaves in a local minimum, planned
// and followed in a World to its goal configuration; the plan's shape; bad
// input refused with the field named and no world changed.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { reachProblems } from '../../package/reach-node.js';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const problem = () => reachProblems('pr2').find((p) => p.name === 'pr2/bookshelf/4');

test('planPath: a path from q0 to goalQ, followed as a joints task to the goal', () => {
  const p = problem();
  const plan = sa.planPath(p.scenario, p.goalQ);
  assert.deepEqual(plan.configurations[0], p.scenario.q0);
  assert.deepEqual(plan.configurations.at(-1), p.goalQ);
  assert.equal(plan.times.length, plan.configurations.length);
  assert.equal(plan.times[0], 0);
  assert.ok(plan.thresholds.obstacles >= 0.02, 'keeps the safety band');
  assert.equal(plan.escape, 0);
  const scenario = {
    ...p.scenario,
    task: { type: 'joints', configurations: plan.configurations, times: plan.times },
  };
  const world = new sa.World(scenario);
  try {
    // The path's clock waits while the arm lags (its limits, a guard), so
    // the arm arrives after the path's last time: wait for the arm, with
    // 5 s of simulated time to spare.
    const last = plan.times.at(-1);
    const arrived = () =>
      world.time > last && world.q().every((v, j) => Math.abs(v - p.goalQ[j]) < 1e-4);
    let lowest = Infinity;
    while (world.time < last + 5 && !arrived()) {
      world.step(scenario.dt);
      lowest = Math.min(lowest, world.state().minClearance);
    }
    const q = world.q();
    p.goalQ.forEach((g, j) => assert.ok(Math.abs(q[j] - g) < 1e-3, `joint ${j}: ${q[j]} vs ${g}`));
    assert.ok(lowest > 0.019, `clearance ${lowest}`);
  } finally {
    world.free();
  }
});

test('planPath is deterministic for a seed', () => {
  const p = problem();
  const a = sa.planPath(p.scenario, p.goalQ, { seed: 3 });
  const b = sa.planPath(p.scenario, p.goalQ, { seed: 3 });
  assert.deepEqual(a, b);
});

test('planPath and the joints task refuse bad input with the field named', () => {
  const p = problem();
  const throwsField = (f, field) =>
    assert.throws(f, (e) => e instanceof Error && e.message.startsWith(field), field);
  throwsField(() => sa.planPath(p.scenario, [0, 0]), 'goalQ');
  throwsField(() => sa.planPath(p.scenario, p.goalQ.map((v, j) => (j === 1 ? NaN : v))), 'goalQ');
  throwsField(() => sa.planPath(p.scenario, p.goalQ.map((v, j) => (j === 0 ? 99 : v))), 'goalQ[0]');
  throwsField(() => sa.planPath(p.scenario, p.goalQ, { step: 0 }), 'options.step');
  throwsField(() => sa.planPath(p.scenario, p.goalQ, { rounds: 0 }), 'options.rounds');
  throwsField(() => sa.planPath(p.scenario, p.goalQ, { timeScale: 0.5 }), 'options.timeScale');
  throwsField(() => sa.planPath(p.scenario, p.goalQ, { speed: 1 }), 'options');
  const joints = (task, controller) => ({ ...p.scenario, task, controller: { ...p.scenario.controller, ...controller } });
  const ok = { type: 'joints', configurations: [p.scenario.q0], times: [0] };
  throwsField(() => new sa.World(joints(ok, { avoidance: 'repulsion' })), 'task.type');
  throwsField(() => new sa.World(joints({ ...ok, times: [0, 1] })), 'task.times');
  throwsField(() => new sa.World(joints({ ...ok, configurations: [[0, 0]] })), 'task.configurations[0]');
  throwsField(() => new sa.World(joints([ok, { type: 'hold' }])), 'task[0].type');
  // A refused controller edit leaves a world following its path unchanged.
  const world = new sa.World(joints(ok));
  try {
    throwsField(() => world.setController({ ...p.scenario.controller, avoidance: 'repulsion' }), 'task.type');
    world.step(p.scenario.dt);
    assert.equal(world.time, p.scenario.dt);
  } finally {
    world.free();
  }
});
