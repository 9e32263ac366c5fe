//! The projection of a command onto the guards and the velocity box (the
//! protective layer of the `repulsion` avoidance and of the torque and
//! `clik2` modes; see [`super`]).

use super::{GUARD_TOLERANCE, Guard};

/// The outcome of [`project`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Projection {
    /// Largest remaining violation `row · q̇ − bound` (m/s; ≤ 1e-9 when
    /// every guard holds).
    pub violation: f64,
    /// The guard with the largest violation, when one is violated.
    pub worst: Option<usize>,
    /// Sweeps used.
    pub sweeps: usize,
}

const MAX_SWEEPS: usize = 200;

/// `x` closest to `desired` in the metric `Σ wᵢ (xᵢ − desiredᵢ)²` with
/// `lo ≤ x ≤ hi` and every guard `row · x ≤ bound` (Hildreth's method on the
/// dual). Empty `weights` means unit weights.
pub fn project(
    desired: &[f64],
    weights: &[f64],
    lo: &[f64],
    hi: &[f64],
    guards: &[Guard],
    x: &mut Vec<f64>,
) -> Projection {
    let n = desired.len();
    x.clear();
    x.extend_from_slice(desired);
    let winv: Vec<f64> = (0..n)
        .map(|i| weights.get(i).map_or(1.0, |w| 1.0 / w))
        .collect();
    let norms: Vec<f64> = guards
        .iter()
        .map(|g| g.row.iter().zip(&winv).map(|(r, w)| r * r * w).sum())
        .collect();
    let mut lambda = vec![0.0; guards.len()];
    let (mut up, mut down) = (vec![0.0; n], vec![0.0; n]);
    let mut sweeps = 0;
    while sweeps < MAX_SWEEPS {
        sweeps += 1;
        let mut change: f64 = 0.0;
        for (k, g) in guards.iter().enumerate() {
            if norms[k] <= 1e-18 {
                continue;
            }
            let gx: f64 = g.row.iter().zip(x.iter()).map(|(r, v)| r * v).sum();
            let next = (lambda[k] + (gx - g.bound) / norms[k]).max(0.0);
            let delta = next - lambda[k];
            if delta != 0.0 {
                for ((xi, r), w) in x.iter_mut().zip(&g.row).zip(&winv) {
                    *xi -= w * r * delta;
                }
                lambda[k] = next;
                change = change.max((delta * norms[k]).abs());
            }
        }
        for i in 0..n {
            // x_i ≤ hi_i (multiplier up[i]) and −x_i ≤ −lo_i (down[i]).
            let next = (up[i] + (x[i] - hi[i]) / winv[i]).max(0.0);
            x[i] -= winv[i] * (next - up[i]);
            change = change.max(((next - up[i]) * winv[i]).abs());
            up[i] = next;
            let next = (down[i] + (lo[i] - x[i]) / winv[i]).max(0.0);
            x[i] += winv[i] * (next - down[i]);
            change = change.max(((next - down[i]) * winv[i]).abs());
            down[i] = next;
        }
        if change < 1e-12 {
            break;
        }
    }
    for (xi, (l, h)) in x.iter_mut().zip(lo.iter().zip(hi)) {
        *xi = xi.clamp(*l, *h);
    }
    let mut out = Projection {
        sweeps,
        ..Projection::default()
    };
    for (k, g) in guards.iter().enumerate() {
        let gx: f64 = g.row.iter().zip(x.iter()).map(|(r, v)| r * v).sum();
        let v = gx - g.bound;
        if v > out.violation {
            out.violation = v;
            if v > GUARD_TOLERANCE.max(1e-6 * g.bound.abs()) {
                out.worst = Some(k);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guard(row: &[f64], bound: f64) -> Guard {
        Guard {
            row: row.to_vec(),
            bound,
            ..Guard::default()
        }
    }

    #[test]
    fn projection_is_the_weighted_closest_feasible_point() {
        let gs = [guard(&[1.0, 1.0], 1.0)];
        let mut x = Vec::new();
        let p = project(&[2.0, 2.0], &[], &[-5.0; 2], &[5.0; 2], &gs, &mut x);
        assert!(p.worst.is_none());
        assert!(
            (x[0] - 0.5).abs() < 1e-9 && (x[1] - 0.5).abs() < 1e-9,
            "{x:?}"
        );
        // Joint 1 four times heavier: it moves a quarter as much.
        project(&[2.0, 2.0], &[1.0, 4.0], &[-5.0; 2], &[5.0; 2], &gs, &mut x);
        assert!(
            (x[0] + 0.4).abs() < 1e-9 && (x[1] - 1.4).abs() < 1e-9,
            "{x:?}"
        );
        // Inactive guard: untouched.
        project(&[0.1, 0.2], &[], &[-5.0; 2], &[5.0; 2], &gs, &mut x);
        assert_eq!(x, vec![0.1, 0.2]);
    }

    #[test]
    fn guards_and_box_together_and_infeasibility_reported() {
        let gs = [guard(&[1.0, 0.0], -1.0)];
        let mut x = Vec::new();
        let p = project(&[0.0, 0.3], &[], &[-2.0; 2], &[2.0; 2], &gs, &mut x);
        assert!(p.worst.is_none());
        assert!((x[0] + 1.0).abs() < 1e-9 && (x[1] - 0.3).abs() < 1e-9);
        // Retreat faster than the box allows: reported.
        let gs = [guard(&[1.0, 0.0], -3.0)];
        let p = project(&[0.0, 0.0], &[], &[-2.0; 2], &[2.0; 2], &gs, &mut x);
        assert_eq!(p.worst, Some(0));
        assert!((p.violation - 1.0).abs() < 1e-9);
    }
}
