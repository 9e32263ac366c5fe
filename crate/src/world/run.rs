//! Running a scenario to its end ([`simulate`]) and the control-step
//! benchmark's world ([`control_step_workload`]).

use super::World;
use crate::avoidance::ControllerConfig;
use crate::distance::PrimitiveSpec;
use crate::scenario::{ObstacleSpec, Scenario, ScenarioError, ShapeSpec, TaskSpec, Trace};

/// Runs `scenario` from `t = 0` to its duration and returns the trace: a
/// sample every `sampleEvery` steps from `t = 0` (`t = k·dt` exactly) and
/// one at `t = duration`, then every event.
///
/// # Errors
/// Whatever [`Scenario::validate`] reports.
///
/// # Example
/// ```
/// use skeleton_avoidance::{scenario, world};
/// let trace = world::simulate(&scenario::example("planar-transition")?)?;
/// assert!(!trace.samples.is_empty());
/// # Ok::<(), skeleton_avoidance::scenario::ScenarioError>(())
/// ```
pub fn simulate(scenario: &Scenario) -> Result<Trace, ScenarioError> {
    let mut world = World::new(scenario.clone())?;
    world.log.keep_all = true;
    let steps = (scenario.duration / scenario.dt).round() as u64;
    let every = scenario.sample_every.max(1) as u64;
    let mut samples = Vec::new();
    // A sample is the state a step acts on: its time and joints, and the
    // clearance to each obstacle posed at that time (read after the step,
    // from the skeleton the step built at the sample's `q`).
    let take = |world: &mut World| {
        world.step(scenario.dt);
        let mut sample = world.sample();
        sample.clearances = world.clearances();
        sample
    };
    for k in 0..steps {
        if k % every == 0 {
            samples.push(take(&mut world));
        } else {
            world.step(scenario.dt);
        }
    }
    // The sample at `t = duration`: one more control step evaluates the
    // state there (clearances, control points); only its sample is kept,
    // not its motion or its events.
    let events = world.log.events.len();
    samples.push(take(&mut world));
    world.log.events.truncate(events);
    Ok(Trace {
        samples,
        events: world.log.events,
    })
}

/// The control-step benchmark's world: `lwr4` following a circular
/// end-effector trajectory among `obstacles` static spheres (radius 5 cm)
/// spread pseudo-randomly (seeded) over a 1.6 × 1.6 × 1.2 m box around it,
/// at 1 kHz. Shared by the criterion bench and the wasm export so both time
/// the same work.
///
/// # Errors
/// None in practice (the scenario is valid by construction).
pub fn control_step_workload(obstacles: usize) -> Result<World, ScenarioError> {
    use crate::distance::SphereSpec;
    let mut rng = crate::rng::Rng::new(11);
    let obstacles = (0..obstacles)
        .map(|k| ObstacleSpec {
            id: format!("o{k}"),
            shape: ShapeSpec::Primitive(PrimitiveSpec::Sphere(SphereSpec {
                center: [
                    rng.range(-0.8, 0.8),
                    rng.range(-0.8, 0.8),
                    rng.range(0.0, 1.2),
                ],
                radius: 0.05,
            })),
            motion: None,
        })
        .collect();
    let points: Vec<[f64; 3]> = (0..=8)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 8.0;
            [
                0.45 + 0.1 * crate::math::cos(a),
                0.1 * crate::math::sin(a),
                0.6,
            ]
        })
        .collect();
    let times = (0..=8).map(|k| 0.5 * f64::from(k)).collect();
    let scenario = Scenario {
        robot: crate::scenario::RobotRef::Preset("lwr4".to_owned()),
        q0: Some(vec![0.0, 0.6, 0.0, -1.2, 0.0, 0.6, 0.0]),
        obstacles,
        task: TaskSpec::Trajectory {
            points,
            times,
            chain: 0,
        }
        .into(),
        controller: ControllerConfig::default(),
        sensing: crate::scenario::SensingConfig::default(),
        dependability: crate::dependability::DependabilityConfig::default(),
        dt: 0.001,
        duration: 4.0,
        sample_every: 1,
        camera: None,
    };
    World::new(scenario)
}
