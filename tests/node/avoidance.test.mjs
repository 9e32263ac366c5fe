// The avoidance settings of the public JS contract, against crate/pkg-node:
// controller.avoidance, safetyBand, selfCollisionExclude, protective.withdrawSpeed,
// the startContact event and robotFromUrdf's srdf option.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const sa = require('../../crate/pkg-node/skeleton_avoidance.js');

const READY = [0, -0.785398, 0, -2.356194, 0, 1.570796, 0.785398];
/** The flange's orientation in the ready pose, [x, y, z, w]. */
const READY_ORIENTATION = [-0.9238795637760318, 0.38268335688530947, 0, 0];
const scene = (controller, obstacles = []) => ({
  robot: { preset: 'panda' },
  q0: READY,
  obstacles: [{ id: 'ball', shape: { type: 'sphere', center: [0.307, 0.2, 0.59], radius: 0.05 } }, ...obstacles],
  task: { type: 'goal', position: [0.307, 0.4, 0.59], orientation: READY_ORIENTATION },
  controller,
  dt: 0.002,
  duration: 6,
});

function finalError(trace) {
  const robot = sa.robotPreset('panda');
  const q = trace.samples.at(-1).q;
  const ee = sa.forwardKinematics(robot, q).endEffector;
  return Math.hypot(ee[0][3] - 0.307, ee[1][3] - 0.4, ee[2][3] - 0.59);
}

test('the default avoidance reaches a goal behind a ball; the paper\'s repulsion, selectable, does not', () => {
  assert.equal(sa.exampleScenario('lwr4-elbow').controller.avoidance, 'constraints');
  assert.equal(sa.exampleScenario('lwr4-elbow').controller.safetyBand, 0.02);
  const constraints = finalError(sa.simulate(scene({})));
  const repulsion = finalError(sa.simulate(scene({ avoidance: 'repulsion' })));
  assert.ok(constraints < 0.01, `constraints: ${constraints} m from the goal`);
  assert.ok(repulsion > 0.05, `repulsion: ${repulsion} m from the goal`);
});

test('bad avoidance settings are refused with the field named', () => {
  assert.throws(() => sa.simulate(scene({ avoidance: 'magnets' })), /controller\.avoidance/);
  assert.throws(() => sa.simulate(scene({ safetyBand: 0.4 })), /controller\.safetyBand: must be < influenceDistance/);
  assert.throws(() => sa.simulate(scene({ selfCollisionExclude: [[1, 12]] })), /controller\.selfCollisionExclude\[0\]\[1\]: 12 is not a link/);
  assert.throws(() => sa.simulate(scene({ selfCollisionExclude: [[1, 4], [4, 1]] })), /controller\.selfCollisionExclude\[1\]: the pair is listed twice/);
  assert.throws(() => sa.simulate(scene({ protective: { withdrawSpeed: 0 } })), /controller\.protective\.withdrawSpeed/);
  const w = new sa.World(scene({}));
  const before = JSON.stringify(w.state().q);
  assert.throws(() => w.setController({ selfCollisionExclude: [['nope', 2]] }), /selfCollisionExclude\[0\]\[0\]: no link named "nope"/);
  assert.equal(JSON.stringify(w.state().q), before);
  w.free();
});

test('an overlap at the start is reported once and backed out of', () => {
  const s = scene({}, [{ id: 'crate', shape: { type: 'box', center: [0.03, 0, 0.79], halfExtents: [0.1, 0.1, 0.05] } }]);
  const trace = sa.simulate(s);
  const start = trace.events.filter((e) => e.kind === 'startContact');
  assert.equal(start.length, 1);
  assert.equal(start[0].obstacle, 'crate');
  assert.ok(start[0].distance < 0 && typeof start[0].link === 'string' && start[0].pairs >= 1);
  assert.ok(trace.samples.at(-1).minClearance > 0, 'backed out');
});

test('robotFromUrdf reads an SRDF\'s disable_collisions and names links', () => {
  const xml = fs.readFileSync(new URL('../../crate/tests/data/urdf/panda_collision.urdf', import.meta.url), 'utf8');
  const srdf = '<robot name="panda"><disable_collisions link1="panda_link1" link2="panda_link4" reason="Never"/></robot>';
  const spec = sa.robotFromUrdf(xml, { tip: 'panda_link8', srdf });
  assert.deepEqual(spec.selfCollisionExclude, [[1, 4]]);
  assert.equal(spec.linkNames[0], 'panda_link1');
  assert.throws(() => sa.robotFromUrdf(xml, { srdf: '<robot><disable_collisions link1="a"/></robot>' }), /srdf: .*link2/);
});

test('the NEO baseline is selectable; its gains out of range are refused with the field named, the world unchanged', () => {
  // The goal beside a ball passed within NEO's influence distance (crate/tests/neo_baseline.rs).
  const ready = [0.307, 0, 0.59];
  const neoScene = (neo) => ({
    ...scene({ avoidance: 'neo', ...(neo ? { neo } : {}) }),
    obstacles: [{ id: 'ball', shape: { type: 'sphere', center: [ready[0] + 0.22, 0.17, ready[2] - 0.05], radius: 0.05 } }],
    task: { type: 'goal', position: [ready[0], 0.35, ready[2] - 0.1], orientation: READY_ORIENTATION },
    dt: 0.005,
    duration: 15,
  });
  const trace = sa.simulate(neoScene({ limiter: true }));
  const robot = sa.robotPreset('panda');
  const ee = sa.forwardKinematics(robot, trace.samples.at(-1).q).endEffector;
  const error = Math.hypot(ee[0][3] - ready[0], ee[1][3] - 0.35, ee[2][3] - (ready[2] - 0.1));
  assert.ok(error < 0.01, `neo: ${error} m from the goal`);
  assert.ok(trace.samples.every((s) => s.minClearance === null || s.minClearance > 0));

  assert.throws(() => sa.simulate(neoScene({ influenceDistance: -0.1 })), /controller\.neo\.influenceDistance/);
  assert.throws(() => sa.simulate(neoScene({ stoppingDistance: 0.3 })), /controller\.neo\.stoppingDistance: must be < neo\.influenceDistance/);
  assert.throws(() => sa.simulate(neoScene({ damperGain: Number.NaN })), /controller\.neo\.damperGain/);
  assert.throws(() => sa.simulate(neoScene({ reach: 1 })), /controller\.neo/);
  const w = new sa.World(scene({}));
  w.step(0.002);
  const before = JSON.stringify([w.state().q, w.controller()]);
  assert.throws(() => w.setController({ avoidance: 'neo', neo: { stoppingDistance: 0.5 } }), /controller\.neo\.stoppingDistance/);
  assert.throws(() => w.setController({ avoidance: 'neo2' }), /controller\.avoidance/);
  assert.equal(JSON.stringify([w.state().q, w.controller()]), before);
  w.setController({ avoidance: 'neo', neo: { limiter: true } });
  assert.equal(w.controller().avoidance, 'neo');
  assert.equal(w.controller().neo.limiter, true);
  assert.equal(w.controller().neo.influenceDistance, 0.3);
  w.free();
});
