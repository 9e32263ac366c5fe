// Type declarations of the `skeleton-avoidance` npm package, written by hand
// from docs/js-api.md and docs/scenarios.md (wasm-bindgen types plain objects
// as `any`). SI units, radians, z up; quaternions [x, y, z, w]; matrices as
// arrays of rows.

export type Vec3 = [number, number, number];
/** Unit quaternion `[x, y, z, w]`. */
export type Quat = [number, number, number, number];
/** A 4×4 homogeneous transform as rows. */
export type Matrix4 = number[][];
/** Joint values: a plain array or a `Float64Array`. */
export type JointVector = number[] | Float64Array;

// ---- robots ----

export type PresetName = 'planar3' | 'lwr4' | 'panda' | 'ur5' | 'dual-arm' | (string & {});

export interface Pose {
  /** Translation (m); default `[0, 0, 0]`. */
  position?: Vec3;
  /** Unit quaternion `[x, y, z, w]`; default identity. */
  rotation?: Quat;
}

/** One DH row. */
export interface JointSpec {
  /** Link length (m); `a_{i-1}` in the modified convention. */
  a: number;
  /** Link twist (rad). */
  alpha: number;
  /** Link offset (m); the offset added to a prismatic joint's value. */
  d: number;
  /** Joint angle (rad); the offset added to a revolute joint's value. */
  theta: number;
  type?: 'revolute' | 'prismatic';
  /** Position limits (rad or m). */
  min?: number;
  max?: number;
  /** rad/s or m/s, > 0. */
  maxVelocity?: number;
  /** rad/s² or m/s², > 0. */
  maxAcceleration?: number;
  /** rad/s³ or m/s³, > 0. */
  maxJerk?: number;
  /** N·m or N, > 0. */
  maxTorque?: number;
  /** Radius of the link's volume (m), or `[r0, r1]` tapered along each segment; default 0.05. */
  radius?: number | [number, number];
  /** Spine behind the joint (m, ≥ 0): counterbalances, motors. */
  extension?: number;
}

export interface BranchSpec {
  name?: string;
  /** 1-based row whose frame carries the branch; 0 is the base. */
  parent: number;
  /** Rotation `[x, y, z, w]` from the parent frame to the branch's first row. */
  mount?: Quat;
  joints: JointSpec[];
  tool?: Pose;
}

/** A robot described by its DH table. */
export interface RobotSpec {
  name?: string;
  convention: 'standard' | 'modified';
  /** Pose of frame 0 in the world. */
  base?: Pose;
  joints: JointSpec[];
  /** Transform after the main chain's last row. */
  tool?: Pose;
  /** Further chains on the same base. */
  branches?: BranchSpec[];
  /** One unique name per joint, in the order of `q`. */
  jointNames?: string[];
  /** One unique name per link (the link each row moves), in the order of `q`. */
  linkNames?: string[];
  /** Pairs of links that never repel each other (an SRDF's `disable_collisions`). */
  selfCollisionExclude?: [LinkRef, LinkRef][];
}

/** A link by row index (1-based, 0 the base) or by a name from `linkNames`. */
export type LinkRef = number | string;

/** A spec, `{ preset }` or a preset name. */
export type RobotInput = RobotSpec | { preset: PresetName } | PresetName;

export interface UrdfOptions {
  /** Link the chain ends at; default: the end of the longest movable chain. */
  tip?: string;
  /** Link the chain starts at (the world frame); default: the root link. */
  base?: string;
  /** An SRDF document: its `disable_collisions` pairs become `selfCollisionExclude`. */
  srdf?: string;
}

export interface ForwardKinematics {
  /** Origins of frames 0..n. */
  origins: Vec3[];
  frames: Matrix4[];
  endEffector: Matrix4;
  /** One per chain. */
  endEffectors: Matrix4[];
}

export interface SkeletonSegment {
  from: number;
  to: number;
  /** 1-based DH row. */
  link: number;
  part: 'd' | 'a' | 'extension';
  radius: [number, number];
}

export interface SkeletonResult {
  nodes: Vec3[];
  segments: SkeletonSegment[];
  frameNodes: number[];
}

/** A point of the shorter manipulator cut at `link` (1-based). */
export interface DhPoint {
  link: number;
  d: number;
  a: number;
}

export interface ControlPointRates {
  qdot: JointVector;
  aRate?: number;
  dRate?: number;
}

export interface ControlPointResult {
  position: Vec3;
  /** 3 × n, as rows. */
  jTheta: number[][];
  jA: number[][];
  jD: number[][];
  segment?: number;
  t?: number;
  velocity?: Vec3;
  jThetaDot?: number[][];
  jADot?: number[][];
  jDDot?: number[][];
}

// ---- primitives ----

export type Primitive =
  | { type: 'point'; p: Vec3 }
  | { type: 'segment'; a: Vec3; b: Vec3 }
  | { type: 'sphere'; center: Vec3; radius: number }
  | { type: 'capsule'; a: Vec3; b: Vec3; radius: number }
  | { type: 'taperedCapsule'; a: Vec3; b: Vec3; radius: [number, number] }
  | { type: 'plane'; normal: Vec3; offset: number }
  | { type: 'rectangle'; center: Vec3; axes: [Vec3, Vec3]; halfExtents: [number, number] }
  | { type: 'disk'; center: Vec3; normal: Vec3; radius: number }
  | { type: 'polygon'; vertices: Vec3[] }
  | { type: 'box'; center: Vec3; halfExtents: Vec3; rotation: Quat }
  | { type: 'convexHull'; points: Vec3[] };

/** Joint angles of a human (rad), any subset; docs/scenarios.md lists the names and ranges. */
export type HumanPose = Partial<Record<
  | 'spineFlexion' | 'spineLateral' | 'spineTwist' | 'neckFlexion' | 'neckTwist'
  | 'leftShoulderFlexion' | 'leftShoulderAbduction' | 'leftShoulderRotation' | 'leftElbow'
  | 'rightShoulderFlexion' | 'rightShoulderAbduction' | 'rightShoulderRotation' | 'rightElbow'
  | 'leftHipFlexion' | 'leftHipAbduction' | 'leftKnee'
  | 'rightHipFlexion' | 'rightHipAbduction' | 'rightKnee',
  number
>>;

export interface HumanKeyframe {
  /** s */
  t: number;
  pose?: HumanPose;
  /** Root displacement in the body's frame: forward, left, up (m). */
  shift?: Vec3;
}

/** Keyframes, or a motion of the library with its parameters. */
export interface HumanAnimation {
  keyframes?: HumanKeyframe[];
  loop?: boolean;
  clip?: 'reach' | 'wave' | 'walk' | 'bend' | 'stepBack';
  /** `reach`: the point the hand reaches for (m). */
  target?: Vec3;
  side?: 'left' | 'right';
  /** m/s: the hand's peak speed (`reach`) or the walking speed (`walk`). */
  speed?: number;
  /** s */
  start?: number;
}

export interface Human {
  type: 'human';
  position: Vec3;
  heading?: number;
  height?: number;
  reach?: number;
  pose?: HumanPose;
  animation?: HumanAnimation;
}

export type Shape = Primitive | Human;

export interface DistanceResult {
  /** Negative by the penetration depth when two solids overlap. */
  distance: number;
  pointA: Vec3;
  pointB: Vec3;
}

// ---- scenarios ----

export type Motion =
  | { type: 'static' }
  | { type: 'linear'; velocity: Vec3 }
  | { type: 'waypoints'; points: Vec3[]; times: number[]; loop?: boolean }
  | { type: 'circular'; center: Vec3; axis: Vec3; period: number };

export interface Obstacle {
  id: string;
  shape: Shape;
  motion?: Motion;
}

export type Task =
  | { type: 'hold' }
  | { type: 'goal'; position: Vec3; orientation?: Quat; chain?: number }
  | { type: 'trajectory'; points: Vec3[]; times: number[]; chain?: number }
  /** Eq. 4's task: a point whose DH values slide from `from` to `to` holds `position`. */
  | {
      type: 'point';
      link: number;
      from: { d: number; a: number };
      to: { d: number; a: number };
      start?: number;
      duration: number;
      position?: Vec3;
    };

export interface Controller {
  mode?: 'velocity' | 'torque' | 'clik2';
  /** Velocity mode: one-sided constraints in one QP with the tasks (default) or the paper's repulsion. */
  avoidance?: 'constraints' | 'repulsion';
  /** Clearance below which the constraints avoidance pushes the arm away (m; default 0.02, < influenceDistance). */
  safetyBand?: number;
  /** Further pairs of links left out of the self-collision query. */
  selfCollisionExclude?: [LinkRef, LinkRef][];
  selection?: 'pairs' | 'perObstacle' | 'pinned';
  pinned?: DhPoint[];
  influenceDistance?: number;
  repulsionGain?: number;
  maxRepulsionSpeed?: number;
  transitionTime?: number;
  jumpThreshold?: number;
  activationBand?: number;
  taskGain?: number;
  /** One positive weight per joint (eq. 4's W). */
  jointWeights?: number[];
  damping?: { epsilon?: number; lambdaMax?: number };
  torque?: { stiffness?: number; damping?: number; jointDamping?: number; inertia?: number; forceGain?: number };
  clik2?: { kp?: number; kd?: number };
  selfCollision?: boolean;
  /** Whether a point task subtracts its point's own sliding (eq. 4; default true). */
  movingPointTerms?: boolean;
  /** The protective layer beneath the repulsion. */
  protective?: { enabled?: boolean; safetyDistance?: number; reactionTime?: number; withdrawSpeed?: number };
}

/** Sensing model of one obstacle (docs/scenarios.md, Sensing); every field ≥ 0, absent = 0. */
export interface SensingError {
  /** Bound of the error redrawn every step (m). */
  bound?: number;
  /** Bound of the fixed offset drawn once per run (m). */
  biasBound?: number;
  /** White Gaussian standard deviation per axis (m). */
  sigma?: number;
  /** Stationary standard deviation of the Gauss–Markov noise per axis (m). */
  correlatedSigma?: number;
  /** Time constant of the correlated noise (s; default 0.1). */
  correlationTime?: number;
  /** Age of the sensed pose (s). */
  latency?: number;
  seed?: number;
}

export interface Dependability {
  switchWindow?: number;
  maxSwitches?: number;
  onChattering?: 'stop' | 'lock';
  lockTime?: number;
  maxDeceleration?: number;
  /** Switch probability above which `switchRisk` is raised, in (0, 1]; default 0.05. */
  switchRisk?: number;
}

export interface Scenario {
  robot: RobotInput;
  q0?: JointVector;
  obstacles: Obstacle[];
  /** One task, or a list with at most one per chain. */
  task?: Task | Task[];
  controller?: Controller;
  /** `default` and obstacle ids. */
  sensing?: { [obstacleIdOrDefault: string]: SensingError };
  dependability?: Dependability;
  dt: number;
  duration: number;
  sampleEvery?: number;
}

// ---- traces and state ----

export interface TraceControlPoint {
  position: Vec3;
  link: number;
  d: number;
  a: number;
  obstacle: string;
  distance: number;
  /** First-order standard deviations from the sensing error (absent when sensed exactly). */
  sigma?: PointSigma;
}

/** Standard deviations of a control point's quantities caused by the sensing error. */
export interface PointSigma {
  /** Of its clearance (m). */
  distance: number;
  /** Of the selected witness's DH values d', a' (m). */
  d: number;
  a: number;
  /** Of each repulsion component (m/s, or N in torque mode). */
  repulsion: Vec3;
}

export interface TraceSample {
  t: number;
  q: number[];
  minClearance: number | null;
  controlPoints: TraceControlPoint[];
  /** Standard deviation of each joint's command from the sensing errors (absent when sensed exactly). */
  commandSigma?: number[];
}

/** What `World.riskAt` returns: one cell of a risk map. */
export interface Risk {
  /** m; null for a robot without segments. */
  clearance: number | null;
  /** Probability that the closest segment, as sensed, differs from the ideal one. */
  switchProbability: number;
  segment?: number;
  alternative?: number;
}

/** The sensing uncertainty of one obstacle in `WorldState`. */
export interface ObstacleUncertainty {
  obstacle: string;
  /** Margin added to its distances (m). */
  radius: number;
  /** Standard deviation of its sensed position along any axis (m). */
  sigma: number;
  /** Probability that its closest segment, as sensed, differs from the ideal one. */
  switchProbability: number;
  segment?: number;
  alternative?: number;
}

export type EventKind =
  | 'segmentSwitch'
  | 'transitionStart'
  | 'transitionEnd'
  | 'switchRisk'
  | 'chattering'
  | 'stop'
  | 'resume'
  | 'lock'
  | 'unlock'
  | 'transitionTooSlow'
  | 'unavoidable'
  | 'startContact'
  | (string & {});

/** `{ t, kind }` and the fields of its kind (docs/scenarios.md). */
export interface TraceEvent {
  t: number;
  kind: EventKind;
  obstacle?: string;
  [field: string]: unknown;
}

export interface Trace {
  samples: TraceSample[];
  events: TraceEvent[];
}

export interface StateControlPoint extends TraceControlPoint {
  witness: Vec3;
  /** The human part it answers, `id:part` (`person:rightHand`); absent for other obstacles. */
  part?: string;
  /** m/s (velocity, clik2) or N (torque). */
  repulsion: Vec3;
  transitioning: boolean;
  target?: DhPoint;
  /** The DH table of its shorter manipulator, one `{ d, a }` per row (fig. 5). */
  table: { d: number; a: number }[];
}

export interface WorldState {
  t: number;
  q: number[];
  qdot: number[];
  qddot: number[];
  minClearance: number | null;
  /** The human part at `minClearance`, `id:part`; absent when that pair is not a human's. */
  closestPart?: string;
  skeleton: { nodes: Vec3[]; segments: SkeletonSegment[] };
  obstacles: { id: string; shape: Shape; parts: Primitive[] }[];
  controlPoints: StateControlPoint[];
  uncertainty: ObstacleUncertainty[];
  /** The controller's command of the last step, before the protective layer and the limits. */
  command: number[];
  commandSigma?: number[];
  events: TraceEvent[];
  timeToCollision?: number;
  stopped: boolean;
  /** Where the sliding point of each point task is now (m), in task order; empty without point tasks. */
  slidingPoints: Vec3[];
}

export interface PickResult {
  id: string;
  /** The human part hit (`rightHand`); absent for other obstacles. */
  part?: string;
  point: Vec3;
  distance: number;
}

// ---- Monte Carlo studies ----

/** Options of `monteCarlo`. */
export interface MonteCarloOptions {
  /** Number of runs, 1..=10000 in one call. */
  runs: number;
  /** Seed of the study, an integer in 0..=2^53 − 1 (default 0). */
  seed?: number;
  /** Keep every run's row in the report (default false). */
  rows?: boolean;
}

/** Options of `monteCarloRuns`: runs `from .. from + count − 1` of a study. */
export interface MonteCarloRunsOptions {
  seed?: number;
  /** First run (default 0). */
  from?: number;
  /** Number of runs, 1..=10000. */
  count: number;
}

/** One run of a study. */
export interface MonteCarloRow {
  run: number;
  seed: number;
  /** Smallest true clearance over every control step (m); null when nothing came within reach. */
  minClearance: number | null;
  contactWhileMoving: boolean;
  stopped: boolean;
  chattering: boolean;
  /** The monitor raised transitionTooSlow. */
  transitionTooSlow: boolean;
  switches: number;
  switchesPerSecond: number;
  /** Smallest time to collision − remaining transition time (s); null when no transition met an approach. */
  transitionSlack: number | null;
}

/** How often something happened, with a 95 % Wilson interval. */
export interface MonteCarloProbability {
  count: number;
  p: number;
  low: number;
  high: number;
}

/** The distributions of a study. */
export interface MonteCarloReport {
  runs: number;
  seed: number;
  /** Quantiles of each run's smallest clearance (m); null where a run out of reach falls. */
  minClearance: {
    min: number | null;
    p01: number | null;
    p05: number | null;
    p50: number | null;
    p95: number | null;
    max: number | null;
    mean: number | null;
    outOfReach: number;
  };
  contactWhileMoving: MonteCarloProbability;
  stop: MonteCarloProbability;
  chattering: MonteCarloProbability;
  transitionTooSlow: MonteCarloProbability;
  switchesPerSecond: { mean: number; max: number };
  worstTransitionSlack: number | null;
  rows?: MonteCarloRow[];
}

/** A point of the skeleton picked with a ray: DH values usable in `controller.pinned`. */
export interface SkeletonPickResult extends DhPoint {
  /** Index of the skeleton segment. */
  segment: number;
  /** m, from the DH values. */
  position: Vec3;
  /** Along the ray from its origin to its closest approach (m). */
  distance: number;
  /** From the ray to the point (m). */
  offset: number;
  /** Radius of the link's volume there (m). */
  radius: number;
}

// ---- functions ----

export function robotPreset(name: PresetName): RobotSpec;
export function presetNames(): string[];
export function robotFromUrdf(xml: string, options?: UrdfOptions): RobotSpec & { jointNames: string[] };
export function forwardKinematics(robot: RobotInput, q: JointVector): ForwardKinematics;
export function skeleton(robot: RobotInput, q: JointVector): SkeletonResult;
export function controlPoint(robot: RobotInput, q: JointVector, point: DhPoint, rates?: ControlPointRates): ControlPointResult;
export function skeletonPoint(robot: RobotInput, q: JointVector, at: { segment: number; t: number }): DhPoint & { position: Vec3 };
export function distance(a: Primitive, b: Primitive): DistanceResult;
/** A figure's reference point: the point motions move and `moveObstacle` places. */
export function referencePoint(shape: Shape): Vec3;
/** The figure moved by `delta` (m), in the form it was given. */
export function translateShape<S extends Shape>(shape: S, delta: Vec3): S;
/** The human with its `side` hand moved by `delta` (m) from rest: only that arm changes; the animation is dropped. */
export function moveHumanHand(shape: Human, side: 'left' | 'right', delta: Vec3): Human;

export interface TrackOptions {
  format?: 'json' | 'csv';
  layout?: 'coco17' | 'body25' | 'kinect32';
  /** m; default estimated from the limbs. */
  height?: number;
  /** Time constant of the zero-phase jitter filter (s, default 0.03; 0: off). */
  smoothing?: number;
  /** Longest gap filled by interpolation (s, default 0.5). */
  maxGap?: number;
}

export interface TrackReport {
  layout: string;
  frames: number;
  duration: number;
  height: number;
  /** Keypoint positions filled in (interpolated or held). */
  filled: number;
  /** Joint angles clamped into the body's range. */
  clamped: number;
}

/** A recorded keypoint track (JSON or CSV text) as a human that replays it; changes nothing by itself. */
export function importTrack(text: string, options?: TrackOptions): { shape: Human; report: TrackReport };
export function simulate(scenario: Scenario): Trace;
export function exampleScenario(name: string): Scenario;
export function exampleScenarioNames(): string[];
/** `runs` copies of `scenario` with independent sensing seeds, reduced to distributions. */
export function monteCarlo(scenario: Scenario, options: MonteCarloOptions): MonteCarloReport;
/** A block of runs of a study (for a progress bar); merge the rows with `monteCarloMerge`. */
export function monteCarloRuns(scenario: Scenario, options: MonteCarloRunsOptions): MonteCarloRow[];
/** The report of rows 0..n − 1 of one study, in any order. */
export function monteCarloMerge(rows: MonteCarloRow[], options?: { rows?: boolean }): MonteCarloReport;

/** A live simulation; JavaScript owns it: call `free()` when done. */
export class World {
  constructor(scenario: Scenario);
  /** One control step of `dt` seconds, `0 < dt ≤ 0.1`. */
  step(dt: number): void;
  /** `steps` control steps of `dt`. */
  advance(dt: number, steps: number): void;
  readonly time: number;
  readonly eventCount: number;
  /** The state; with `since`, only the events from that index. */
  state(since?: number): WorldState;
  addObstacle(obstacle: Obstacle): void;
  removeObstacle(id: string): void;
  setObstacleShape(id: string, shape: Shape): void;
  /** Clearance (m) between the arm now and `shape`, which is not added (negative: overlap). */
  clearanceTo(shape: Shape): number;
  /** Clearance and switch probability of a figure placed with the arm where it is; `sensing` defaults to the scenario's default. */
  riskAt(shape: Shape, sensing?: SensingError): Risk;
  moveObstacle(id: string, position: Vec3): void;
  setController(partial: Controller): void;
  pick(origin: Vec3, direction: Vec3): PickResult | null;
  /** The skeleton's point under a ray as `{ link, d, a }`, or null when the ray misses the arm. */
  pickSkeleton(origin: Vec3, direction: Vec3): SkeletonPickResult | null;
  reset(): void;
  free(): void;
}
