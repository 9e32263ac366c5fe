// The declarations against the runtime, from the packed package in a fresh
// project:
//
// 1. What every export really returns (presets, URDF import, kinematics,
//    distances, figures, examples, traces with their events, a World's
//    state, readouts, picks, risks, studies) is written out as object
//    literals typed with the declared types and given to `tsc --strict
//    --exactOptionalPropertyTypes`. An object literal gets excess-property
//    checks, so a field the runtime returns that the types lack is an error,
//    and a required field the runtime omits is an error too.
// 2. A program that uses every export as docs/js-api.md shows (a `using`
//    World, events narrowed by kind, `{ tip: undefined }`, a box without
//    rotation, `seg.part`) type-checks under the same flags and runs.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { installPackage, sh, tsc } from './project.mjs';

let dir;
before(() => { dir = installPackage('types'); });
after(() => { if (dir) fs.rmSync(dir, { recursive: true, force: true }); });

const URDF = `<robot name="two">
  <link name="base"/><link name="upper"><collision><geometry><cylinder radius="0.06" length="0.4"/></geometry></collision></link>
  <link name="fore"/><link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="2"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/></joint>
  <joint name="flange" type="fixed"><parent link="fore"/><child link="tool"/><origin xyz="0 0 0.3"/></joint>
</robot>`;

// Runs in the project (Node, ESM): calls every export and writes observed.ts.
const OBSERVE = `
import fs from 'node:fs';
import * as sa from 'skeleton-avoidance';

/** A TypeScript literal of a runtime value (typed arrays kept as such). */
function lit(v) {
  if (v === undefined) return 'undefined';
  if (v === null) return 'null';
  if (typeof v === 'number') return Object.is(v, -0) ? '-0' : Number.isFinite(v) ? String(v) : (Number.isNaN(v) ? 'NaN' : (v > 0 ? 'Infinity' : '-Infinity'));
  if (typeof v === 'string' || typeof v === 'boolean') return JSON.stringify(v);
  if (v instanceof Float64Array) return \`new Float64Array(\${lit([...v])})\`;
  if (Array.isArray(v)) return \`[\${v.map(lit).join(', ')}]\`;
  if (typeof v === 'object') {
    if (Object.getPrototypeOf(v) !== Object.prototype) throw new Error('not a plain object: ' + Object.prototype.toString.call(v));
    return \`{ \${Object.entries(v).map(([k, x]) => \`\${JSON.stringify(k)}: \${lit(x)}\`).join(', ')} }\`;
  }
  throw new Error('unexpected ' + typeof v);
}
const lines = ["import type * as T from 'skeleton-avoidance';"];
let n = 0;
const add = (type, value) => lines.push(\`export const v\${n++}: \${type} = \${lit(value)};\`);
/** The first and last few of a long list (the file stays small). */
const ends = (list, k = 3) => (list.length <= 2 * k ? list : [...list.slice(0, k), ...list.slice(-k)]);
/** At most four events of each kind. */
function someEvents(events) {
  const per = new Map();
  return events.filter((e) => { const c = per.get(e.kind) ?? 0; per.set(e.kind, c + 1); return c < 4; });
}

const names = sa.presetNames();
add('T.PresetName[]', names);
lines.push(\`type Unlisted = Exclude<T.PresetName, \${names.map((x) => JSON.stringify(x)).join(' | ')}>;\`);
lines.push('export const everyPresetListed: [Unlisted] extends [never] ? true : false = true;');
for (const name of names) add('T.RobotSpec', sa.robotPreset(name));
add('T.RobotSpec & { jointNames: string[] }', sa.robotFromUrdf(${JSON.stringify(URDF)}, { tip: 'tool' }));
add('ReturnType<typeof T.importUrdf>', sa.importUrdf(${JSON.stringify(URDF)}, { tip: 'tool', radii: { fore: 0.03 } }));
const q = [0.1, -0.4, 0.2, -1.8, 0.1, 1.4, 0.6];
add('T.ForwardKinematics', sa.forwardKinematics('panda', q));
add('T.ForwardKinematics', sa.forwardKinematics('dual-arm', new Float64Array(sa.robotPreset('dual-arm').joints.length + sa.robotPreset('dual-arm').branches.reduce((s, b) => s + b.joints.length, 0))));
add('T.SkeletonResult', sa.skeleton('panda', q));
add('T.ControlPointResult', sa.controlPoint('panda', q, { link: 4, d: 0, a: 0.04 }));
add('T.ControlPointResult', sa.controlPoint('panda', q, { link: 4, d: 0, a: 0.04 }, { qdot: [0.1, 0, 0, 0.2, 0, 0, 0], aRate: 0.01, dRate: 0 }));
add('T.DhPoint & { position: T.Vec3 }', sa.skeletonPoint('panda', q, { segment: 3, t: 0.5 }));
add('Float64Array', sa.inverseDynamics('panda', q, q, q));
add('ReturnType<typeof T.inverseDynamics>', sa.inverseDynamics('iiwa14', q, q, q, { gravity: [0, 0, -9.81] }));
add('number[][]', sa.massMatrix({ preset: 'ur5' }, q.slice(0, 6)));
const shapes = [
  { type: 'point', p: [0, 0, 1] }, { type: 'segment', a: [0, 0, 0], b: [1, 0, 0] },
  { type: 'sphere', center: [0.5, 0, 0.5], radius: 0.1 }, { type: 'capsule', a: [0, 1, 0], b: [1, 1, 0], radius: 0.05 },
  { type: 'plane', normal: [0, 0, 1], offset: 0 }, { type: 'disk', center: [0, 0, 2], normal: [0, 0, 1], radius: 0.2 },
  { type: 'rectangle', center: [2, 0, 0], axes: [[1, 0, 0], [0, 1, 0]], halfExtents: [0.1, 0.2] },
  { type: 'polygon', vertices: [[0, 0, 3], [1, 0, 3], [0, 1, 3]] },
  { type: 'box', center: [0, 2, 0], halfExtents: [0.1, 0.1, 0.1] },
  { type: 'box', center: [0, 2, 0], halfExtents: [0.1, 0.1, 0.1], rotation: [0, 0, 0, 1] },
];
for (const s of shapes) add('T.Primitive', s);
for (const s of shapes.slice(1)) add('T.DistanceResult', sa.distance(shapes[0], s));
add('T.Vec3', sa.referencePoint({ type: 'human', position: [1, 0, 0] }));
add('T.Shape', sa.translateShape(shapes[8], [0.1, 0, 0]));
add('T.Shape', sa.translateShape({ type: 'human', position: [1, 0, 0] }, [0.1, 0, 0]));
for (const name of sa.exampleScenarioNames()) {
  const scenario = sa.exampleScenario(name);
  add('T.Scenario', scenario);
  const trace = sa.simulate({ ...scenario, duration: Math.min(scenario.duration, 3) });
  add('T.Trace', { samples: ends(trace.samples), events: someEvents(trace.events) });
  const world = new sa.World(scenario);
  world.advance(scenario.dt, Math.round(1 / scenario.dt));
  const state = world.state();
  add('T.WorldState', { ...state, events: someEvents(state.events) });
  add('T.ControllerInEffect', world.controller());
  add('Float64Array', world.q());
  add('Float64Array', world.qdot());
  for (const o of scenario.obstacles) add('number', world.clearance(o.id));
  add('T.Risk', world.riskAt({ type: 'sphere', center: [0.4, 0, 0.4], radius: 0.05 }, { bound: 0.01 }));
  const nodes = state.skeleton.nodes;
  const mid = nodes[Math.floor(nodes.length / 2)];
  add('T.SkeletonPickResult | null', world.pickSkeleton([mid[0], mid[1], mid[2] + 5], [0, 0, -1]));
  for (const o of state.obstacles.slice(0, 2)) {
    const c = sa.referencePoint(o.shape);
    add('T.PickResult | null', world.pick([c[0] + 5, c[1], c[2]], [-1, 0, 0]));
  }
  world.free();
}
const study = sa.exampleScenario('chattering');
const small = { ...study, duration: 0.5 };
add('T.MonteCarloReport', sa.monteCarlo(small, { runs: 2, seed: 1, rows: true }));
add('T.MonteCarloRow[]', sa.monteCarloRuns(small, { seed: 1, from: 0, count: 2 }));
for (const set of ['pr2', 'panda', 'mbm']) add('T.ReachProblem[]', sa.reachProblems(set).slice(0, 2));
fs.writeFileSync('observed.ts', lines.join('\\n') + '\\n');
console.log(n);
`;

// Every export as the docs show it, under strict flags; printed results are checked.
const USAGE = `
import {
  robotPreset, presetNames, robotFromUrdf, importUrdf, forwardKinematics, skeleton, controlPoint, skeletonPoint,
  inverseDynamics, massMatrix, distance, referencePoint, translateShape, simulate, exampleScenario, exampleScenarioNames,
  monteCarlo, monteCarloRuns, monteCarloMerge, World, Viewer,
  type EventOf, type TraceEvent, type Primitive, type Scenario, type PresetName,
} from 'skeleton-avoidance';

declare const console: { log(...values: unknown[]): void };
const xml = ${JSON.stringify(URDF)};
const robot = robotFromUrdf(xml, { tip: 'tool', base: undefined });
const imported = importUrdf(xml, { radii: { upper: 0.05 } });
const byName = forwardKinematics(robot, { shoulder: 0.1, elbow: -0.2 });
const presets: PresetName[] = ['planar3', 'lwr4', 'iiwa14', 'panda', 'ur5', 'dual-arm', 'stanford'];
const fk = forwardKinematics(robotPreset(presets[presets.length - 1]!), new Float64Array(6));
// The listed names are the literal type robotPreset takes.
const firstPreset = robotPreset(presetNames()[0]);
const parts = skeleton('panda', [0, -0.5, 0, -2, 0, 1.5, 0.8]).segments.map((s) => s.part.toUpperCase());
const cp = controlPoint('panda', [0, -0.5, 0, -2, 0, 1.5, 0.8], { link: 4, d: 0, a: 0.04 });
const sp = skeletonPoint('planar3', [0, 0, 0], { segment: 1, t: 0.5 });
const tau: Float64Array = inverseDynamics('panda', [0, -0.5, 0, -2, 0, 1.5, 0.8], new Float64Array(7), [0, 0, 0, 0, 0, 0, 0], { gravity: [0, 0, -9.81] });
const mass: number[][] = massMatrix({ preset: 'lwr4' }, new Float64Array(7));
const box: Primitive = { type: 'box', center: [0.5, 0, 0.5], halfExtents: [0.1, 0.1, 0.1] };
const d = distance(box, { type: 'point', p: [0.5, 0, 1] });
const moved = translateShape(box, [0, 0, 0.1]);
const scenario: Scenario = exampleScenario('chattering');
const trace = simulate(scenario);
const stops: EventOf<'stop'>[] = trace.events.filter((e): e is EventOf<'stop'> => e.kind === 'stop');
const described = trace.events.map((e: TraceEvent) => {
  switch (e.kind) {
    case 'segmentSwitch': return \`\${e.obstacle}: \${e.from} -> \${e.to}\`;
    case 'stop': return e.reason;
    case 'chattering': return \`\${e.switches} switches\`;
    default: return e.kind;
  }
});
let time = 0;
let clearance = 0;
{
  using world = new World({ robot: { preset: 'ur5' }, obstacles: [{ id: 'ball', shape: { type: 'sphere', center: [0.4, 0, 0.4], radius: 0.05 } }], dt: 0.001, duration: 1 });
  world.advance(0.001, 100);
  time = world.time;
  clearance = world.clearance('ball');
  const q: Float64Array = world.q();
  const qdot: Float64Array = world.qdot();
  void [q, qdot, world.controller().influenceDistance, world.state().skeleton.segments[0]?.part];
}
const study = monteCarlo({ ...scenario, duration: 0.3 }, { runs: 2, seed: 1 });
const merged = monteCarloMerge(monteCarloRuns({ ...scenario, duration: 0.3 }, { seed: 1, count: 2 }));
let viewer = 'none';
try {
  await Viewer.create({ width: 10, height: 10, clientWidth: 10, clientHeight: 10 });
} catch (e) {
  viewer = (e as Error).message;
}
console.log(JSON.stringify({
  joints: robot.jointNames, radiusFrom: imported.report.joints.map((j) => j.radiusFrom), byName: byName.origins.length, presets: presetNames(), examples: exampleScenarioNames().length, fk: fk.origins.length, firstPreset: firstPreset.joints.length, parts,
  cp: cp.jTheta.length, sp: sp.link, tau: tau.length, mass: mass.map((row) => row.length), d: d.distance, normal: d.normal, unique: d.unique, moved: referencePoint(moved),
  stops: stops.length, described: described.length, time, clearance, runs: study.runs, same: JSON.stringify(merged) === JSON.stringify(study), viewer,
}));

export function misuses(): void {
  // @ts-expect-error: 'sphere' has no size.
  distance({ type: 'sphere', center: [0, 0, 0], size: 1 }, box);
  // @ts-expect-error: no preset of that name.
  robotPreset('kr210');
  // @ts-expect-error: a scenario's robot is a spec or { preset }, not a bare name.
  simulate({ robot: 'ur5', obstacles: [], dt: 0.01, duration: 1 });
  // @ts-expect-error: a stop event has a reason, not an obstacle.
  void ((e: EventOf<'stop'>) => e.obstacle);
}
`;

// `skeleton-avoidance/element` as a page's TypeScript uses it, and the compat
// entries (the same declarations).
const ELEMENT = `
import { SkeletonPlayground, Playground, loadWasm } from 'skeleton-avoidance/element';
import { World as CompatWorld, presetNames } from 'skeleton-avoidance/compat';
import { SkeletonPlayground as CompatElement } from 'skeleton-avoidance/compat/element';
import type { World } from 'skeleton-avoidance';

export const compatWorld: typeof World = CompatWorld;
export const compatPresets: string[] = presetNames();
export const compatReady = (e: CompatElement): Promise<number> => e.ready.then((pg) => pg.world?.time ?? 0);

const made: SkeletonPlayground = document.createElement('skeleton-playground');
made.setAttribute('scenario', 'human-panda');
document.body.append(made);
export const time: Promise<number> = made.ready.then((pg) => pg.world?.time ?? 0);
export const names: Promise<string[]> = loadWasm().then((sa) => sa.presetNames());
export const widget = new Playground(document.createElement('div'), { controls: 'none', plot: undefined });
// @ts-expect-error: no such control mode.
export const wrong = new Playground(document.createElement('div'), { controls: 'some' });
`;

test('every field the runtime returns is declared, every required field is returned (tsc --strict --exactOptionalPropertyTypes)', () => {
  fs.writeFileSync(path.join(dir, 'observe.mjs'), OBSERVE);
  const observed = sh(process.execPath, ['observe.mjs'], dir);
  assert.equal(observed.status, 0, observed.out);
  const count = Number(observed.out.trim().split('\n').pop());
  console.log(`# ${count} runtime values written as typed literals (${(fs.statSync(path.join(dir, 'observed.ts')).size / 1e3).toFixed(0)} kB)`);
  assert.ok(count > 90, `${count} values`);
  fs.writeFileSync(path.join(dir, 'usage.ts'), USAGE);
  fs.writeFileSync(path.join(dir, 'tsconfig.json'), JSON.stringify({
    compilerOptions: {
      target: 'es2022', module: 'nodenext', moduleResolution: 'nodenext', strict: true,
      exactOptionalPropertyTypes: true, noUncheckedIndexedAccess: true, noEmitOnError: true,
      skipLibCheck: false, types: [], lib: ['es2022'], outDir: 'out',
    },
    files: ['observed.ts', 'usage.ts'],
  }));
  const typed = sh(tsc, ['-p', '.'], dir);
  assert.equal(typed.status, 0, `tsc:\n${typed.out.slice(0, 6000)}`);
  // The element's declarations, in a program with the DOM's types.
  fs.writeFileSync(path.join(dir, 'element.ts'), ELEMENT);
  fs.writeFileSync(path.join(dir, 'tsconfig.element.json'), JSON.stringify({
    compilerOptions: {
      target: 'es2022', module: 'nodenext', moduleResolution: 'nodenext', strict: true,
      exactOptionalPropertyTypes: true, noEmit: true, skipLibCheck: false, types: [], lib: ['es2022', 'dom'],
    },
    files: ['element.ts'],
  }));
  const element = sh(tsc, ['-p', 'tsconfig.element.json'], dir);
  assert.equal(element.status, 0, `tsc (element):\n${element.out.slice(0, 4000)}`);
  const ran = sh(process.execPath, ['out/usage.js'], dir);
  assert.equal(ran.status, 0, ran.out);
  const r = JSON.parse(ran.out.trim().split('\n').pop());
  assert.deepEqual(r.joints, ['shoulder', 'elbow']);
  assert.deepEqual(r.radiusFrom, ['override', 'default']);
  assert.equal(r.byName, 3);
  assert.deepEqual(r.presets, ['planar3', 'lwr4', 'iiwa14', 'panda', 'ur5', 'dual-arm', 'stanford']);
  assert.equal(r.examples, 7);
  assert.equal(r.fk, 7);
  assert.equal(r.tau, 7);
  assert.deepEqual(r.mass, [7, 7, 7, 7, 7, 7, 7]);
  assert.equal(r.firstPreset, 3);
  assert.ok(r.parts.every((p) => ['D', 'A', 'EXTENSION'].includes(p)) && r.parts.length > 5);
  assert.equal(r.cp, 3);
  assert.ok(Math.abs(r.d - 0.4) < 1e-12, `box to point ${r.d}`);
  assert.deepEqual(r.normal, [0, 0, 1]);
  assert.equal(r.unique, true);
  assert.ok(Math.abs(r.moved[2] - 0.6) < 1e-12);
  assert.ok(r.stops >= 1, 'the chattering example stops');
  assert.ok(Math.abs(r.time - 0.1) < 1e-12, `time ${r.time}`);
  assert.ok(Number.isFinite(r.clearance) && r.clearance > 0);
  assert.equal(r.runs, 2);
  assert.equal(r.same, true);
  assert.match(r.viewer, /browser/);
});
