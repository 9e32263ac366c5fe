//! Yoshikawa's manipulability of a chain's end effector,
//! `m = √det(J Jᵀ)`, and its gradient `J_m = ∂m/∂q` (NEO's
//! *manipulability Jacobian*), in closed form from the columns of the
//! geometric Jacobian.
//!
//! **The derivative of a column.** Write column `j` of `J` as `(vⱼ, ωⱼ)`
//! (linear, angular; `ωⱼ` the axis of a revolute joint, zero for a
//! prismatic one). Moving joint `i` rotates about `ωᵢ` everything after
//! it, and moves the end effector by `vᵢ`:
//!
//! * `i` at or before `j` on the chain: `∂(vⱼ, ωⱼ)/∂qᵢ = (ωᵢ × vⱼ, ωᵢ × ωⱼ)`;
//! * `i` after `j`: `∂(vⱼ, ωⱼ)/∂qᵢ = (ωⱼ × vᵢ, 0)`.
//!
//! **The gradient.** With `A = J Jᵀ`, `∂ log det A / ∂qᵢ =
//! 2 tr(A⁻¹ ∂J/∂qᵢ Jᵀ)`, so `∂m/∂qᵢ = m ⟨∂J/∂qᵢ, A⁻¹ J⟩` (the sum of the
//! entrywise products). Rows the chain cannot move along at all in this
//! configuration (a planar arm's `z`, its tilts) are left out of `det`
//! (their diagonal set to 1, as in the QP's singularity damping), so a
//! planar arm has a manipulability too. At any other singularity (`A` not
//! positive definite) both are zero.

use crate::error::FieldError;
use crate::kinematics::ik::end_effector_jacobian;
use crate::kinematics::{Frames, Robot};
use crate::linalg::{Mat, cholesky_into};

/// The manipulability of `chain`'s end effector and its gradient (one
/// value per joint; zero for the joints not on the chain).
///
/// # Errors
/// A chain that does not exist.
pub fn manipulability(
    robot: &Robot,
    frames: &Frames,
    chain: usize,
) -> Result<(f64, Vec<f64>), FieldError> {
    let jac = end_effector_jacobian(robot, frames, chain)?;
    Ok(manipulability_of(&jac, &chain_order(robot, chain)))
}

/// Each joint's place along `chain` from its base (`None` off the chain).
fn chain_order(robot: &Robot, chain: usize) -> Vec<Option<usize>> {
    let n = robot.dof();
    let mut path = Vec::new();
    if let Some(c) = robot.chains.get(chain) {
        let mut k = c.last;
        while k >= 1 && path.len() < n {
            path.push(k - 1);
            k = robot.joints[k - 1].parent;
        }
    }
    let mut order = vec![None; n];
    for (place, &i) in path.iter().rev().enumerate() {
        order[i] = Some(place);
    }
    order
}

fn column(jac: &Mat, j: usize) -> ([f64; 3], [f64; 3]) {
    let g = |r| jac.get(r, j);
    ([g(0), g(1), g(2)], [g(3), g(4), g(5)])
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `m` and `∂m/∂q` of the 6 × n Jacobian `jac`, the joints placed along
/// the chain by `order`.
pub(super) fn manipulability_of(jac: &Mat, order: &[Option<usize>]) -> (f64, Vec<f64>) {
    let n = jac.cols;
    let mut a = [0.0; 36];
    for r in 0..6 {
        for s in 0..=r {
            let v: f64 = (0..n).map(|c| jac.get(r, c) * jac.get(s, c)).sum();
            a[r * 6 + s] = v;
            a[s * 6 + r] = v;
        }
        if a[r * 6 + r] < 1e-18 {
            a[r * 6 + r] = 1.0;
        }
    }
    let mut l = Vec::new();
    if !cholesky_into(&a, 6, 1e-30, &mut l) {
        return (0.0, vec![0.0; n]);
    }
    let m: f64 = (0..6).map(|i| l[i * 6 + i]).product::<f64>().abs();
    // B = A⁻¹ J, one column at a time through the two triangular solves.
    let mut b = Mat::zeros(6, n);
    for c in 0..n {
        let mut x: [f64; 6] = std::array::from_fn(|r| jac.get(r, c));
        for i in 0..6 {
            let s: f64 = x[i] - (0..i).map(|k| l[i * 6 + k] * x[k]).sum::<f64>();
            x[i] = s / l[i * 6 + i];
        }
        for i in (0..6).rev() {
            let s: f64 = x[i] - (i + 1..6).map(|k| l[k * 6 + i] * x[k]).sum::<f64>();
            x[i] = s / l[i * 6 + i];
        }
        for (r, v) in x.iter().enumerate() {
            b.set(r, c, *v);
        }
    }
    let gradient = (0..n)
        .map(|i| {
            let Some(pi) = order[i] else { return 0.0 };
            let (vi, wi) = column(jac, i);
            let mut sum = 0.0;
            for (j, pj) in order.iter().enumerate() {
                let Some(pj) = *pj else { continue };
                let (vj, wj) = column(jac, j);
                let (dv, dw) = if pi <= pj {
                    (cross(wi, vj), cross(wi, wj))
                } else {
                    (cross(wj, vi), [0.0; 3])
                };
                for r in 0..3 {
                    sum += dv[r] * b.get(r, j) + dw[r] * b.get(r + 3, j);
                }
            }
            m * sum
        })
        .collect();
    (m, gradient)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::presets;

    fn robot(name: &str) -> Robot {
        Robot::from_spec(&presets::preset(name).unwrap()).unwrap()
    }

    fn m_at(robot: &Robot, q: &[f64]) -> f64 {
        manipulability(robot, &robot.forward(q).unwrap(), 0)
            .unwrap()
            .0
    }

    #[test]
    fn the_gradient_matches_central_differences() {
        for (name, q) in [
            ("panda", vec![0.3, -0.6, 0.2, -2.0, 0.4, 1.7, 0.6]),
            ("lwr4", vec![0.1, 0.7, -0.3, -1.1, 0.5, 0.8, -0.2]),
            ("ur5", vec![0.2, -1.1, 1.3, -0.7, 1.2, 0.4]),
            ("planar3", vec![0.4, 0.9, -0.5]),
            ("stanford", vec![0.2, 1.1, 0.4, 0.3, 0.9, 0.2]),
        ] {
            let r = robot(name);
            let (m, g) = manipulability(&r, &r.forward(&q).unwrap(), 0).unwrap();
            assert!(m > 0.0, "{name}: m = {m}");
            for i in 0..q.len() {
                let h = 1e-6;
                let (mut a, mut b) = (q.clone(), q.clone());
                a[i] += h;
                b[i] -= h;
                let fd = (m_at(&r, &a) - m_at(&r, &b)) / (2.0 * h);
                assert!(
                    (fd - g[i]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{name} joint {i}: {} against {fd}",
                    g[i]
                );
            }
        }
    }
}
