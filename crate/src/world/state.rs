//! What a [`World`] shows after a step: [`WorldState`] for viewers, trace
//! [`Sample`]s for [`super::simulate`].

use serde::Serialize;

use super::World;
use super::parts::State;
use crate::control_point::{DhPoint, DhRow};
use crate::dependability::{Event, PointSigma};
use crate::distance::PrimitiveSpec;
use crate::scenario::{Sample, ShapeSpec, TracePoint, translated};
use crate::skeleton::Skeleton;

/// An active control point in [`WorldState`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ControlPointState {
    /// Position (m).
    pub position: [f64; 3],
    /// Link (1-based).
    pub link: usize,
    /// DH value `d'` (m).
    pub d: f64,
    /// DH value `a'` (m).
    pub a: f64,
    /// Id of the obstacle it answers (`self:<link>` for self-collision,
    /// `pinned:<k>` for a pinned point with no obstacle in reach).
    pub obstacle: String,
    /// The part of a human it answers, as `id:part`
    /// (`person:leftForearm`; absent for other obstacles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<String>,
    /// Measured clearance (m).
    pub distance: f64,
    /// Closest point of the obstacle (m).
    pub witness: [f64; 3],
    /// Repulsion: velocity (m/s) in velocity and `clik2` modes, force (N)
    /// in torque mode.
    pub repulsion: [f64; 3],
    /// Whether it is travelling along the skeleton.
    pub transitioning: bool,
    /// Where it goes while transitioning.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target: Option<DhPoint>,
    /// First-order standard deviations from the sensing error of the
    /// obstacle it answers (absent when that obstacle is sensed exactly;
    /// [`crate::dependability::propagate`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma: Option<PointSigma>,
    /// The DH table of its shorter manipulator, `{ d, a }` per row
    /// ([`DhPoint::table`]); filled when the state is read.
    pub table: Vec<DhRow>,
    /// The arm's effective mass at the point along the unit direction
    /// `u` to the obstacle's witness, `(uᵀ J M⁻¹ Jᵀ u)⁻¹` (kg; filled when
    /// the state is read; absent for a robot without inertial data, and
    /// where no joint moves the point towards the obstacle).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub effective_mass: Option<f64>,
}

/// A skeleton segment in [`WorldState`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SegmentState {
    /// Index of the first node.
    pub from: usize,
    /// Index of the second node.
    pub to: usize,
    /// Link (1-based).
    pub link: usize,
    /// Which translation of the row it spans (`d`, `a` or `extension`).
    pub part: crate::skeleton::SpinePart,
    /// Radius at each end (m).
    pub radius: [f64; 2],
}

/// The skeleton in [`WorldState`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SkeletonState {
    /// Node positions (m).
    pub nodes: Vec<[f64; 3]>,
    /// Segments.
    pub segments: Vec<SegmentState>,
}

/// An obstacle in [`WorldState`]: its figure where it is now (true pose).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObstacleStateOut {
    /// Id.
    pub id: String,
    /// Figure at its current pose.
    pub shape: ShapeSpec,
    /// The primitives it is made of (one, or a human's parts).
    pub parts: Vec<PrimitiveSpec>,
}

/// The sensing uncertainty of one obstacle and what it does to the
/// choice of the closest segment.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Uncertainty {
    /// Obstacle id.
    pub obstacle: String,
    /// Distance uncertainty added to the safety margin (m).
    pub radius: f64,
    /// Standard deviation of the sensed position along any axis (m).
    pub sigma: f64,
    /// Probability that the closest segment, as sensed, differs from the
    /// ideal one (0 when the obstacle is out of reach).
    pub switch_probability: f64,
    /// The closest segment (when within reach).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub segment: Option<usize>,
    /// The likeliest other segment (when there is one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alternative: Option<usize>,
    /// A human with `partSigma`: the margin of each part (m), with its own
    /// σ, by part name; `radius` is their largest.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part_margins: Option<std::collections::BTreeMap<String, f64>>,
    /// A streamed human (`World::push_human_frame`): each part without a
    /// good frame, with the age of its data (s), by part name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stale: Option<std::collections::BTreeMap<String, f64>>,
}

/// The human part nearest the arm ([`WorldState::closest_human`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ClosestHuman {
    /// `id:part`, e.g. `person:leftHand`.
    pub part: String,
    /// Its clearance to the arm's volumes (m, true poses).
    pub distance: f64,
}

/// Everything a viewer needs after a step (serde, camelCase).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorldState {
    /// Time (s).
    pub t: f64,
    /// Joint values.
    pub q: Vec<f64>,
    /// Joint velocities.
    pub qdot: Vec<f64>,
    /// Joint accelerations.
    pub qddot: Vec<f64>,
    /// Smallest clearance (m) between the arm and any obstacle (true poses)
    /// or between non-adjacent links, among pairs within reach.
    pub min_clearance: Option<f64>,
    /// The part of a human at `minClearance`, as `id:part`
    /// (`person:rightHand`; absent when the closest pair is not a human's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closest_part: Option<String>,
    /// The human part nearest the arm and its clearance, among pairs within
    /// reach, even when another pair (two of the arm's own links, another
    /// obstacle) is closer (absent when no human is within reach).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closest_human: Option<ClosestHuman>,
    /// The skeleton at `q`.
    pub skeleton: SkeletonState,
    /// Obstacles at their current pose.
    pub obstacles: Vec<ObstacleStateOut>,
    /// Active control points (of the last step).
    pub control_points: Vec<ControlPointState>,
    /// Obstacles sensed with error: margin, spread, switch probability.
    pub uncertainty: Vec<Uncertainty>,
    /// The controller's joint command of the last step, before the
    /// protective layer and the joint limits (rad/s or m/s; N·m or N in
    /// torque mode).
    pub command: Vec<f64>,
    /// Standard deviation of each joint's command from the sensing errors
    /// (absent when every obstacle is sensed exactly, and with the
    /// `constraints` avoidance, whose command is not a smooth function of
    /// the sensed positions).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub command_sigma: Option<Vec<f64>>,
    /// Events (all so far, or since a cursor).
    pub events: Vec<Event>,
    /// The drive torques of the last step, `M q̈ + C q̇ + g` (N·m or N;
    /// empty for a robot without inertial data).
    pub torque: Vec<f64>,
    /// Smallest time to collision of the last step (s), if any point closes in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_to_collision: Option<f64>,
    /// Whether the monitor is stopping the robot.
    pub stopped: bool,
    /// The protective bound in force for the human part nearest the arm
    /// (`ssm` or `pfl`, its body region; absent with no human within the
    /// influence distance or the protective layer off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protection: Option<super::ProtectionReadout>,
    /// Where the sliding point of each point task is now (m, world frame):
    /// the point of the arm that the task's DH values `(d', a')` move along
    /// its link (paper eq. 4), in the order of the tasks; empty without
    /// point tasks.
    pub sliding_points: Vec<[f64; 3]>,
}

/// The result of [`World::pick`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pick {
    /// Obstacle id.
    pub id: String,
    /// The part of a human it hit (`rightHand`; absent for other obstacles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<String>,
    /// Where the ray meets it (m).
    pub point: [f64; 3],
    /// Distance along the ray (m).
    pub distance: f64,
}

/// The result of [`World::pick_skeleton`]: the point of the skeleton's
/// spine closest to a ray, as DH values of the shorter manipulator (the
/// form `controller.pinned` takes).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SkeletonPick {
    /// Link (1-based DH row; rows of branches follow the main chain).
    pub link: usize,
    /// DH value `d'` (m).
    pub d: f64,
    /// DH value `a'` (m).
    pub a: f64,
    /// Index of the skeleton segment.
    pub segment: usize,
    /// Position of the point (m), computed from the DH values.
    pub position: [f64; 3],
    /// Distance along the ray from its origin to its closest approach (m).
    pub distance: f64,
    /// Distance between the ray and the point (m); at most `radius` plus
    /// [`super::PICK_RADIUS`].
    pub offset: f64,
    /// Radius of the link's volume at the point (m).
    pub radius: f64,
}

/// The body of [`World::state_since`].
pub(super) fn state_since(w: &World, cursor: usize) -> WorldState {
    let sk = &w.data.skeleton;
    let (sigmas, command_sigma) = w.propagation();
    let mut control_points = w.data.readout.points.clone();
    for (c, s) in control_points.iter_mut().zip(sigmas) {
        c.sigma = s;
    }
    for c in &mut control_points {
        let point = DhPoint {
            link: c.link,
            d: c.d,
            a: c.a,
        };
        c.table = point.table(&w.model.robot, &w.data.frames);
    }
    super::dynamics::effective_masses(&w.model, &w.data, &w.state.q, &mut control_points);
    let obstacles = obstacles_out(&w.state);
    WorldState {
        t: w.state.t,
        q: w.state.q.clone(),
        qdot: w.state.motion.qdot.clone(),
        qddot: w.state.motion.qddot.clone(),
        min_clearance: w.data.readout.min_clearance,
        closest_part: w.data.readout.closest_part.clone(),
        closest_human: w
            .data
            .readout
            .closest_human
            .as_ref()
            .map(|(part, distance)| ClosestHuman {
                part: part.clone(),
                distance: *distance,
            }),
        skeleton: skeleton_state(sk),
        obstacles,
        control_points,
        uncertainty: uncertainty_out(&w.state),
        command: w.data.request.clone(),
        command_sigma,
        torque: w.data.dynamics.torque.clone(),
        protection: w.data.readout.protection.clone(),
        events: w
            .log
            .events
            .get(cursor.saturating_sub(w.log.dropped)..)
            .unwrap_or(&[])
            .to_vec(),
        time_to_collision: w.data.readout.time_to_collision,
        stopped: w.state.stop.stopped,
        sliding_points: sliding_points(w),
    }
}

/// The obstacles at their true pose now, with their parts.
fn obstacles_out(state: &State) -> Vec<ObstacleStateOut> {
    state
        .sensed
        .obstacles
        .iter()
        .map(|o| {
            let offset = o.offset(state.t);
            let shape = translated(&o.spec.shape, offset);
            let parts = match (&shape, &o.human) {
                (ShapeSpec::Primitive(p), _) => vec![p.clone()],
                (ShapeSpec::Human(_), Some(h)) => h
                    .posed_at(state.t, offset, glam::DVec3::ZERO)
                    .parts
                    .into_iter()
                    .map(|p| p.shape)
                    .collect(),
                (ShapeSpec::Human(h), None) => h.parts(),
            };
            ObstacleStateOut {
                id: o.spec.id.clone(),
                shape,
                parts,
            }
        })
        .collect()
}

/// The skeleton's nodes and segments.
fn skeleton_state(sk: &Skeleton) -> SkeletonState {
    SkeletonState {
        nodes: sk.nodes.iter().map(|n| n.to_array()).collect(),
        segments: sk
            .segments
            .iter()
            .map(|s| SegmentState {
                from: s.from,
                to: s.to,
                link: s.link,
                part: s.part,
                radius: s.radius,
            })
            .collect(),
    }
}

/// The sensing margin, switch risk and part margins of each obstacle
/// sensed with error.
fn uncertainty_out(state: &State) -> Vec<Uncertainty> {
    state
        .sensed
        .obstacles
        .iter()
        .filter(|o| o.margin > 0.0)
        .map(|o| Uncertainty {
            obstacle: o.spec.id.clone(),
            radius: o.margin,
            sigma: o.covariance.variance_along(glam::DVec3::X).sqrt(),
            switch_probability: o.switch.probability,
            segment: o.switch.segment,
            alternative: o.switch.alternative,
            part_margins: (!o.part_margins.is_empty()).then(|| {
                crate::human::PART_NAMES
                    .iter()
                    .zip(&o.part_margins)
                    .map(|(n, m)| ((*n).to_owned(), *m))
                    .collect()
            }),
            stale: o.stale_ages(),
        })
        .collect()
}

/// Where each point task's sliding point is at the current time.
fn sliding_points(w: &World) -> Vec<[f64; 3]> {
    w.model
        .scenario
        .task
        .as_slice()
        .iter()
        .filter_map(|task| task.point_at(w.state.t))
        .map(|(dh, _)| dh.position(&w.model.robot, &w.data.frames).to_array())
        .collect()
}

/// The body of [`World::sample`].
pub(super) fn sample(w: &World) -> Sample {
    let (sigmas, command_sigma) = w.propagation();
    Sample {
        t: w.data.propagation.t,
        q: w.data.propagation.q.clone(),
        qdot: w.data.propagation.qdot.clone(),
        clearances: std::collections::BTreeMap::new(),
        min_clearance: w.data.readout.min_clearance,
        control_points: w
            .data
            .readout
            .points
            .iter()
            .zip(sigmas)
            .map(|(c, sigma)| TracePoint {
                position: c.position,
                link: c.link,
                d: c.d,
                a: c.a,
                obstacle: c.obstacle.clone(),
                distance: c.distance,
                sigma,
            })
            .collect(),
        command_sigma,
    }
}
