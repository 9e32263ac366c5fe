//! # skeleton-avoidance
//!
//! The *skeleton algorithm* of De Santis & Siciliano for fast whole-body
//! collision avoidance of robot arms: a skeleton built from the DH table,
//! closed-form distances from its segments to environment primitives, control
//! points described by DH values with their Jacobians (`J_θ`, `J_a`, `J_d`),
//! repulsion turned into joint velocities or torques, smooth control-point
//! transitions, and a dependability monitor.
//!
//! ## Architecture
//!
//! The crate is a pure numerical core with two thin skins, and dependencies
//! point one way: `wasm → render → core` (`view` is core: plain data, tested natively).
//!
//! | module | what it holds | paper |
//! |---|---|---|
//! | [`kinematics`] | DH robots (standard and modified, several chains on one base), each row's inertial parameters, presets (with published inertial data), the DH table from joint axes (for the URDF reader), forward kinematics, end-effector IK (6-D CLIK) | §II, §III |
//! | [`dynamics`] | rigid-body dynamics of a robot whose rows carry inertial parameters (presets, URDF `<inertial>` or by hand), recursive Newton–Euler inverse dynamics, the mass matrix (factored for forward dynamics and effective masses), gravity and Coriolis terms | — |
//! | [`skeleton`] | nodes and tapered segments built from the DH table | §II, fig. 1 |
//! | [`control_point`] | points as DH values `(link, d', a')`, `J_θ`, `J_a`, `J_d` and their time derivatives; first- and second-order CLIK of a moving point (`clik`) | §III-A, eq. 2–4 |
//! | [`transition`] | a control point travelling along the skeleton through the nodes, one quintic per DH value (C2) | §III-B, fig. 5 |
//! | [`avoidance`] | control-point selection, repulsion, velocity / torque (on the robot's own `M(q)`, gravity and Coriolis compensated) / second-order CLIK controllers with task priority and joint weights, the constraints that bring their own QP rows (`rows`: limits and tasks), the QP and its assembler, NEO as a baseline controller (`neo`), the protective layer (separation monitoring, or ISO/TS 15066 power and force limiting) and the jerk-limited joint limiter | §II, §III-A |
//! | [`dependability`] | sensing models, first-order uncertainty propagation, switch probability, chattering (stop or lock, every selection mode), time to collision, events | §IV |
//! | [`human`] | the interacting human: an articulated body of capsules sized by anthropometric proportions, posed by joint angles, keyframes or a motion library, with every part's velocity | §II |
//! | [`scenario`] | scenario and trace types, tasks (one per chain; the sliding `point` task of eq. 4; a joint-space path, `joint_path`), validation with JSON paths, the shipped examples, the motion audit (velocity, acceleration, jerk, torque) | — |
//! | [`world`] | a live simulation: the control step as a pipeline of stages, torque limits held in every motion, obstacle edits, picking, a person streamed from a sensor (stale parts' margins grown at a person's speed), `simulate` | §IV |
//! | [`study`] | Monte Carlo studies: many runs of a scenario with independent sensing seeds, reduced to distributions (clearance quantiles, probabilities of contact, stop, chattering), in parallel with the feature `parallel`, merged from shards | §IV |
//! | [`linalg`] | small dense matrices, symmetric eigen-decomposition, the weighted damped least-squares inverse; depends on nothing else in the crate | §III-A |
//! | [`math`] | transcendental functions (libm) with the same bits natively and in wasm (deterministic traces) | — |
//! | [`distance`] | primitives (`primitive/`: one file per group of figures, `spec.rs` for the JS description), closed-form distances and witnesses, scene query, picking | §II, figs. 2–3 |
//! | [`parsers`] | readers of files: URDF and SRDF, meshes (STL, OBJ, COLLADA, glTF), keypoint tracks (JSON, CSV) and BVH motion capture | — |
//! | [`mesh`] | the triangle mesh (`TriMesh`): scale and origin, bounds, enclosed volume, area, simplification for drawing | — |
//! | [`fitting`] | skeleton volumes fitted to collision meshes, their coverage and excess; a URDF with its mesh files | — |
//! | [`plan`] | global guidance: a joint-space path to a goal configuration (RRT-Connect, segments certified clear by a Lipschitz bound, shortcut, timed within the limits), followed as a `joints` task | — |
//! | [`reach`] | reach problems (NEO's PR2 scenes, seeded Panda problems, MotionBenchMaker's Panda problems) judged by one evaluator, for the reach benchmark; the sets by name as plain data | — |
//! | [`rng`] | a seeded generator (xoshiro256**), the same bits on every target | — |
//! | [`workloads`] | fixed workloads shared by the native and the wasm benchmarks | — |
//! | [`error`] | `FieldError` (a JSON-like path and a reason) and the shared validators | — |
//! | [`view`] | what the viewer shows as plain data: the scene built from a world's state, framing (reach, planar robots), the camera, the viewer's state apart from the GPU | — |
//! | `wasm` (wasm32 only) | the `#[wasm_bindgen]` layer: converts and validates, no logic | — |
//! | `render` (wasm32, feature `render`) | the wgpu renderer of the playground: uploads a [`view::Drawing`] and draws it, nothing else | — |
//!
//! One control step is a pipeline (table in [`world`]): **sense** (obstacles
//! as sensed) → **scene query** (forward kinematics in one pass, skeleton,
//! distances from every segment to nearby obstacles) → **select** (control
//! points as DH values) → **transition** (points travel along the skeleton
//! when the selection jumps) → **monitor** (switch risk, chattering, time to
//! collision) → **control** (repulsion and tasks → requested joint
//! velocities) → **protect** (every pair's approach bounded so the arm can
//! stop before contact) → **limit** (jerk-limited tracking within the
//! joints' velocity, acceleration, jerk and position limits) → **integrate**.
//!
//! ## Conventions
//!
//! SI units, radians, right-handed frames, z up. All numerics are `f64`
//! (glam `DVec3`, `DMat3`, `DAffine3`). Standard DH is
//! `A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)` (Siciliano & Sciavicco); modified DH
//! is `A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)` (Craig). Links and joints
//! are numbered from 1, frame 0 is the base. Quaternions cross the JS boundary
//! as `[x, y, z, w]`, matrices as arrays of rows.
//!
//! Every fallible function returns a typed error whose message names the field
//! and the reason; nothing in the core panics on user input.

#![warn(missing_docs)]

pub mod avoidance;
pub mod control_point;
pub mod dependability;
pub mod distance;
pub mod dynamics;
pub mod error;
pub mod fitting;
pub mod human;
pub mod kinematics;
pub mod linalg;
pub mod math;
pub mod mesh;
pub mod parsers;
pub mod plan;
pub mod reach;
pub mod rng;
pub mod scenario;
pub mod skeleton;
pub mod study;
pub mod transition;
pub mod view;
pub mod workloads;
pub mod world;

#[cfg(all(target_arch = "wasm32", feature = "render"))]
pub mod render;
#[cfg(target_arch = "wasm32")]
mod wasm;

pub use error::FieldError;
