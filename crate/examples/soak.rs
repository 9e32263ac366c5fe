//! Soak: millions of control steps of the `human-panda` example in one
//! [`World`], checking every step for non-finite numbers and the process's
//! resident memory for growth.
//!
//! The person walks to the table and back forever (the example's waypoints,
//! looped there and back), so the avoidance, transitions and the monitor keep
//! working for the whole run rather than settling once the scripted six
//! seconds are over.
//!
//! ```sh
//! cargo run --release --example soak -- [steps]     # default 10 000 000
//! ```
//!
//! Prints the steps per second and the resident set size (RSS, from
//! `/proc/self/status`, Linux only) at the start, every tenth of the run and
//! the end; exits with status 1 when a number goes non-finite or the RSS of
//! the second half grows by more than [`MAX_GROWTH_KB`].

use std::error::Error;
use std::time::Instant;

use skeleton_avoidance::scenario::{self, Motion};
use skeleton_avoidance::world::{World, WorldState};

/// Largest RSS growth (KiB) allowed between the middle and the end of the run.
const MAX_GROWTH_KB: u64 = 1024;

/// Steps between two full checks of the state (the joints are checked at
/// every step).
const CHECK_EVERY: u64 = 1000;

fn main() -> Result<(), Box<dyn Error>> {
    let steps: u64 = match std::env::args().nth(1) {
        Some(s) => s.replace('_', "").parse()?,
        None => 10_000_000,
    };
    let mut world = soak_world()?;
    let dt = world.scenario().dt;
    println!("soak (native): human-panda, person walking to and fro, {steps} steps of {dt} s");

    let rss0 = rss_kb();
    let mut marks = vec![(0, rss0, 0.0)];
    let tenth = (steps / 10).max(1);
    let start = Instant::now();
    let mut cursor = 0;
    for k in 1..=steps {
        world.step(dt);
        if let Some(bad) = world.q().iter().position(|x| !x.is_finite()) {
            return fail(&format!("step {k}: q[{bad}] = {}", world.q()[bad]));
        }
        if k % CHECK_EVERY == 0 {
            let state = world.state_since(cursor);
            cursor = world.event_count();
            if let Some(bad) = non_finite(&state) {
                return fail(&format!("step {k} (t = {} s): {bad}", state.t));
            }
        }
        if k % tenth == 0 || k == steps {
            marks.push((k, rss_kb(), start.elapsed().as_secs_f64()));
        }
    }
    let secs = start.elapsed().as_secs_f64();

    println!("{:>12}  {:>10}  {:>10}", "step", "RSS (KiB)", "time (s)");
    for (k, rss, t) in &marks {
        let rss = rss.map_or_else(|| "n/a".to_owned(), |r| r.to_string());
        println!("{k:>12}  {rss:>10}  {t:>10.1}");
    }
    #[allow(clippy::cast_precision_loss)]
    let rate = steps as f64 / secs;
    println!(
        "soak (native): {steps} steps in {secs:.1} s ({rate:.0} steps/s), simulated {:.0} s, \
         {} events, no non-finite number",
        world.time(),
        world.event_count()
    );
    let middle = marks.get(marks.len() / 2).and_then(|m| m.1);
    let end = marks.last().and_then(|m| m.1);
    match (rss0, middle, end) {
        (Some(s), Some(m), Some(e)) => {
            println!("soak (native): RSS start {s} KiB, middle {m} KiB, end {e} KiB");
            if e > m + MAX_GROWTH_KB {
                return fail(&format!(
                    "RSS grew by {} KiB in the second half (allowed {MAX_GROWTH_KB})",
                    e - m
                ));
            }
        }
        _ => println!("soak (native): RSS not measured (no /proc/self/status)"),
    }
    Ok(())
}

/// The `human-panda` example with the person's walk looped there and back.
fn soak_world() -> Result<World, Box<dyn Error>> {
    let mut s = scenario::example("human-panda")?;
    let person = s
        .obstacles
        .iter_mut()
        .find(|o| o.id == "person")
        .ok_or("human-panda has no obstacle \"person\"")?;
    let Some(Motion::Waypoints { points, times, .. }) = &person.motion else {
        return Err("the person of human-panda no longer walks through waypoints".into());
    };
    let (first, last) = (points[0], points[points.len() - 1]);
    let (t0, t1) = (times[0], times[times.len() - 1]);
    person.motion = Some(Motion::Waypoints {
        points: vec![first, last, first],
        times: vec![t0, t1, 2.0 * t1 - t0],
        repeat: true,
    });
    Ok(World::new(s)?)
}

/// Where a non-finite number is in `s`, if anywhere.
fn non_finite(s: &WorldState) -> Option<String> {
    let mut named: Vec<(String, f64)> = vec![("t".into(), s.t)];
    let list = |name: &str, xs: &[f64]| -> Vec<(String, f64)> {
        xs.iter()
            .enumerate()
            .map(|(k, x)| (format!("{name}[{k}]"), *x))
            .collect()
    };
    named.extend(list("q", &s.q));
    named.extend(list("qdot", &s.qdot));
    named.extend(list("qddot", &s.qddot));
    named.extend(s.min_clearance.map(|x| ("minClearance".into(), x)));
    named.extend(s.time_to_collision.map(|x| ("timeToCollision".into(), x)));
    for (k, n) in s.skeleton.nodes.iter().enumerate() {
        named.extend(list(&format!("skeleton.nodes[{k}]"), n));
    }
    for (k, c) in s.control_points.iter().enumerate() {
        let p = format!("controlPoints[{k}]");
        named.extend(list(&format!("{p}.position"), &c.position));
        named.extend(list(&format!("{p}.witness"), &c.witness));
        named.extend(list(&format!("{p}.repulsion"), &c.repulsion));
        named.push((format!("{p}.d"), c.d));
        named.push((format!("{p}.a"), c.a));
        named.push((format!("{p}.distance"), c.distance));
    }
    for (k, u) in s.uncertainty.iter().enumerate() {
        named.push((format!("uncertainty[{k}].radius"), u.radius));
    }
    named
        .into_iter()
        .find(|(_, x)| !x.is_finite())
        .map(|(name, x)| format!("{name} = {x}"))
}

/// Resident set size of this process (KiB), where `/proc` tells it.
fn rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn fail(what: &str) -> Result<(), Box<dyn Error>> {
    eprintln!("soak (native): FAILED: {what}");
    std::process::exit(1)
}
