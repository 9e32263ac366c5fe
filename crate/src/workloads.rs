//! Fixed workloads shared by the native benchmarks (criterion) and the wasm
//! benchmarks (Node), so that both measure exactly the same code.

use crate::control_point::{DhPoint, PointJacobians};
use crate::dynamics::{Dynamics, Workspace};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot, presets};
use crate::rng::Rng;
use crate::skeleton::Skeleton;

/// One control step's kinematics for a robot: forward kinematics, skeleton,
/// and the Jacobians `J_θ`, `J_a`, `J_d` of 8 control points spread over the
/// skeleton, at a sequence of configurations.
#[derive(Debug)]
pub struct KinematicsStep {
    robot: Robot,
    configs: Vec<Vec<f64>>,
    frames: Frames,
    skeleton: Skeleton,
    points: Vec<DhPoint>,
    jacobians: Vec<PointJacobians>,
    next: usize,
}

impl KinematicsStep {
    /// The workload for preset `name` with `configs` random configurations.
    ///
    /// # Errors
    /// An unknown preset.
    pub fn new(name: &str, configs: usize) -> Result<Self, FieldError> {
        let robot = Robot::from_spec(&presets::preset(name)?)?;
        let mut rng = Rng::new(1);
        let configs: Vec<Vec<f64>> = (0..configs.max(1))
            .map(|_| robot.joints.iter().map(|_| rng.range(-1.5, 1.5)).collect())
            .collect();
        let frames = robot.forward(&configs[0])?;
        let skeleton = Skeleton::build(&robot, &frames);
        let count = skeleton.segments.len().max(1);
        let points = (0..8)
            .map(|k| {
                let seg = k % count;
                let t = 0.25 + 0.5 * (k / count) as f64 / (8 / count).max(1) as f64;
                DhPoint::from_skeleton(&robot, &frames, &skeleton, seg, t.min(1.0))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let jacobians = vec![PointJacobians::default(); points.len()];
        Ok(Self {
            robot,
            configs,
            frames,
            skeleton,
            points,
            jacobians,
            next: 0,
        })
    }

    /// Runs one step at the next configuration; returns a checksum so that
    /// nothing is optimised away.
    pub fn run(&mut self) -> f64 {
        let q = &self.configs[self.next];
        self.next = (self.next + 1) % self.configs.len();
        if self.robot.forward_into(q, &mut self.frames).is_err() {
            return f64::NAN;
        }
        self.skeleton.build_into(&self.robot, &self.frames);
        let mut sum = self.skeleton.nodes.len() as f64;
        for (p, j) in self.points.iter().zip(self.jacobians.iter_mut()) {
            p.jacobians_into(&self.robot, &self.frames, j);
            sum += j.position.x + j.j_theta[0].y + j.j_a[0].z + j.j_d[0].x;
        }
        sum
    }
}

/// Which dynamics term a [`DynamicsStep`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DynamicsTerm {
    /// Recursive Newton–Euler: `τ = M q̈ + C q̇ + g`.
    InverseDynamics,
    /// The composite-rigid-body mass matrix `M(q)`.
    MassMatrix,
}

/// The dynamics of one control step for a preset with inertial data, at a
/// sequence of random states, with one reused workspace.
#[derive(Debug)]
pub struct DynamicsStep {
    dynamics: Dynamics,
    workspace: Workspace,
    states: Vec<[Vec<f64>; 3]>,
    tau: Vec<f64>,
    mass: Vec<f64>,
    next: usize,
}

impl DynamicsStep {
    /// The workload for preset `name` with `states` random states.
    ///
    /// # Errors
    /// An unknown preset, or one without inertial data.
    pub fn new(name: &str, states: usize) -> Result<Self, FieldError> {
        let dynamics = Dynamics::from_robot(Robot::from_spec(&presets::preset(name)?)?)?;
        let n = dynamics.dof();
        let mut rng = Rng::new(2);
        let mut draw = |s: f64| (0..n).map(|_| rng.range(-s, s)).collect::<Vec<f64>>();
        let states = (0..states.max(1))
            .map(|_| [draw(1.5), draw(1.0), draw(3.0)])
            .collect();
        Ok(Self {
            workspace: dynamics.workspace(),
            tau: vec![0.0; n],
            mass: vec![0.0; n * n],
            dynamics,
            states,
            next: 0,
        })
    }

    /// Computes `term` at the next state; returns a checksum so that
    /// nothing is optimised away.
    pub fn run(&mut self, term: DynamicsTerm) -> f64 {
        let [q, qd, qdd] = &self.states[self.next];
        self.next = (self.next + 1) % self.states.len();
        let ws = &mut self.workspace;
        let done = match term {
            DynamicsTerm::InverseDynamics => {
                self.dynamics
                    .inverse_dynamics(ws, q, (qd, qdd), &mut self.tau)
            }
            DynamicsTerm::MassMatrix => self.dynamics.mass_matrix(ws, q, &mut self.mass),
        };
        match (done, term) {
            (Err(_), _) => f64::NAN,
            (Ok(()), DynamicsTerm::InverseDynamics) => self.tau.iter().sum(),
            (Ok(()), DynamicsTerm::MassMatrix) => self.mass[0] + self.mass[self.mass.len() - 1],
        }
    }
}

/// Simulated time of one run of [`monte_carlo_workload`] (s).
pub const MONTE_CARLO_DURATION: f64 = 2.0;

/// The Monte Carlo benchmark's scenario: the `lwr4-elbow` example (a sphere
/// driven at the elbow while the end effector goes to a goal, 1 kHz) cut
/// to [`MONTE_CARLO_DURATION`], every obstacle sensed with a fixed bias
/// within 1 cm, white noise of 2 mm and correlated noise of 3 mm per axis.
/// Shared by the criterion bench and the wasm export, so that runs per
/// second compare like with like.
///
/// # Errors
/// None in practice (the example is valid).
pub fn monte_carlo_workload() -> Result<crate::scenario::Scenario, crate::scenario::ScenarioError> {
    let mut s = crate::scenario::example("lwr4-elbow")?;
    s.duration = MONTE_CARLO_DURATION;
    s.sensing.default = Some(crate::dependability::SensingSpec {
        bias_bound: Some(0.01),
        sigma: Some(0.002),
        correlated_sigma: Some(0.003),
        ..crate::dependability::SensingSpec::default()
    });
    Ok(s)
}

/// The control step's workload ([`crate::world::control_step_workload`]
/// with `obstacles` spheres) with an articulated human walking to and fro
/// past the arm at 1.5 m/s, arms swinging (sixteen moving parts, each with
/// its own velocity).
///
/// # Errors
/// None in practice (the scene is valid).
pub fn control_step_human_workload(
    obstacles: usize,
) -> Result<crate::world::World, crate::scenario::ScenarioError> {
    let mut w = crate::world::control_step_workload(obstacles)?;
    let person: crate::scenario::ObstacleSpec = serde_json::from_value(serde_json::json!({
        "id": "person",
        "shape": {
            "type": "human", "position": [0.75, -1.5, 0.0], "heading": std::f64::consts::FRAC_PI_2,
            "animation": { "clip": "walk", "speed": 1.5 }
        },
        "motion": { "type": "waypoints", "points": [[0, 0, 0], [0, 3, 0], [0, 0, 0]],
                    "times": [0, 2, 4], "loop": true }
    }))
    .map_err(|e| crate::error::FieldError::new("person", e.to_string()))?;
    w.add_obstacle(person)?;
    Ok(w)
}
