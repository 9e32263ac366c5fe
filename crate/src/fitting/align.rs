//! A URDF's bodies carried onto another description of the same arm (a
//! preset's DH table): the rigid transform between the two base frames is
//! fitted to the tip positions over sampled configurations and checked, so
//! a preset can be drawn with its manufacturer's meshes.

use glam::{DAffine3, DMat3, DVec3};

use super::Body;
use crate::kinematics::Robot;
use crate::rng::Rng;

/// Largest tip distance (m) between the two descriptions, after the base
/// transform, for them to count as the same arm.
pub const SAME_ARM_TOLERANCE: f64 = 1e-6;

/// Configurations sampled to fit and check the base transform.
const SAMPLES: usize = 20;

/// The rigid transform `W` (rotation and translation) with `W a_i ≈ b_i`
/// in the least-squares sense (Kabsch, the rotation from the polar
/// decomposition of the cross-covariance by Newton's iteration).
#[must_use]
pub fn rigid_fit(a: &[DVec3], b: &[DVec3]) -> DAffine3 {
    let n = a.len().max(1) as f64;
    let ca = a.iter().copied().sum::<DVec3>() / n;
    let cb = b.iter().copied().sum::<DVec3>() / n;
    let mut h = DMat3::ZERO;
    for (p, q) in a.iter().zip(b) {
        let (p, q) = (*p - ca, *q - cb);
        h += DMat3::from_cols(q * p.x, q * p.y, q * p.z);
    }
    let mut r = h;
    for _ in 0..100 {
        if r.determinant().abs() < 1e-300 {
            break;
        }
        r = (r + r.inverse().transpose()) * 0.5;
    }
    if !r.is_finite() || (r.determinant() - 1.0).abs() > 1e-6 {
        r = DMat3::IDENTITY;
    }
    DAffine3::from_mat3_translation(r, cb - r * ca)
}

/// `bodies` (world frame of `from` at `q = 0`, each on a row of `from`)
/// carried into the world frame of `onto` at `q = 0`, when the two are the
/// same arm: same number of joints, and over sampled configurations within
/// `onto`'s limits the tip of `from` (its end effector) lands on the last
/// frame of `onto` once moved by one rigid transform.
///
/// # Errors
/// A message when the joint counts differ or the tips stray by more than
/// [`SAME_ARM_TOLERANCE`] (naming the distance).
pub fn bodies_onto(from: &Robot, onto: &Robot, bodies: &[Body]) -> Result<Vec<Body>, String> {
    let n = onto.dof();
    if from.dof() != n {
        return Err(format!(
            "the URDF's chain has {} joints, the robot {n}",
            from.dof()
        ));
    }
    let mut rng = Rng::new(5);
    let (mut a, mut b) = (Vec::with_capacity(SAMPLES), Vec::with_capacity(SAMPLES));
    for _ in 0..SAMPLES {
        let q: Vec<f64> = onto
            .joints
            .iter()
            .map(|j| {
                let (lo, hi) = (j.min.max(-3.0), j.max.min(3.0));
                lo + (hi - lo) * rng.uniform()
            })
            .collect();
        let (Ok(fa), Ok(fb)) = (from.forward(&q), onto.forward(&q)) else {
            return Err("forward kinematics failed on a sampled configuration".to_owned());
        };
        a.push(fa.end_effector().translation);
        b.push(fb.transforms[n].translation);
    }
    let w = rigid_fit(&a, &b);
    let stray = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (w.transform_point3(*p) - *q).length())
        .fold(0.0, f64::max);
    if stray.is_nan() || stray > SAME_ARM_TOLERANCE {
        return Err(format!(
            "the URDF's kinematics are not the robot's: its tip strays {stray:.3e} m from the robot's last frame"
        ));
    }
    // The same joint values give the same pose of the arm in both (the tips
    // agree for every sampled configuration): the bodies at q = 0 move with
    // the base transform alone, and each stays on its row.
    Ok(bodies
        .iter()
        .map(|body| {
            let mut out = body.clone();
            for v in &mut out.mesh.vertices {
                *v = w.transform_point3(*v);
            }
            out
        })
        .collect())
}
