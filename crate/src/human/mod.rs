//! The interacting human as a skeleton: an articulated body of capsules and
//! a sphere, posed by joint angles and a root pose, moved by keyframes or a
//! motion of the library, with the velocity of every part.
//!
//! The body (height `H`) has sixteen parts ([`PART_NAMES`]): pelvis, torso,
//! neck, head (a sphere), and per side upper arm, forearm, hand, thigh,
//! shin and foot (capsules). Segment lengths and joint heights are
//! fractions of `H` after **Drillis & Contini (1966)**, as tabulated in
//! Winter, *Biomechanics and Motor Control of Human Movement* (4th ed.,
//! fig. 4.1) ([`proportion`]); the radii and the spacing of the hip joints
//! are this crate's own estimates for a clothed adult. Joint ranges
//! ([`JOINTS`]) are the active ranges of motion of healthy adults, rounded.
//!
//! Frames: the root is the floor point between the feet, x forward (the
//! heading), y to the person's left, z up. The pelvis hangs on the root at
//! hip height; the lumbar joint above it turns the trunk (twist, lateral
//! bend, flexion), which carries the neck (twist, flexion) and the
//! shoulders (flexion, abduction, rotation, then the elbow); the hips carry
//! the legs (flexion, abduction, then the knee). All angles are zero
//! standing upright with the arms hanging ([`Pose`] gives the signs).
//!
//! Part velocities are exact: each frame carries its angular velocity and
//! its origin's velocity through the chain (`ω_child = ω + R a q̇`,
//! `v_point = v + ω × (p − o)`), so the protective layer and the time to
//! collision see the speed of the hand that approaches, not the body's.
//!
//! In a scenario a human is the shape `{ "type": "human", position,
//! heading?, height?, reach?, pose?, animation?, partSigma?, vary? }`
//! ([`HumanSpec`]; `partSigma` gives parts their own sensing error, `vary`
//! what a Monte Carlo study draws per run ([`HumanVariation`]); the
//! format is in `docs/scenarios.md`); its parts answer to the obstacle's
//! one id and each is reported as `id:part` (`person:leftForearm`).

mod animation;
mod body;
pub mod library;
mod pose;
mod segments;
mod spec;
pub mod track;
mod vary;

pub use animation::{Animation, Keyframe, MAX_KEYFRAMES, MAX_SHIFT, Sampled};
pub use body::{PART_NAMES, Part, Posed, Root, pose_body, pose_sized, proportion, rotation};
pub use pose::{JOINT_COUNT, JOINTS, JointRange, Pose, joint, joint_index};
pub use segments::{Dims, PLAUSIBLE, Segments, measure};
pub use spec::{AnimationSpec, Human, HumanSpec, MAX_HEIGHT, MAX_PART_SIGMA};
pub use vary::{HumanVariation, MAX_VARY_SPEED};
