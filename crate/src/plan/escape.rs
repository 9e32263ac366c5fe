//! Step 1 of a plan ([`super`]'s docs): the escape from a start closer to
//! the obstacles (or to itself) than the thresholds.
//!
//! The start climbs its margin (the smallest over the pairs, see
//! [`Checker::margin`]) by steps of 2 cm of sweep at most (1 cm, 5 mm when
//! no longer step gains), each in the best of three kinds of direction:
//! - the *opening* direction: the smallest joint motion (weighted by each
//!   joint's reach) that opens every pair within [`TIGHT`] of the smallest
//!   margin at once, by a small QP ([`crate::avoidance::qp`]). An arm
//!   between two boxes has two pairs nearly equally close; the gradient of
//!   the smallest margin opens one and closes the other, and random
//!   directions in seven joints rarely open both. On the PR2 benchmark's
//!   starts between boxes, the climb stalled 5–25 mm short of the
//!   thresholds where the reactive controller, which meets every guard at
//!   once the same way, slid 13–17 mm clear;
//! - the margin's finite-difference gradient;
//! - 24 random directions.
//!
//! A start no step frees further keeps each pair still short at a
//! threshold of its own (its clearance less `3 MIN_MARGIN`, see
//! [`Checker::relax`]), so that the path never closes it further, as long
//! as that clearance is at least the *floor*: the protective layer's safety
//! distance plus [`FLOOR_ABOVE_SAFETY`]. The planned path then keeps every
//! pair beyond the distance at which the guards would stop the arm. Below
//! the floor (an arm wedged between boxes), the start is refused.

use super::checker::{Checker, MIN_MARGIN, Thresholds};
use crate::avoidance::qp;
use crate::error::FieldError;
use crate::linalg::Mat;
use crate::rng::Rng;

/// How far above the protective layer's safety distance a pair the escape
/// cannot free must be kept (m).
pub const FLOOR_ABOVE_SAFETY: f64 = 0.002;

/// Pairs whose margin is within this of the smallest are opened together
/// by the opening direction (m).
pub const TIGHT: f64 = 0.01;

/// Longest step of the climb, then shorter ones (m of sweep).
const STEPS: [f64; 3] = [0.02, 0.01, 0.005];
/// Random directions tried per step.
const TRIES: usize = 24;
/// Most steps of the climb.
const MAX_STEPS: usize = 400;

/// The configurations from `start` to the first with a margin of
/// `3 MIN_MARGIN` at least over `thresholds`, or to where no step gains,
/// the pairs still short there relaxed down to `floor` (module docs).
///
/// # Errors
/// `q0`: a pair still short at a clearance below `floor` (the start is
/// wedged); as [`Checker::clearances`].
pub fn escape(
    checker: &mut Checker,
    start: &[f64],
    (thresholds, floor): (&Thresholds, f64),
    rng: &mut Rng,
) -> Result<Vec<Vec<f64>>, FieldError> {
    let mut path = vec![start.to_vec()];
    let mut q = start.to_vec();
    let mut m = checker.margin(&q, thresholds)?;
    for _ in 0..MAX_STEPS {
        if m >= 3.0 * MIN_MARGIN {
            return straighten(checker, path, thresholds);
        }
        match best_step(checker, &q, m, thresholds, rng)? {
            Some((next, m_next)) if m_next > m => {
                (q, m) = (next, m_next);
                path.push(q.clone());
            }
            _ => break,
        }
    }
    let short = checker.relax(&q, thresholds, floor)?;
    if short > 0.0 {
        return Err(FieldError::new(
            "q0",
            format!(
                "the start cannot be freed (wedged between obstacles): {:.1} mm short of the {:.1} mm kept at least",
                short * 1e3,
                floor * 1e3
            ),
        ));
    }
    straighten(checker, path, thresholds)
}

/// Sweep between two samples of a straightened escape (m).
const SAMPLE: f64 = 0.001;

/// `path` (an escape, its margin rising from node to node) with as many
/// nodes left out as keep the margin: from each node kept, the next is the
/// farthest whose straight segment keeps, at samples [`SAMPLE`] of sweep
/// apart, the margin of the node it leaves ([`super::skip_nodes`]). The
/// climb zigzags (each step the best of a few directions), and the
/// `joints` task stops the arm at every node: on the PR2 starts between
/// boxes, escapes of 50–60 nodes took 4 s of the 10 s a problem has.
fn straighten(
    checker: &mut Checker,
    path: Vec<Vec<f64>>,
    thresholds: &Thresholds,
) -> Result<Vec<Vec<f64>>, FieldError> {
    super::skip_nodes(path, |a, b| {
        let floor = checker.margin(a, thresholds)?;
        keeps(checker, (a, b), thresholds, floor)
    })
}

/// Whether every sample of the straight segment `a`–`b` keeps a margin of
/// `floor` (see [`straighten`]).
fn keeps(
    checker: &mut Checker,
    (a, b): (&[f64], &[f64]),
    thresholds: &Thresholds,
    floor: f64,
) -> Result<bool, FieldError> {
    let samples = (checker.sweep(a, b) / SAMPLE).ceil().max(1.0) as usize;
    for k in 1..=samples {
        let u = k as f64 / samples as f64;
        let q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + (y - x) * u).collect();
        if checker.margin(&q, thresholds)? < floor {
            return Ok(false);
        }
    }
    Ok(true)
}

/// The best step from `q` (margin `m`) over every direction and length
/// (module docs), with its margin; `None` when no direction moves.
fn best_step(
    checker: &mut Checker,
    q: &[f64],
    m: f64,
    thresholds: &Thresholds,
    rng: &mut Rng,
) -> Result<Option<(Vec<f64>, f64)>, FieldError> {
    const H: f64 = 1e-5;
    let robot = checker.robot().clone();
    let reach = checker.reach().to_vec();
    let mut best: Option<(Vec<f64>, f64)> = None;
    for k in 0..=TRIES + 1 {
        let dir = match k {
            0 => match opening(checker, q, m, thresholds)? {
                Some(d) => d,
                None => continue,
            },
            1 => {
                let mut grad = vec![0.0; q.len()];
                let mut p = q.to_vec();
                for (j, g) in grad.iter_mut().enumerate() {
                    p[j] = q[j] + H;
                    *g = (checker.margin(&p, thresholds)? - m) / H;
                    p[j] = q[j];
                }
                grad
            }
            _ => (0..q.len()).map(|_| rng.normal()).collect(),
        };
        let rate: f64 = dir.iter().zip(&reach).map(|(g, r)| g.abs() * r).sum();
        if !(rate > 0.0 && rate.is_finite()) {
            continue;
        }
        for step in STEPS {
            if step < STEPS[0] && best.as_ref().is_some_and(|b| b.1 > m) {
                // A long step already gains: shorter ones are not tried.
                break;
            }
            let mut next: Vec<f64> = q
                .iter()
                .zip(&dir)
                .map(|(x, g)| x + g * step / rate)
                .collect();
            robot.clamp_to_limits(&mut next);
            let m_next = checker.margin(&next, thresholds)?;
            if best.as_ref().is_none_or(|b| m_next > b.1) {
                best = Some((next, m_next));
            }
        }
    }
    Ok(best)
}

/// The opening direction at `q` (module docs): the `x` of least
/// `Σ ρ_j² x_j²` with `g·x ≥ 1` for the margin gradient `g` of every pair
/// within [`TIGHT`] of the smallest margin `m`, no joint pushed past a
/// limit it sits at; `None` when no motion opens them all.
fn opening(
    checker: &mut Checker,
    q: &[f64],
    m: f64,
    thresholds: &Thresholds,
) -> Result<Option<Vec<f64>>, FieldError> {
    let rows: Vec<Vec<f64>> = checker
        .tight_gradients(q, thresholds, m + TIGHT)?
        .into_iter()
        .filter(|g| g.iter().any(|x| *x != 0.0))
        .map(|g| g.into_iter().map(|x| -x).collect())
        .collect();
    if rows.is_empty() {
        return Ok(None);
    }
    let n = q.len();
    let mut h = Mat::zeros(n, n);
    for (i, r) in checker.reach().iter().enumerate() {
        h.data[i * n + i] = (r * r).max(1e-12);
    }
    let robot = checker.robot();
    // A joint at a limit may only move away from it.
    let pinned = |limit: fn(&crate::kinematics::Joint) -> f64, free: f64| -> Vec<f64> {
        (0..n)
            .map(|j| {
                if (q[j] - limit(&robot.joints[j])).abs() < 1e-9 {
                    0.0
                } else {
                    free
                }
            })
            .collect()
    };
    let lo = pinned(|j| j.min, f64::NEG_INFINITY);
    let hi = pinned(|j| j.max, f64::INFINITY);
    let rows: Vec<(&[f64], f64)> = rows.iter().map(|r| (r.as_slice(), -1.0)).collect();
    let problem = qp::Problem {
        h: &h,
        f: &vec![0.0; n],
        rows: &rows,
        lo: &lo,
        hi: &hi,
    };
    let mut x = Vec::with_capacity(n);
    let solution = qp::solve(&problem, 1e-6, &mut qp::Workspace::default(), &mut x);
    Ok(solution.worst.is_none().then_some(x))
}
