//! The reach benchmark: NEO's 198 PR2 problems, seeded random Panda
//! problems and MotionBenchMaker's 700 Panda problems, each run to its goal
//! by every controller — the default `constraints`, the paper's
//! `repulsion`, NEO as published and NEO through the limiter — in one run
//! with one evaluator ([`skeleton_avoidance::reach::run`]), reported per
//! scene and per set with both criteria ([`skeleton_avoidance::reach::report`]),
//! timed per control step.
//!
//! `cargo run --release --example reach [-- --panda N] [--seed S] [--only pr2,panda,mbm] [--controllers constraints,repulsion,neo,neo+limiter] [--every K] [--verbose]`
//!
//! `--every K` runs every K-th problem of each set (a quicker look; the
//! report's figures are for the whole sets); `--problems a,b` only the
//! problems named (`pr2/bookshelf/7`).
//!
//! `--pr2-capsules` runs the PR2 set with the arm as imported (three 0.05 m
//! capsules) instead of its fitted volumes. `-- --write-pr2` rewrites the
//! built-in PR2 set (`crate/src/reach/pr2.json`)
//! from the URDF, the meshes and NEO's scenes file.

use std::collections::BTreeMap;
use std::time::Instant;

use skeleton_avoidance::reach::report::{self, Controller};
use skeleton_avoidance::reach::{self, Outcome, Problem};

fn arg(name: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

/// Runs every problem with `controller`: outcomes and µs per step.
fn run_all(
    problems: &[Problem],
    controller: Controller,
    verbose: bool,
) -> Result<Vec<(Outcome, f64)>, Box<dyn std::error::Error>> {
    let mut out = Vec::new();
    for p in problems {
        let t_plan = Instant::now();
        let (p, plan) = controller.guided(p);
        let plan_ms = t_plan.elapsed().as_secs_f64() * 1e3;
        if verbose && let Some(plan) = &plan {
            match plan {
                Ok(plan) => println!(
                    "{:<28} plan: {} configurations ({} escaping), {:.2} s, {} evaluations, {plan_ms:.0} ms",
                    p.name,
                    plan.configurations.len(),
                    plan.escape,
                    plan.times.last().copied().unwrap_or(0.0),
                    plan.evaluations
                ),
                Err(e) => println!("{:<28} plan: none ({e}), {plan_ms:.0} ms", p.name),
            }
        }
        let t0 = Instant::now();
        let o = reach::run(&p)?;
        let us = t0.elapsed().as_secs_f64() * 1e6 / o.steps.max(1) as f64;
        if verbose {
            println!(
                "{:<28} {:<12} {} reached {:>6} neo {:>6} final {:.4} m {:.2}°  clearance {:.4} (start {:.4}, goal {:.4})  q̇ {:.2} q̈ {:.2}{}",
                p.name,
                controller.label(),
                if o.success { "ok  " } else { "FAIL" },
                o.reached.map_or("-".into(), |t| format!("{t:.2}")),
                o.neo_reached.map_or("-".into(), |t| format!("{t:.2}")),
                o.final_error.0,
                o.final_error.1,
                o.audit.clearance,
                o.start_clearance,
                o.goal_clearance.unwrap_or(f64::NAN),
                o.audit.velocity,
                o.audit.acceleration,
                if o.stopped { "  (stopped)" } else { "" }
            );
        }
        out.push((o, us));
    }
    Ok(out)
}

/// Every controller on `problems`, then the report's rows: per scene (the
/// second part of the problems' names) and overall, each controller in
/// turn.
fn report_set(
    label: &str,
    problems: &[Problem],
    controllers: &[Controller],
    verbose: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let band = problems
        .first()
        .map_or(0.02, |p| p.scenario.controller.safety_band);
    let mut runs = Vec::new();
    for &c in controllers {
        runs.push(run_all(problems, c, verbose)?);
    }
    let mut scenes: Vec<&str> = Vec::new();
    for p in problems {
        let scene = p.name.split('/').nth(1).unwrap_or("");
        if !scenes.contains(&scene) {
            scenes.push(scene);
        }
    }
    let scene_of = |p: &Problem| p.name.split('/').nth(1).map(str::to_owned);
    if scenes.len() > 1 {
        for scene in &scenes {
            for (c, r) in controllers.iter().zip(&runs) {
                let set: Vec<&(Outcome, f64)> = problems
                    .iter()
                    .zip(r)
                    .filter(|(p, _)| scene_of(p).as_deref() == Some(scene))
                    .map(|(_, r)| r)
                    .collect();
                println!(
                    "{}",
                    report::line(&format!("{label} {scene}"), *c, &report::row(&set, band))
                );
            }
        }
    }
    for (c, r) in controllers.iter().zip(&runs) {
        let all: Vec<&(Outcome, f64)> = r.iter().collect();
        println!(
            "{}",
            report::line(&format!("**{label}, all**"), *c, &report::row(&all, band))
        );
    }
    Ok(())
}

/// The PR2's collision meshes (`tests/data/meshes/pr2/collision/`), by path.
fn pr2_meshes(data: &str) -> Result<BTreeMap<String, Vec<u8>>, Box<dyn std::error::Error>> {
    let mut files = BTreeMap::new();
    let root = format!("{data}/meshes/pr2/collision");
    for dir in std::fs::read_dir(&root)? {
        for file in std::fs::read_dir(dir?.path())? {
            let path = file?.path();
            let name = path
                .strip_prefix(&root)?
                .to_string_lossy()
                .replace('\\', "/");
            files.insert(name, std::fs::read(&path)?);
        }
    }
    Ok(files)
}

/// The PR2's arm fitted to its meshes, with its coverage printed.
fn pr2_fit(data: &str) -> Result<reach::Pr2Fit, Box<dyn std::error::Error>> {
    let urdf = std::fs::read_to_string(format!("{data}/urdf/pr2.urdf"))?;
    let fit = reach::pr2_fitted_arm(&urdf, &pr2_meshes(data)?)?;
    for (label, c) in [("0.05 m capsules", &fit.before), ("fitted", &fit.after)] {
        let r = &c.robot;
        println!(
            "PR2 arm and gripper, {label}: {:.1} % of {} mesh vertices inside, {:.1} % of the surface within {} mm, worst vertex {:.1} mm outside, volumes {:.2}× the meshes'",
            100.0 * r.vertex_coverage,
            r.vertices,
            100.0 * r.surface_coverage,
            c.surface_tolerance * 1e3,
            r.worst_outside.max(0.0) * 1e3,
            r.excess
        );
    }
    for p in &fit.problems {
        println!("PR2 meshes: {p}");
    }
    if std::env::args().any(|a| a == "--verbose") {
        for (b, a) in fit.before.bodies.iter().zip(&fit.after.bodies) {
            println!(
                "  {:<28} row {}  {:>4} vertices  inside {:5.1} % → {:5.1} %  worst outside {:6.1} → {:4.1} mm  volumes {:.2}× the mesh's",
                b.name,
                b.link,
                b.vertices,
                100.0 * b.vertex_coverage,
                100.0 * a.vertex_coverage,
                b.worst_outside.max(0.0) * 1e3,
                a.worst_outside.max(0.0) * 1e3,
                a.excess
            );
        }
    }
    Ok(fit)
}

/// Rebuilds `crate/src/reach/pr2.json` from the URDF, the meshes and NEO's
/// scenes.
fn write_pr2(data: &str) -> Result<(), Box<dyn std::error::Error>> {
    let scenes = std::fs::read_to_string(format!("{data}/neo/pr2-scenes.json"))?;
    let fit = pr2_fit(data)?;
    let text = reach::pr2_data(&fit.robot, &scenes)?;
    let out = concat!(env!("CARGO_MANIFEST_DIR"), "/src/reach/pr2.json");
    std::fs::write(out, text)?;
    println!("wrote {out}");
    Ok(())
}

/// The MotionBenchMaker problems, scene by scene.
fn mbm(data: &str) -> Result<Vec<Problem>, Box<dyn std::error::Error>> {
    let mut out = Vec::new();
    for scene in reach::mbm::SCENES {
        let text = std::fs::read_to_string(format!("{data}/mbm/{scene}.json"))?;
        out.extend(reach::mbm_problems(&text, scene)?);
    }
    Ok(out)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let verbose = std::env::args().any(|a| a == "--verbose");
    let only = arg("--only");
    let wanted = |set: &str| {
        only.as_deref()
            .is_none_or(|o| o.split(',').any(|s| s == set))
    };
    let controllers: Vec<Controller> = match arg("--controllers") {
        Some(list) => list
            .split(',')
            .map(|c| {
                Controller::parse(c)
                    .ok_or_else(|| format!("--controllers: unknown controller \"{c}\""))
            })
            .collect::<Result<_, _>>()?,
        None => Controller::ALL.to_vec(),
    };
    let every: usize = arg("--every").map_or(Ok(1), |s| s.parse())?;
    let named = arg("--problems");
    let thin = |p: Vec<Problem>| -> Vec<Problem> {
        p.into_iter()
            .step_by(every.max(1))
            .filter(|p| {
                named
                    .as_deref()
                    .is_none_or(|n| n.split(',').any(|n| n == p.name))
            })
            .collect()
    };
    let seed: u64 = arg("--seed").map_or(Ok(reach::PANDA_SEED), |s| s.parse())?;
    let count: usize = arg("--panda").map_or(Ok(reach::PANDA_COUNT), |s| s.parse())?;
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    if std::env::args().any(|a| a == "--write-pr2") {
        return write_pr2(data);
    }
    if wanted("pr2") {
        pr2_fit(data)?;
        println!();
    }
    println!("{}", report::header());
    if wanted("pr2") {
        let problems = if std::env::args().any(|a| a == "--pr2-capsules") {
            // The arm as imported, the 0.05 m capsules, for comparison.
            let urdf = std::fs::read_to_string(format!("{data}/urdf/pr2.urdf"))?;
            let (_, scenes) = reach::pr2_builtin()?;
            reach::pr2_problems(&reach::pr2_arm(&urdf)?, &scenes)?
        } else {
            reach::problems("pr2", None)?
        };
        report_set("PR2", &thin(problems), &controllers, verbose)?;
    }
    if wanted("panda") {
        let problems = thin(reach::panda_problems(seed, count)?);
        report_set(
            &format!("Panda, random (seed {seed})"),
            &problems,
            &controllers,
            verbose,
        )?;
    }
    if wanted("mbm") {
        let problems = thin(mbm(data)?);
        report_set("MotionBenchMaker", &problems, &controllers, verbose)?;
    }
    Ok(())
}
