// Type declarations of the `skeleton-avoidance` npm package, written by hand
// from docs/js-api.md and docs/scenarios.md (wasm-bindgen types plain objects
// as `any`) and checked against what the runtime returns by the package
// layer's tests (tests/package). SI units, radians, z up; quaternions
// [x, y, z, w]; matrices as arrays of rows. Optional fields accept
// `undefined` (for `exactOptionalPropertyTypes`).
/// <reference lib="esnext.disposable" />

export type Vec3 = [number, number, number];
/** Unit quaternion `[x, y, z, w]`. */
export type Quat = [number, number, number, number];
/** A 4×4 homogeneous transform as rows. */
export type Matrix4 = number[][];
/** Joint values: a plain array or a `Float64Array`. */
export type JointVector = number[] | Float64Array;
/** Joint values by name, `{ panda_joint1: 0.1, … }`, for a robot with `jointNames` (every joint named once). */
export type NamedJoints = { [jointName: string]: number };
/** Where `q` / `q0` are taken: an array, a `Float64Array`, or by joint name. */
export type JointInput = JointVector | NamedJoints;

// ---- robots ----

/** The library's presets (`presetNames()` lists the same). */
export type PresetName = 'planar3' | 'lwr4' | 'iiwa14' | 'panda' | 'ur5' | 'dual-arm' | 'stanford';

export interface Pose {
  /** Translation (m); default `[0, 0, 0]`. */
  position?: Vec3 | undefined;
  /** Unit quaternion `[x, y, z, w]`; default identity. */
  rotation?: Quat | undefined;
}

/** Radii of a row's segments (m): one value or `[r0, r1]` from the segment's start to its end. */
export interface SegmentRadii {
  /** The segment along the row's `d` translation. */
  d?: number | [number, number] | undefined;
  /** The segment along the row's `a` translation. */
  a?: number | [number, number] | undefined;
  /** The segment behind the start of the `a` spine (the row's `extension`). */
  extension?: number | [number, number] | undefined;
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
  type?: 'revolute' | 'prismatic' | undefined;
  /** Position limits (rad or m). */
  min?: number | undefined;
  max?: number | undefined;
  /** rad/s or m/s, > 0. */
  maxVelocity?: number | undefined;
  /** rad/s² or m/s², > 0. */
  maxAcceleration?: number | undefined;
  /** rad/s³ or m/s³, > 0. */
  maxJerk?: number | undefined;
  /** N·m or N, > 0. */
  maxTorque?: number | undefined;
  /**
   * Radius of the link's volume (m), or `[r0, r1]` tapered along each segment, or one of these
   * per segment (`d`, `a`, `extension`: the row's spines; one left out gets 0.05); default 0.05.
   */
  radius?: number | [number, number] | SegmentRadii | undefined;
  /** Spine behind the joint (m, ≥ 0): counterbalances, motors. */
  extension?: number | undefined;
  /** The body this row moves (the link and what is fixed to it), in the row's DH frame; needed for dynamics. */
  inertial?: InertialSpec | undefined;
}

/** A body's inertial parameters in a frame it carries (URDF's layout). */
export interface InertialSpec {
  /** kg, finite, ≥ 0. */
  mass: number;
  /** Centre of mass (m); default `[0, 0, 0]`. */
  com?: Vec3 | undefined;
  /** Inertia about the centre of mass (kg·m²), `[ixx, ixy, ixz, iyy, iyz, izz]`: positive semi-definite, principal moments obeying the triangle inequality; default zero. */
  inertia?: [number, number, number, number, number, number] | undefined;
}

export interface BranchSpec {
  name?: string | undefined;
  /** 1-based row whose frame carries the branch; 0 is the base. */
  parent: number;
  /** Rotation `[x, y, z, w]` from the parent frame to the branch's first row. */
  mount?: Quat | undefined;
  joints: JointSpec[];
  tool?: Pose | undefined;
}

/** A robot described by its DH table. */
export interface RobotSpec {
  name?: string | undefined;
  convention: 'standard' | 'modified';
  /** Pose of frame 0 in the world. */
  base?: Pose | undefined;
  joints: JointSpec[];
  /** Transform after the main chain's last row. */
  tool?: Pose | undefined;
  /** Further chains on the same base. */
  branches?: BranchSpec[] | undefined;
  /** One unique name per joint, in the order of `q`. */
  jointNames?: string[] | undefined;
  /** One unique name per link (the link each row moves), in the order of `q`. */
  linkNames?: string[] | undefined;
  /** Pairs of links that never repel each other (an SRDF's `disable_collisions`). */
  selfCollisionExclude?: [LinkRef, LinkRef][] | undefined;
}

/** A link by row index (1-based, 0 the base) or by a name from `linkNames`. */
export type LinkRef = number | string;

/** A spec, `{ preset }` or a preset name. */
export type RobotInput = RobotSpec | { preset: PresetName } | PresetName;

export interface UrdfOptions {
  /** Link the chain ends at; default: the end of the longest movable chain. */
  tip?: string | undefined;
  /** Link the chain starts at (the world frame); default: the root link. */
  base?: string | undefined;
  /** An SRDF document: its `disable_collisions` pairs become `selfCollisionExclude`. */
  srdf?: string | undefined;
  /** Radius (m) per link name instead of its collision geometry; a row takes the largest over the links it moves. */
  radii?: { [linkName: string]: number } | undefined;
  /**
   * Mesh files by path (`robot/meshes/link1.stl`): STL, OBJ, COLLADA, glTF,
   * GLB. Given, the radii are fitted to the links' collision meshes.
   */
  meshes?: Record<string, Uint8Array | ArrayBuffer> | undefined;
}

/** What `importUrdf` did for one joint (one DH row). */
export interface UrdfJointReport {
  name: string;
  /** The links it moves up to the next joint. */
  links: string[];
  /** The radius of its volume (m). */
  radius: number;
  radiusFrom: 'collision' | 'override' | 'default';
  /** Limits the URDF did not give, filled with the documented defaults. */
  defaulted: ('maxVelocity' | 'maxAcceleration' | 'maxJerk' | 'maxTorque')[];
  /** Whether it has position limits (continuous joints have none). */
  positionLimits: boolean;
}

/** What `importUrdf` did besides the spec. */
export interface UrdfReport {
  joints: UrdfJointReport[];
  /** Links of the chain with only meshes or no collision shape. */
  linksWithoutPrimitive: string[];
  /** Joints of the document outside the chain (not imported). */
  outsideChain: string[];
  /** Non-adjacent links overlapping at q = 0 (a simulation starting there stops at once). */
  startContacts: { links: [string, string]; joints: [string, string]; distance: number }[];
}

/** How well volumes cover one link's collision mesh (or the robot's). */
export interface BodyCoverage {
  name: string;
  /** Row whose frame carries the link (0 for the robot as a whole). */
  link: number;
  vertices: number;
  /** Share of vertices inside (0..1). */
  vertexCoverage: number;
  /** Share of the area at most `surfaceTolerance` outside (0..1). */
  surfaceCoverage: number;
  /** Largest distance of a vertex outside (m; ≤ 0 when none). */
  worstOutside: number;
  meshVolume: number;
  volumesVolume: number;
  /** volumesVolume / meshVolume. */
  excess: number;
}

export interface Coverage {
  bodies: BodyCoverage[];
  robot: BodyCoverage;
  /** m. */
  surfaceTolerance: number;
}

/** `fitUrdf`'s result. */
export interface UrdfFit {
  robot: RobotSpec & { jointNames: string[] };
  /** Coverage by the radii imported without meshes; null without a readable mesh. */
  before: Coverage | null;
  /** Coverage by the fitted radii. */
  after: Coverage | null;
  /** One message per mesh not found or not readable, naming it. */
  problems: string[];
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
  /** Which translation of the row the segment spans. */
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
  aRate?: number | undefined;
  dRate?: number | undefined;
}

export interface ControlPointResult {
  position: Vec3;
  /** 3 × n, as rows. */
  jTheta: number[][];
  jA: number[][];
  jD: number[][];
  segment?: number | undefined;
  t?: number | undefined;
  velocity?: Vec3 | undefined;
  jThetaDot?: number[][] | undefined;
  jADot?: number[][] | undefined;
  jDDot?: number[][] | undefined;
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
  /** `rotation` default: identity. */
  | { type: 'box'; center: Vec3; halfExtents: Vec3; rotation?: Quat | undefined }
  | { type: 'convexHull'; points: Vec3[] };

/** Joint angles of a human (rad), any subset; docs/scenarios.md lists the names and ranges. */
export type HumanPose = Partial<Record<
  | 'spineFlexion' | 'spineLateral' | 'spineTwist' | 'neckFlexion' | 'neckTwist'
  | 'leftShoulderFlexion' | 'leftShoulderAbduction' | 'leftShoulderRotation' | 'leftElbow'
  | 'rightShoulderFlexion' | 'rightShoulderAbduction' | 'rightShoulderRotation' | 'rightElbow'
  | 'leftHipFlexion' | 'leftHipAbduction' | 'leftKnee'
  | 'rightHipFlexion' | 'rightHipAbduction' | 'rightKnee'
  | 'leftShoulderElevation' | 'leftShoulderProtraction'
  | 'rightShoulderElevation' | 'rightShoulderProtraction',
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
  heading?: number | undefined;
  height?: number | undefined;
  /** The subject's own segment lengths (default: proportional to `height`; `importTrack` measures them). */
  segments?: Segments | undefined;
  reach?: number | undefined;
  pose?: HumanPose | undefined;
  animation?: HumanAnimation | undefined;
  /** Sensing σ of single parts by part name (m per axis, on top of the obstacle's `sensing`). */
  partSigma?: { [part: string]: number } | undefined;
  /** What a Monte Carlo study draws for this person in each run (docs/monte-carlo.md). */
  vary?: HumanVariation | undefined;
}

/** Ranges `[min, max]` a study draws from, uniformly, per run. */
export interface HumanVariation {
  /** Body height (m). */
  height?: [number, number] | undefined;
  /** The clip's speed (m/s); a `linear` motion is rescaled to it. */
  speed?: [number, number] | undefined;
  /** Motions of the library, one drawn per run. */
  clips?: Array<'reach' | 'wave' | 'walk' | 'bend' | 'stepBack'> | undefined;
  /** One sensing σ for every part (m). */
  partSigma?: [number, number] | undefined;
}

export type Shape = Primitive | Human;

export interface DistanceResult {
  /** Negative by the penetration depth when two solids overlap. */
  distance: number;
  pointA: Vec3;
  pointB: Vec3;
  /** Unit vector with `pointB − pointA = distance × normal`. */
  normal: Vec3;
  /** False when equally close witnesses form a family (the witnesses are then its middle). */
  unique: boolean;
}

// ---- scenarios ----

export type Motion =
  | { type: 'static' }
  | { type: 'linear'; velocity: Vec3 }
  | { type: 'waypoints'; points: Vec3[]; times: number[]; loop?: boolean | undefined }
  | { type: 'circular'; center: Vec3; axis: Vec3; period: number };

export interface Obstacle {
  id: string;
  shape: Shape;
  motion?: Motion | undefined;
}

export type Task =
  | { type: 'hold' }
  | { type: 'goal'; position: Vec3; orientation?: Quat | undefined; chain?: number | undefined }
  | { type: 'trajectory'; points: Vec3[]; times: number[]; chain?: number | undefined }
  /** Eq. 4's task: a point whose DH values slide from `from` to `to` holds `position`. */
  | {
      type: 'point';
      link: number;
      from: { d: number; a: number };
      to: { d: number; a: number };
      start?: number | undefined;
      duration: number;
      position?: Vec3 | undefined;
    }
  /** A path in joint space (e.g. from `planPath`): at `configurations[k]` at `times[k]` s, at rest there, on the straight segments between; the only task, `constraints` avoidance only. */
  | { type: 'joints'; configurations: number[][]; times: number[] };

export interface Controller {
  mode?: 'velocity' | 'torque' | 'clik2' | undefined;
  /** Velocity mode: one-sided constraints in one QP with the tasks (default), the paper's repulsion, or NEO (Haviland & Corke 2021) as a baseline. */
  avoidance?: 'constraints' | 'repulsion' | 'neo' | undefined;
  /** Clearance below which the constraints avoidance pushes the arm away (m; default 0.02, < influenceDistance). */
  safetyBand?: number | undefined;
  /** Further pairs of links left out of the self-collision query. */
  selfCollisionExclude?: [LinkRef, LinkRef][] | undefined;
  selection?: 'pairs' | 'perObstacle' | 'pinned' | undefined;
  pinned?: DhPoint[] | undefined;
  influenceDistance?: number | undefined;
  repulsionGain?: number | undefined;
  maxRepulsionSpeed?: number | undefined;
  transitionTime?: number | undefined;
  jumpThreshold?: number | undefined;
  /** How much closer (m) another segment must come before a perObstacle point leaves its own (default 0). */
  switchHysteresis?: number | undefined;
  activationBand?: number | undefined;
  taskGain?: number | undefined;
  /** One positive weight per joint (eq. 4's W). */
  jointWeights?: number[] | undefined;
  damping?: { epsilon?: number | undefined; lambdaMax?: number | undefined } | undefined;
  torque?: { stiffness?: number | undefined; damping?: number | undefined; jointDamping?: number | undefined; forceGain?: number | undefined } | undefined;
  clik2?: { kp?: number | undefined; kd?: number | undefined } | undefined;
  selfCollision?: boolean | undefined;
  /** Whether a point task subtracts its point's own sliding (eq. 4; default true). */
  movingPointTerms?: boolean | undefined;
  /** The protective layer beneath the repulsion. */
  protective?: {
    enabled?: boolean | undefined;
    safetyDistance?: number | undefined;
    reactionTime?: number | undefined;
    withdrawSpeed?: number | undefined;
    /** `ssm` (default) or `pfl`: ISO/TS 15066 power and force limiting (needs inertial data). */
    mode?: 'ssm' | 'pfl' | undefined;
  } | undefined;
  /** NEO's settings (the `neo` avoidance; defaults from its published example). */
  neo?: NeoSettings | undefined;
}

/** NEO's gains (`controller.neo`); out of range (e.g. `stoppingDistance ≥ influenceDistance`) → an Error naming the field. */
export interface NeoSettings {
  /** Influence distance d_i of the collision dampers (m, > 0; default 0.3). */
  influenceDistance?: number | undefined;
  /** Stopping distance d_s (m, ≥ 0 and < influenceDistance; default 0.05). */
  stoppingDistance?: number | undefined;
  /** Damper gain ξ (m/s, ≥ 0; default 1). */
  damperGain?: number | undefined;
  /** Joint-limit damper: influence angle (rad, > 0; default 0.9), stop angle (≥ 0, < jointInfluence; default 0.05), gain (≥ 0; default 1). */
  jointInfluence?: number | undefined;
  jointStop?: number | undefined;
  jointGain?: number | undefined;
  /** Weight λ_q of the joint velocities (> 0; default 0.01). */
  velocityWeight?: number | undefined;
  /** Weight λ_δ of the task slack, divided by the pose error (> 0; default 1). */
  slackWeight?: number | undefined;
  /** Bound of each slack component (> 0; default 10). */
  slackBound?: number | undefined;
  /** Weight of the manipulability gradient (≥ 0; default 1). */
  manipulabilityGain?: number | undefined;
  /** Gain K of the spatial velocity ν = K e towards the goal (1/s, > 0; default 0.5). */
  taskGain?: number | undefined;
  /** Through the jerk-limited limiter (true) or straight to the joints as published (false, default). */
  limiter?: boolean | undefined;
}

/** `World.controller()`: every field of `Controller` in effect. */
export interface ControllerInEffect extends Controller {
  mode: 'velocity' | 'torque' | 'clik2';
  avoidance: 'constraints' | 'repulsion' | 'neo';
  selection: 'pairs' | 'perObstacle' | 'pinned';
  pinned: DhPoint[];
  influenceDistance: number;
  repulsionGain: number;
  maxRepulsionSpeed: number;
  transitionTime: number;
}

/** Sensing model of one obstacle (docs/scenarios.md, Sensing); every field ≥ 0, absent = 0. */
export interface SensingError {
  /** Bound of the error redrawn every step (m). */
  bound?: number | undefined;
  /** Bound of the fixed offset drawn once per run (m). */
  biasBound?: number | undefined;
  /** White Gaussian standard deviation per axis (m). */
  sigma?: number | undefined;
  /** Stationary standard deviation of the Gauss–Markov noise per axis (m). */
  correlatedSigma?: number | undefined;
  /** Time constant of the correlated noise (s; default 0.1). */
  correlationTime?: number | undefined;
  /** Age of the sensed pose (s). */
  latency?: number | undefined;
  seed?: number | undefined;
}

export interface Dependability {
  switchWindow?: number | undefined;
  maxSwitches?: number | undefined;
  onChattering?: 'stop' | 'lock' | undefined;
  lockTime?: number | undefined;
  maxDeceleration?: number | undefined;
  /** Switch probability above which `switchRisk` is raised, in (0, 1]; default 0.05. */
  switchRisk?: number | undefined;
}

export interface Scenario {
  /** A spec or `{ preset }` (a bare preset name is for the functions taking `RobotInput`, not for scenarios). */
  robot: RobotSpec | { preset: PresetName };
  q0?: JointInput | undefined;
  obstacles: Obstacle[];
  /** One task, or a list with at most one per chain. */
  task?: Task | Task[] | undefined;
  controller?: Controller | undefined;
  /** `default` and obstacle ids. */
  sensing?: { [obstacleIdOrDefault: string]: SensingError } | undefined;
  dependability?: Dependability | undefined;
  dt: number;
  duration: number;
  sampleEvery?: number | undefined;
  /** How viewers should look at it (the simulation ignores it; the playground and the element apply it on load). */
  camera?: ScenarioCamera | undefined;
}

/**
 * A scenario's view: a direction and the points a fit keeps on screen, not a
 * fixed eye, so that it holds at any size and aspect.
 */
export interface ScenarioCamera {
  /** Azimuth of the eye about z (rad; 0: on the +x side, π/2: on the +y side; default −0.6). */
  yaw?: number | undefined;
  /** Elevation of the eye (rad, within ±1.55; default 0.5). */
  pitch?: number | undefined;
  /** World points (m) that `fit` keeps on screen besides the robot and the obstacles within its reach (at most 64). */
  frame?: Vec3[] | undefined;
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
  sigma?: PointSigma | undefined;
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
  /** s: `k·dt`; the last sample is at `t = duration`. */
  t: number;
  q: number[];
  /** Joint velocities at `t` (rad/s or m/s). */
  qdot: number[];
  /** Clearance (m) from the arm at `q` to each obstacle at its true pose at `t` (a person posed), by id, within reach or not; self pairs apart. */
  clearances: { [obstacleId: string]: number };
  minClearance: number | null;
  controlPoints: TraceControlPoint[];
  /** Standard deviation of each joint's command from the sensing errors (absent when sensed exactly). */
  commandSigma?: number[] | undefined;
}

/** What `World.riskAt` returns: one cell of a risk map. */
export interface Risk {
  /** m; null for a robot without segments. */
  clearance: number | null;
  /** Probability that the closest segment, as sensed, differs from the ideal one. */
  switchProbability: number;
  segment?: number | undefined;
  alternative?: number | undefined;
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
  segment?: number | undefined;
  alternative?: number | undefined;
  /** A human with `partSigma`, or a streamed human with a stale part: each part's margin (m), by part name. */
  partMargins?: { [part: string]: number } | undefined;
  /** A streamed human (`pushHumanFrame`): each part without a good frame, with the age of its data (s). */
  stale?: { [part: string]: number } | undefined;
}

/** Every event: its time (s) and its kind's fields (docs/scenarios.md, Events). */
export type TraceEvent = { t: number } & (
  /** A control point's selected point moved to another segment. */
  | { kind: 'segmentSwitch'; obstacle: string; from: number; to: number }
  /** A control point started travelling along the skeleton (`duration`: s). */
  | { kind: 'transitionStart'; obstacle: string; from: number; to: number; duration: number; replan: boolean }
  | { kind: 'transitionEnd'; obstacle: string; segment: number }
  /** The sensing error can switch the closest segment (`gap`, `margin`: m). */
  | { kind: 'switchRisk'; obstacle: string; segment: number; alternative: number; gap: number; margin: number; probability: number }
  | { kind: 'chattering'; obstacle: string; switches: number }
  | { kind: 'stop'; reason: string }
  | { kind: 'resume' }
  /** A control point held on one segment until `until` (s). */
  | { kind: 'lock'; obstacle: string; segment: number; until: number }
  | { kind: 'unlock'; obstacle: string }
  /** The protective layer cannot keep a pair's approach stoppable (`distance`: m, `excess`: m/s). */
  | { kind: 'unavoidable'; obstacle: string; segment: number; distance: number; excess: number }
  /** A streamed person's part without a good frame for `age` s (when it turns stale at 0.1 s, then at each doubling); its margin (m) has grown to `margin`. */
  | { kind: 'staleSensing'; obstacle: string; part: string; age: number; margin: number }
  /** Times in s. */
  | { kind: 'transitionTooSlow'; obstacle: string; timeToCollision: number; remaining: number; braking: number; slowdown: number }
  /** At the start the arm overlaps something: the deepest pair (`distance` ≤ 0, m) by link name, and how many pairs overlap. */
  | { kind: 'startContact'; obstacle: string; link: string; distance: number; pairs: number }
);

export type EventKind = TraceEvent['kind'];

/** The event of one kind: `EventOf<'stop'>` is `{ t, kind: 'stop', reason }`. */
export type EventOf<K extends EventKind> = Extract<TraceEvent, { kind: K }>;

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
  target?: DhPoint | undefined;
  /** The DH table of its shorter manipulator, one `{ d, a }` per row (fig. 5). */
  table: { d: number; a: number }[];
  /** The arm's effective mass at the point towards its obstacle, `(uᵀ J M⁻¹ Jᵀ u)⁻¹` (kg); absent without inertial data and where no joint moves the point that way. */
  effectiveMass?: number;
}

/** An ISO/TS 15066 body region (Annex A). */
export type BodyRegion =
  | 'skull' | 'face' | 'neck' | 'backShoulders' | 'chest' | 'abdomen' | 'pelvis'
  | 'upperArm' | 'forearm' | 'hand' | 'thigh' | 'lowerLeg';

/** `WorldState.protection`: the bound in force for the human part nearest the arm. */
export interface ProtectionState {
  /** `id:part`. */
  part: string;
  region: BodyRegion;
  /** Which bound holds the arm's approach. */
  active: 'ssm' | 'pfl';
  /** Clearance (m). */
  distance: number;
  /** Separation monitoring's bound on the approach (m/s). */
  ssmBound: number;
  /** In `pfl` where the region allows transient contact: the arm's effective mass (kg) and the permissible speed (m/s). */
  contact?: { region: BodyRegion; armMass: number; speed: number };
}

export interface WorldState {
  t: number;
  q: number[];
  qdot: number[];
  qddot: number[];
  minClearance: number | null;
  /** The human part at `minClearance`, `id:part`; absent when that pair is not a human's. */
  closestPart?: string;
  /**
   * The human part nearest the arm, `id:part`, and its clearance (m), even when
   * another pair (two of the arm's own links, another obstacle) is closer;
   * absent when no human is within reach.
   */
  closestHuman?: { part: string; distance: number };
  skeleton: { nodes: Vec3[]; segments: SkeletonSegment[] };
  obstacles: { id: string; shape: Shape; parts: Primitive[] }[];
  controlPoints: StateControlPoint[];
  uncertainty: ObstacleUncertainty[];
  /** The controller's command of the last step, before the protective layer and the limits. */
  command: number[];
  commandSigma?: number[] | undefined;
  events: TraceEvent[];
  /** The drive torques of the last step, `M q̈ + C q̇ + g` (N·m or N); empty without inertial data. */
  torque: number[];
  timeToCollision?: number | undefined;
  stopped: boolean;
  /** The protective bound in force for the human part nearest the arm (absent with none within reach). */
  protection?: ProtectionState;
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
  seed?: number | undefined;
  /** Keep every run's row in the report (default false). */
  rows?: boolean | undefined;
}

/** Options of `monteCarloRuns`: runs `from .. from + count − 1` of a study. */
export interface MonteCarloRunsOptions {
  seed?: number | undefined;
  /** First run (default 0). */
  from?: number | undefined;
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
  rows?: MonteCarloRow[] | undefined;
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
export function presetNames(): [PresetName, ...PresetName[]];
export function robotFromUrdf(xml: string, options?: UrdfOptions): RobotSpec & { jointNames: string[] };
export function fitUrdf(xml: string, options: UrdfOptions): UrdfFit;
/** `robotFromUrdf`'s spec and a report of what was read, defaulted and left out. */
export function importUrdf(xml: string, options?: UrdfOptions): { robot: RobotSpec & { jointNames: string[] }; report: UrdfReport };
export function forwardKinematics(robot: RobotInput, q: JointInput): ForwardKinematics;
export function skeleton(robot: RobotInput, q: JointInput): SkeletonResult;
export function controlPoint(robot: RobotInput, q: JointInput, point: DhPoint, rates?: ControlPointRates): ControlPointResult;
export function skeletonPoint(robot: RobotInput, q: JointInput, at: { segment: number; t: number }): DhPoint & { position: Vec3 };
/** Options of `inverseDynamics`. */
export interface DynamicsOptions {
  /** m/s², world frame; default `[0, 0, -9.81]`. */
  gravity?: Vec3 | undefined;
}
/** Joint torques (N·m) and forces (N) `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` (recursive Newton–Euler); every row needs `inertial`. */
export function inverseDynamics(robot: RobotInput, q: JointInput, qdot: JointInput, qddot: JointInput, options?: DynamicsOptions): Float64Array;
/** The joint-space mass matrix `M(q)`, n × n as rows (composite rigid bodies); every row needs `inertial`. */
export function massMatrix(robot: RobotInput, q: JointInput): number[][];
export function distance(a: Primitive, b: Primitive): DistanceResult;
/** A figure's reference point: the point motions move and `moveObstacle` places. */
export function referencePoint(shape: Shape): Vec3;
/** The figure moved by `delta` (m), in the form it was given. */
export function translateShape<S extends Shape>(shape: S, delta: Vec3): S;
/** The human with its `side` hand moved by `delta` (m) from rest: only that arm changes; the animation is dropped. */
export function moveHumanHand(shape: Human, side: 'left' | 'right', delta: Vec3): Human;

/** Keypoint layouts of tracks and sensor frames (BlazePose: MediaPipe's 33 landmarks). */
export type KeypointLayout = 'coco17' | 'body25' | 'kinect32' | 'blazepose33';

/** A subject's segment lengths (m), joint centre to joint centre; each within 0.7–1.4 times Drillis & Contini's value at the body's height. */
export interface Segments {
  upperArm: number;
  forearm: number;
  thigh: number;
  shank: number;
  shoulderWidth: number;
  hipWidth: number;
  /** Middle of the hip joints to the middle of the shoulder joints, standing upright. */
  trunk: number;
}

/** One frame of a sensed person for `World.pushHumanFrame`. */
export interface HumanFrame {
  /** When the keypoints were seen (s, the world's clock; after the previous frame's). */
  t: number;
  layout: KeypointLayout;
  /** `[x, y, z]` in metres, world frame, z up, in the layout's order (its count exactly, at most 10⁴). */
  keypoints: Vec3[];
  /** Per keypoint, in [0, 1]; below 0.5 the keypoint holds its last good position and the parts it places go stale. */
  confidence?: number[] | undefined;
}

export interface TrackOptions {
  /** Default: JSON when the text starts with `{`, BVH when it starts with `HIERARCHY`, else CSV. */
  format?: 'json' | 'csv' | 'bvh';
  /** Keypoint layout of JSON and CSV (not used for BVH). */
  layout?: KeypointLayout;
  /** Metres per unit of the file (default 1; BVH 0.01, centimetres). */
  scale?: number;
  /** The file's up axis (default 'z'; BVH 'y'). */
  up?: 'z' | 'y';
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
  /** The subject's segment lengths, measured from the recording. */
  segments?: Segments | undefined;
  /** Per joint (`leftWrist`, `rightAnkle`, …): distance (m) between the body's joint and the recorded one over the frames. */
  fitError: { [joint: string]: { p95: number; max: number } };
}

/** A recorded keypoint track (JSON or CSV text) or BVH motion capture as a human that replays it; changes nothing by itself. */
export function importTrack(text: string, options?: TrackOptions): { shape: Human; report: TrackReport };
export function simulate(scenario: Scenario): Trace;
export function exampleScenario(name: string): Scenario;
export function exampleScenarioNames(): string[];

/** A reach problem set: NEO's 198 PR2 problems, 100 seeded Panda problems, MotionBenchMaker's 700 Panda problems. */
export type ReachSet = 'pr2' | 'panda' | 'mbm';
/** One reach problem: the scenario (opens in the playground as it is), the goal pose of the end effector (`orientation` [x, y, z, w]), and the goal configuration where the set has one. */
export interface ReachProblem {
  name: string;
  scenario: Scenario;
  goal: { position: Vec3; orientation: Quat };
  goalQ?: number[] | undefined;
}
/**
 * The problems of a set, the same as Rust's `reach::problems(set)`; fresh objects on every call.
 * Plain JS over the package's `problems/<set>.json` (nothing in the wasm module): Node reads the file;
 * in a browser pass it as `data` (fetched and parsed). An unknown set throws `set: unknown problem set 'x' (pr2, panda, mbm)`.
 */
export function reachProblems(set: ReachSet, data?: unknown): ReachProblem[];
/** Options of `planPath`; every field optional. */
export interface PlanOptions {
  seed?: number | undefined;
  /** Clearance kept beyond the controller's safety band (m; default 0.005). */
  extraClearance?: number | undefined;
  /** Clearance kept between two of the arm's links (m; default 0.005). */
  selfClearance?: number | undefined;
  /** Longest step of a search tree, in metres any point of the arm moves (default 0.15). */
  step?: number | undefined;
  /** Rounds of RRT-Connect before giving up (default 4000, at most 1e6). */
  rounds?: number | undefined;
  /** Random shortcut attempts, each kept only if the path then takes less time (default 200). */
  shortcuts?: number | undefined;
  /** Each segment's duration over the shortest the joint limits allow (≥ 1; default 1: none to spare). */
  timeScale?: number | undefined;
}
/** A timed joint-space path: follow it with `{ type: 'joints', configurations, times }`. */
export interface Plan {
  configurations: number[][];
  times: number[];
  /** How many of the first configurations escape a start closer than the thresholds. */
  escape: number;
  /** The clearances every certified segment keeps (m). */
  thresholds: { obstacles: number; selfPairs: number };
  evaluations: number;
}
/** A path from `scenario.q0` to `goalQ` among the obstacles at t = 0, every segment certified clear of them by the safety band plus `extraClearance`, timed within the joints' limits. */
export function planPath(scenario: Scenario, goalQ: number[], options?: PlanOptions): Plan;
/** `runs` copies of `scenario` with independent sensing seeds, reduced to distributions. */
export function monteCarlo(scenario: Scenario, options: MonteCarloOptions): MonteCarloReport;
/** A block of runs of a study (for a progress bar); merge the rows with `monteCarloMerge`. */
export function monteCarloRuns(scenario: Scenario, options: MonteCarloRunsOptions): MonteCarloRow[];
/** The report of rows 0..n − 1 of one study, in any order. */
export function monteCarloMerge(rows: MonteCarloRow[], options?: { rows?: boolean | undefined }): MonteCarloReport;

/** A live simulation; JavaScript owns it: call `free()` when done. */
export class World {
  constructor(scenario: Scenario);
  /** One control step of `dt` seconds, `0 < dt ≤ 0.1`. */
  step(dt: number): void;
  /** `steps` control steps of `dt`. */
  advance(dt: number, steps: number): void;
  /** Simulated time (s): `k·dt` after k equal steps (no rounding drift). */
  readonly time: number;
  readonly eventCount: number;
  /** Joint values now (rad or m): a cheap read, without the whole state. */
  q(): Float64Array;
  /** Joint velocities now (rad/s or m/s). */
  qdot(): Float64Array;
  /**
   * Clearance (m) between the arm and obstacle `id` where the last step measured its control points:
   * the arm at the `q` that step acted on, the obstacle (a person posed) at that step's time
   * (negative: overlap; Infinity for a robot without segments).
   */
  clearance(id: string): number;
  /** The controller configuration in effect, the library's defaults filled in. */
  controller(): ControllerInEffect;
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
  /**
   * One frame of a sensed person into human obstacle `obstacleId`, fitted as `importTrack` fits a track; the human is
   * then seen at the world's time less its sensing latency. A part without a good frame for `age` s grows its margin by
   * `age × 2.0 m/s` (hands) or `1.6 m/s` (the rest). Throws naming the field (`obstacleId`, `frame.t`, `frame.layout`,
   * `frame.keypoints[3][1]`, `frame.confidence[2]`); a refused frame changes nothing.
   */
  pushHumanFrame(obstacleId: string, frame: HumanFrame): void;
  /**
   * The sensing latency of obstacle `obstacleId` (s, in [0, 2]): it is seen that long ago, and a streamed person's frames
   * are aged from the world's time less it (a live feed sets its measured capture-to-step latency). Kept in the
   * scenario's `sensing`. Throws naming the field (`obstacleId`, `latency`); a refused edit changes nothing.
   */
  setSensingLatency(obstacleId: string, latency: number): void;
  reset(): void;
  free(): void;
  /** `free()`, for `using world = new World(…)`. */
  [Symbol.dispose](): void;
}

// ---- the renderer (browsers only) ----

/** Options of `Viewer.create`. */
export interface ViewerOptions {
  /** Default `"auto"`: WebGPU when the browser has an adapter, else WebGL2. */
  backend?: 'auto' | 'webgpu' | 'webgl2' | undefined;
  /** Default `"auto"`: the top view for a planar robot, else 3D. */
  view?: ViewName | undefined;
  /** 4× multisampling; by default on unless the adapter is a software rasteriser. */
  antialias?: boolean | undefined;
  /**
   * Default false. Draw through the canvas's OffscreenCanvas
   * (`transferControlToOffscreen`), which the browser composites more
   * cheaply; the canvas then belongs to the viewer (no other context, its
   * size set by `resize` only, no second viewer on it). Ignored where the
   * browser cannot hand a canvas over (`ViewerState.offscreenCanvas`).
   */
  offscreen?: boolean | undefined;
}

export type ViewName = 'auto' | '3d' | 'top' | 'front' | 'side';

/** What a viewer draws (missing fields keep their defaults). */
export interface ViewerDisplay {
  /** Default true. */
  volumes?: boolean | undefined;
  /** Default true. */
  nodes?: boolean | undefined;
  /** Default false. */
  axes?: boolean | undefined;
  /** Default true. */
  grid?: boolean | undefined;
  /** Metres of repulsion arrow per m/s (default 0.4). */
  arrowScale?: number | undefined;
}

/** `Viewer.state()`: a snapshot for tests and tools. */
export interface ViewerState {
  backend: 'webgpu' | 'webgl2';
  adapter: string;
  surfaceFormat: string;
  sampleCount: number;
  /** Whether the canvas is drawn through its OffscreenCanvas (`ViewerOptions.offscreen`). */
  offscreenCanvas: boolean;
  /** Triangles the last upload draws (grid hairlines not counted). */
  triangles: number;
  /** Triangles of the capsules and spheres at their level of detail, back faces included. */
  solidTriangles: number;
  /** Frames presented so far. */
  framesDrawn: number;
  /** Frames left out because their scene and camera were those on screen. */
  framesUnchanged: number;
  view: Exclude<ViewName, 'auto'>;
  /** Eye azimuth and elevation (rad), distance to the target (m), the target (m, world frame). */
  camera: { yaw: number; pitch: number; distance: number; target: Vec3 };
  width: number;
  height: number;
  dof: number;
  q: number[];
  /** Skeleton nodes (m, world frame). */
  nodes: Vec3[];
  /** The same nodes in drawing-buffer pixels from the top-left corner (null: behind the eye). */
  screenNodes: ([number, number] | null)[];
}

/** The canvas a viewer draws on: an `HTMLCanvasElement` (named structurally so Node programs need no DOM types). */
export interface ViewerCanvas {
  width: number;
  height: number;
  readonly clientWidth: number;
  readonly clientHeight: number;
}

/**
 * A canvas drawing a robot's skeleton, a world's obstacles, control points and
 * repulsion through WebGPU or WebGL2. Browsers only: in Node, `Viewer.create`
 * rejects and the constructor throws. Call `free()` when done.
 */
export class Viewer {
  private constructor();
  /** Starts a viewer on `canvas`; rejects naming the reason when neither WebGPU nor WebGL2 is available. */
  static create(canvas: ViewerCanvas, options?: ViewerOptions): Promise<Viewer>;
  /** `"webgpu"` or `"webgl2"`. */
  readonly backend: 'webgpu' | 'webgl2';
  /** Number of joints of the current robot (0 before `setRobot`). */
  readonly dof: number;
  /** The current view's name. */
  readonly view: Exclude<ViewName, 'auto'>;
  setRobot(robot: RobotInput): void;
  /** Sets the robot from a URDF and draws its collision meshes; the result is `fitUrdf`'s (give `result.robot` to `new World`). */
  setUrdf(xml: string, options: UrdfOptions): UrdfFit;
  /** Draws a URDF's collision meshes on the current robot, which must be the same arm (a preset): throws when its tip strays from the robot's last frame. */
  setMeshesFromUrdf(xml: string, options: UrdfOptions): { problems: string[] };
  /** Draws a `World.state()`-shaped object (other fields are ignored). */
  drawState(state: Pick<WorldState, 'skeleton'> & Partial<WorldState>): void;
  /** Draws a live world (nothing is copied through JS); call once per frame after stepping. */
  drawWorld(world: World): void;
  /** Highlights the obstacle with this id (null or undefined: none). */
  setSelected(id: string | null | undefined): void;
  /** Where a world point lands on the canvas (drawing-buffer pixels), or null behind the eye. */
  projectPoint(point: Vec3): [number, number] | null;
  /** Unit vector from the eye towards the target (world frame). */
  viewDirection(): number[];
  setJoints(q: JointVector): void;
  setDisplay(display: ViewerDisplay): void;
  setView(name: ViewName): void;
  /** Applies a scenario's `camera` (after `setRobot`, which resets it; before `fit`, which frames its points). */
  setCamera(camera: ScenarioCamera): void;
  orbit(dx: number, dy: number): void;
  pan(dx: number, dy: number): void;
  /** Multiplies the camera distance by `factor` (> 1 zooms out). */
  zoom(factor: number): void;
  /** Frames the robot and the obstacles it can reach so they fill `fill` of the view (default 0.6), below the top `top` pixels. */
  fit(fill?: number, top?: number): void;
  /** Drawing-buffer size in pixels (CSS size × devicePixelRatio). */
  resize(width: number, height: number): void;
  /** Draws one frame when anything changed; call it from requestAnimationFrame. */
  render(): void;
  /** The picking ray through a canvas pixel (world frame, unit direction). */
  rayAt(x: number, y: number): { origin: Vec3; direction: Vec3 };
  state(): ViewerState;
  free(): void;
  /** `free()`, for `using viewer = await Viewer.create(…)`. */
  [Symbol.dispose](): void;
}
