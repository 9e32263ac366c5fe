//! JS bindings of the world contract: `simulate`, the `World` class,
//! `exampleScenario`, `exampleScenarioNames`, `benchControlStep`. Converts
//! and validates only; the work is in [`crate::world`].

use wasm_bindgen::prelude::*;

use super::boundary::{count_arg, guard_class, number_arg, string_arg};
use super::convert::{from_json_at, js_error, object_from_js, point3, refuse_positional, to_js};
use crate::dependability::SensingSpec;
use crate::error::FieldError;
use crate::scenario::{self, ObstacleSpec, Scenario, ScenarioError, ShapeSpec};
use crate::world::{self, World};

pub(super) fn scenario_error(e: &ScenarioError) -> JsError {
    let f = e.field();
    js_error(&FieldError::new(
        f.field.clone(),
        super::convert::plain_reason(&f.reason),
    ))
}

pub(super) fn scenario_from_js(value: JsValue) -> Result<Scenario, JsError> {
    if !value.is_object() {
        return Err(js_error(&FieldError::new("scenario", "expected an object")));
    }
    let mut json = super::boundary::read_json("scenario", &value)?;
    let Some(map) = json.as_object_mut() else {
        return Err(js_error(&FieldError::new("scenario", "expected an object")));
    };
    // `q0` by joint name (`{ panda_joint1: 0.1, … }`) is read once the robot is known.
    let named_q0 = match map.remove("q0") {
        Some(serde_json::Value::Object(q0)) => Some(q0),
        Some(other) => {
            map.insert("q0".to_owned(), other);
            None
        }
        None => None,
    };
    super::convert::check_magnitudes("", &json)?;
    let mut s: Scenario = super::convert::from_json_at("", "scenario", json.clone())?;
    refuse_positional("", &json, &s)?;
    if let Some(q0) = named_q0 {
        let names = s
            .robot
            .spec()
            .map_err(|e| js_error(&e.within("robot")))?
            .joint_names;
        s.q0 = Some(
            super::convert::named_joints("q0", &q0, names.as_deref()).map_err(|e| js_error(&e))?,
        );
    }
    s.validate().map_err(|e| scenario_error(&e))?;
    Ok(s)
}

/// A control step `dt` (s): a number in (0, `MAX_DT`].
fn dt_arg(value: &JsValue) -> Result<f64, JsError> {
    let dt = number_arg("dt", value)?;
    if dt <= 0.0 {
        return Err(js_error(&FieldError::new("dt", "must be > 0")));
    }
    if dt > scenario::MAX_DT {
        return Err(js_error(&FieldError::new(
            "dt",
            format!("must be ≤ {} s", scenario::MAX_DT),
        )));
    }
    Ok(dt)
}

/// Runs a scenario to its duration and returns the trace
/// `{ samples: [{ t, q, minClearance, controlPoints }], events: [{ t, kind, … }] }`.
///
/// # Errors
/// A JS `Error` naming the JSON path and the reason, e.g.
/// `obstacles[2].shape.radius: must be > 0`.
#[wasm_bindgen]
pub fn simulate(scenario: JsValue) -> Result<JsValue, JsError> {
    let s = scenario_from_js(scenario)?;
    if s.duration / s.dt > MAX_SIMULATE_STEPS {
        return Err(js_error(&FieldError::new(
            "duration",
            format!(
                "more than {MAX_SIMULATE_STEPS:e} steps of dt in one simulate call (use a World)"
            ),
        )));
    }
    let trace = world::simulate(&s).map_err(|e| scenario_error(&e))?;
    to_js(&trace)
}

/// The example scenario `name` as a plain object (see `exampleScenarioNames`).
///
/// # Errors
/// `name: unknown example "x" (known: …)`.
#[wasm_bindgen(js_name = exampleScenario)]
pub fn example_scenario(name: JsValue) -> Result<JsValue, JsError> {
    let name = string_arg("name", &name)?;
    let s = scenario::example(&name).map_err(|e| scenario_error(&e))?;
    to_js(&s)
}

/// Names of the shipped example scenarios.
#[wasm_bindgen(js_name = exampleScenarioNames)]
#[must_use]
pub fn example_scenario_names() -> Vec<String> {
    scenario::EXAMPLE_NAMES
        .iter()
        .map(|s| (*s).to_owned())
        .collect()
}

/// Runs `iterations` control steps of the benchmark workload (`lwr4` among
/// `obstacles` static spheres, default 20, at 1 kHz; with `human` true also
/// an articulated human walking past the arm) and returns a checksum.
/// Like the native bench's batches (`benches/control_step.rs`) it builds the
/// workload once and steps it on from call to call, rewound every 4000 steps.
///
/// # Errors
/// `iterations` not an integer in 0..=10000, `obstacles` not one in 0..=1000,
/// `human` not a boolean.
#[wasm_bindgen(js_name = benchControlStep)]
pub fn bench_control_step(
    iterations: JsValue,
    obstacles: JsValue,
    human: JsValue,
) -> Result<f64, JsError> {
    let iterations = count_arg("iterations", &iterations, None, MAX_BENCH_STEPS)?;
    let n = count_arg("obstacles", &obstacles, Some(20), 1000)?;
    let human = match human.as_bool() {
        Some(b) => b,
        None if human.is_undefined() || human.is_null() => false,
        None => return Err(JsError::new("human: expected a boolean")),
    };
    let key = (n, human);
    let mut b = match BENCH_WORLD.take() {
        Some(b) if b.key == key => b,
        _ => {
            let build = if human {
                crate::workloads::control_step_human_workload
            } else {
                world::control_step_workload
            };
            let world = build(n as usize).map_err(|e| scenario_error(&e))?;
            BenchWorld {
                key,
                start: world.clone(),
                world,
                steps: 0,
            }
        }
    };
    let mut sum = 0.0;
    for _ in 0..iterations {
        b.steps += 1;
        if b.steps == 4000 {
            b.world = b.start.clone();
            b.steps = 0;
        }
        b.world.step(0.001);
        sum += b.world.q()[0];
    }
    BENCH_WORLD.set(Some(b));
    Ok(sum)
}

/// `benchControlStep`'s workload: key (obstacles, human), world, start, steps since.
struct BenchWorld {
    key: (u32, bool),
    world: World,
    start: World,
    steps: u32,
}

thread_local! {
    static BENCH_WORLD: std::cell::RefCell<Option<BenchWorld>> =
        const { std::cell::RefCell::new(None) };
}

/// Most iterations one `benchKinematicsStep` call runs (well under a second).
pub(crate) const MAX_BENCH_ITERATIONS: u32 = 100_000;

/// Most control steps one `benchControlStep` call runs.
const MAX_BENCH_STEPS: u32 = 10_000;

/// Most control steps one `simulate` call runs (a few seconds of work).
const MAX_SIMULATE_STEPS: f64 = 1e6;

/// Most obstacles in one World.
const MAX_OBSTACLES: usize = 10_000;

/// Most steps one `advance` call runs.
const MAX_STEPS_PER_CALL: u32 = 100_000;

/// Argument names of the `World` methods, for messages about inputs that
/// cannot be read.
const WORLD_ARGS: &[(&str, &[&str])] = &[
    ("step", &["dt"]),
    ("advance", &["dt", "steps"]),
    ("state", &["since"]),
    ("addObstacle", &["obstacle"]),
    ("removeObstacle", &["id"]),
    ("setObstacleShape", &["id", "shape"]),
    ("clearanceTo", &["shape"]),
    ("clearance", &["id"]),
    ("riskAt", &["shape", "sensing"]),
    ("moveObstacle", &["id", "position"]),
    ("setController", &["controller"]),
    ("pick", &["origin", "direction"]),
    ("pickSkeleton", &["origin", "direction"]),
    ("pushHumanFrame", &["obstacleId", "frame"]),
    ("setSensingLatency", &["obstacleId", "latency"]),
];

/// Guards the `World` class (see `guardClass` in `boundary.js`): called once
/// when the module starts, with a throwaway world.
pub(crate) fn guard_world_class() {
    let Ok(s) = scenario::example("planar-transition") else {
        return;
    };
    let Ok(inner) = World::new(s) else {
        return;
    };
    let instance = JsValue::from(WorldHandle { inner });
    guard_class(&instance, "World", WORLD_ARGS);
    // The throwaway world is freed by the guarded `free()`.
    if let Ok(free) = js_sys::Reflect::get(&instance, &JsValue::from_str("free"))
        && let Some(f) = free.dyn_ref::<js_sys::Function>()
    {
        let _ = f.call0(&instance);
    }
}

/// A live simulation that JavaScript owns: step it, read its state, edit
/// its obstacles and controller; call `free()` when done.
#[wasm_bindgen(js_name = World)]
#[derive(Debug)]
pub struct WorldHandle {
    pub(super) inner: World,
}

impl WorldHandle {
    /// The simulation, for the renderer's `drawWorld` (the playground's
    /// viewer reads it in Rust, so per-frame geometry never crosses to JS).
    #[must_use]
    #[allow(dead_code)]
    pub(crate) fn world(&self) -> &World {
        &self.inner
    }
}

#[wasm_bindgen(js_class = World)]
impl WorldHandle {
    /// A world at `t = 0` for `scenario` (see `docs/scenarios.md`).
    ///
    /// # Errors
    /// The JSON path and the reason of the first bad value.
    #[wasm_bindgen(constructor)]
    pub fn new(scenario: JsValue) -> Result<WorldHandle, JsError> {
        let s = scenario_from_js(scenario)?;
        let inner = World::new(s).map_err(|e| scenario_error(&e))?;
        Ok(Self { inner })
    }

    /// One control step of `dt` seconds.
    ///
    /// # Errors
    /// `dt: must be > 0` (or above 0.1 s, or not finite).
    pub fn step(&mut self, dt: JsValue) -> Result<(), JsError> {
        let dt = dt_arg(&dt)?;
        self.inner.step(dt);
        Ok(())
    }

    /// `steps` control steps of `dt` seconds each (one call per frame).
    ///
    /// # Errors
    /// As `step`; `steps` above 100000.
    pub fn advance(&mut self, dt: JsValue, steps: JsValue) -> Result<(), JsError> {
        let dt = dt_arg(&dt)?;
        let steps = count_arg("steps", &steps, None, MAX_STEPS_PER_CALL)?;
        for _ in 0..steps {
            self.inner.step(dt);
        }
        Ok(())
    }

    /// Simulation time (s).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn time(&self) -> f64 {
        self.inner.time()
    }

    /// Number of events so far (a cursor for `state(since)`).
    #[wasm_bindgen(getter, js_name = eventCount)]
    #[must_use]
    pub fn event_count(&self) -> usize {
        self.inner.event_count()
    }

    /// `{ t, q, qdot, minClearance, skeleton, obstacles, controlPoints,
    /// uncertainty, events, timeToCollision?, stopped }`; `events` holds the
    /// events from number `since` on (pass the last `eventCount` when polling
    /// every frame), or all those kept (the latest 10000 to 20000).
    ///
    /// # Errors
    /// Only if the state cannot be converted (a bug).
    pub fn state(&self, since: JsValue) -> Result<JsValue, JsError> {
        let since = count_arg("since", &since, Some(0), u32::MAX)?;
        to_js(&self.inner.state_since(since as usize))
    }

    /// The joint values now (rad or m), in the order of the robot's joints:
    /// a cheap read for a page that plots them every frame.
    #[must_use]
    pub fn q(&self) -> Vec<f64> {
        self.inner.q().to_vec()
    }

    /// The joint velocities now (rad/s or m/s), in the order of `q`.
    #[must_use]
    pub fn qdot(&self) -> Vec<f64> {
        self.inner.qdot().to_vec()
    }

    /// Clearance (m) between the arm and obstacle `id` where the last step
    /// measured its control points: the arm at the `q` that step acted on,
    /// the obstacle at its true pose (a human posed) at that step's time
    /// (negative: overlap; `Infinity` for a robot without segments).
    ///
    /// # Errors
    /// `id: no obstacle "…"` for an unknown id, or `id` not a string.
    pub fn clearance(&self, id: JsValue) -> Result<f64, JsError> {
        let id = string_arg("id", &id)?;
        self.inner.clearance_of(&id).map_err(|e| scenario_error(&e))
    }

    /// The controller configuration in effect, every field filled in (the
    /// library's defaults for those the scenario omits).
    ///
    /// # Errors
    /// Only if it cannot be converted (a bug).
    pub fn controller(&self) -> Result<JsValue, JsError> {
        to_js(&self.inner.scenario().controller)
    }

    /// Adds an obstacle `{ id, shape, motion? }`.
    ///
    /// # Errors
    /// A bad spec or an id in use; the world is unchanged.
    #[wasm_bindgen(js_name = addObstacle)]
    pub fn add_obstacle(&mut self, spec: JsValue) -> Result<(), JsError> {
        let json: serde_json::Value = object_from_js("obstacle", spec)?;
        let spec: ObstacleSpec = from_json_at("obstacle", "obstacle", json.clone())?;
        refuse_positional("obstacle", &json, &spec)?;
        if self.inner.obstacle_primitives().len() >= MAX_OBSTACLES {
            return Err(js_error(&FieldError::new(
                "obstacle",
                format!("a World holds at most {MAX_OBSTACLES} obstacles"),
            )));
        }
        self.inner
            .add_obstacle(spec)
            .map_err(|e| js_error(&e.field().clone().within("obstacle")))
    }

    /// Removes obstacle `id`.
    ///
    /// # Errors
    /// `id: no obstacle "x"`; the world is unchanged.
    #[wasm_bindgen(js_name = removeObstacle)]
    pub fn remove_obstacle(&mut self, id: JsValue) -> Result<(), JsError> {
        let id = string_arg("id", &id)?;
        self.inner
            .remove_obstacle(&id)
            .map_err(|e| scenario_error(&e))
    }

    /// Replaces the figure of obstacle `id` (a primitive or a human).
    ///
    /// # Errors
    /// An unknown id or a bad figure; the world is unchanged.
    #[wasm_bindgen(js_name = setObstacleShape)]
    pub fn set_obstacle_shape(&mut self, id: JsValue, shape: JsValue) -> Result<(), JsError> {
        let id = string_arg("id", &id)?;
        let shape: ShapeSpec = object_from_js("shape", shape)?;
        self.inner
            .set_obstacle_shape(&id, shape)
            .map_err(|e| scenario_error(&e))
    }

    /// Clearance (m) between the arm as it is now (its segments' volumes)
    /// and the figure `shape` (a primitive or a human), without adding it:
    /// negative when it would overlap the arm. The playground places new
    /// obstacles where this is positive.
    ///
    /// # Errors
    /// A bad figure.
    #[wasm_bindgen(js_name = clearanceTo)]
    pub fn clearance_to(&self, shape: JsValue) -> Result<f64, JsError> {
        let shape: ShapeSpec = object_from_js("shape", shape)?;
        self.inner
            .clearance_to(&shape)
            .map_err(|e| scenario_error(&e))
    }

    /// What an obstacle of figure `shape` would face with the arm where it
    /// is: `{ clearance, switchProbability, segment?, alternative? }`, the
    /// probability that its closest segment, as sensed with `sensing`
    /// (default: the scenario's default sensing), differs from the ideal
    /// one. One cell of a risk map.
    ///
    /// # Errors
    /// A bad figure or sensing spec.
    #[wasm_bindgen(js_name = riskAt)]
    pub fn risk_at(&self, shape: JsValue, sensing: JsValue) -> Result<JsValue, JsError> {
        let shape: ShapeSpec = object_from_js("shape", shape)?;
        let sensing: SensingSpec = if sensing.is_undefined() {
            self.inner.scenario().sensing.default.unwrap_or_default()
        } else {
            object_from_js("sensing", sensing)?
        };
        let risk = self
            .inner
            .risk_at(&shape, &sensing)
            .map_err(|e| scenario_error(&e))?;
        to_js(&risk)
    }

    /// Moves obstacle `id` so that its reference point (centre, middle,
    /// vertex mean, floor point of a human) is at `position` `[x, y, z]`.
    ///
    /// # Errors
    /// An unknown id or a bad position; the world is unchanged.
    #[wasm_bindgen(js_name = moveObstacle)]
    pub fn move_obstacle(&mut self, id: JsValue, position: JsValue) -> Result<(), JsError> {
        let id = string_arg("id", &id)?;
        let p = point3("position", &position)?;
        self.inner
            .set_obstacle_position(&id, p)
            .map_err(|e| scenario_error(&e))
    }

    /// Changes some controller fields (`{ mode: "torque" }`, `{ torque: {
    /// stiffness: 100 } }`, …); the others keep their values.
    ///
    /// # Errors
    /// Unknown fields or bad values, e.g.
    /// `controller.influenceDistance: must be > 0`; the world is unchanged.
    #[wasm_bindgen(js_name = setController)]
    pub fn set_controller(&mut self, partial: JsValue) -> Result<(), JsError> {
        let patch: serde_json::Value = object_from_js("controller", partial)?;
        self.inner
            .update_controller(&patch)
            .map_err(|e| scenario_error(&e))
    }

    /// The first obstacle hit by the ray from `origin` along `direction`:
    /// `{ id, point, distance }` or `null`.
    ///
    /// # Errors
    /// Bad vectors or a zero direction.
    pub fn pick(&self, origin: JsValue, direction: JsValue) -> Result<JsValue, JsError> {
        let o = point3("origin", &origin)?;
        let d = point3("direction", &direction)?;
        match self.inner.pick(o, d).map_err(|e| scenario_error(&e))? {
            Some(p) => to_js(&p),
            None => Ok(JsValue::NULL),
        }
    }

    /// The point of the skeleton the ray from `origin` along `direction`
    /// points at, as DH values of the current configuration:
    /// `{ link, d, a, segment, position, distance, offset, radius }`
    /// (`distance` along the ray, `offset` from the ray to the point, both
    /// m), or `null` when the ray misses every link's volume (by more than
    /// 2 cm). `{ link, d, a }` can be given to `controller.pinned`.
    ///
    /// # Errors
    /// Bad vectors or a zero direction.
    #[wasm_bindgen(js_name = pickSkeleton)]
    pub fn pick_skeleton(&self, origin: JsValue, direction: JsValue) -> Result<JsValue, JsError> {
        let o = point3("origin", &origin)?;
        let d = point3("direction", &direction)?;
        match self
            .inner
            .pick_skeleton(o, d)
            .map_err(|e| scenario_error(&e))?
        {
            Some(p) => to_js(&p),
            None => Ok(JsValue::NULL),
        }
    }

    /// Back to `t = 0` and the initial joints, keeping the edits.
    pub fn reset(&mut self) {
        self.inner.reset();
    }
}
