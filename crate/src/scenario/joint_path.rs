//! The `joints` task: a path in joint space, given as configurations and
//! the times at which the arm is to be at them (a planner's output, see
//! [`crate::plan`]).
//!
//! Between two consecutive configurations the reference moves on the
//! straight joint-space segment that joins them, timed by the quintic
//! `s(u) = 10u³ − 15u⁴ + 6u⁵`: it starts and ends each segment at rest.
//! A path checked segment by segment (as [`crate::plan`] certifies it) is
//! then followed on exactly those segments, with no corner cut: stopping at
//! each waypoint costs time, but the clearance certified for the straight
//! segments is the clearance of the reference. Before the first time the
//! reference is the first configuration; after the last, the last.
//!
//! The times are the path's own clock, which a world runs at its pace
//! only while the arm keeps up: when a guard holds the arm back, or the
//! limits let it fall behind, the clock slows and waits for it (see
//! `world/control.rs`), so that the arm is pulled back onto the path
//! rather than straight towards a reference far along it.
//!
//! The `constraints` avoidance tracks it with one row per joint,
//! `q̇ ≈ q̇_ref + K (q_ref − q)`, under the same guards and limits as any
//! other task: the path guides, the protective layer still decides.

use crate::error::FieldError;
use crate::kinematics::Robot;

/// Checks a `joints` task: at least one configuration, each with one
/// finite value per joint within the joint's limits; one finite time per
/// configuration, `≥ 0` and strictly increasing.
///
/// # Errors
/// `configurations[2][3]: 3.5 is outside the joint's limits [-2.9, 2.9]`,
/// `times[1]: must be greater than times[0]`, …
pub fn validate(
    robot: &Robot,
    configurations: &[Vec<f64>],
    times: &[f64],
) -> Result<(), FieldError> {
    if configurations.is_empty() {
        return Err(FieldError::new(
            "configurations",
            "needs at least one configuration",
        ));
    }
    if times.len() != configurations.len() {
        return Err(FieldError::new(
            "times",
            format!(
                "expected {} times (one per configuration), got {}",
                configurations.len(),
                times.len()
            ),
        ));
    }
    let n = robot.dof();
    for (k, c) in configurations.iter().enumerate() {
        let field = format!("configurations[{k}]");
        if c.len() != n {
            return Err(FieldError::new(
                field,
                format!("expected {n} values (one per joint), got {}", c.len()),
            ));
        }
        for (j, (&v, joint)) in c.iter().zip(&robot.joints).enumerate() {
            if !v.is_finite() {
                return Err(FieldError::new(
                    format!("{field}[{j}]"),
                    "not a finite number",
                ));
            }
            if v < joint.min || v > joint.max {
                return Err(FieldError::new(
                    format!("{field}[{j}]"),
                    format!(
                        "{v} is outside the joint's limits [{}, {}]",
                        joint.min, joint.max
                    ),
                ));
            }
        }
    }
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() || t < 0.0 {
            return Err(FieldError::new(
                format!("times[{k}]"),
                "must be a finite number ≥ 0",
            ));
        }
        if k > 0 && t <= times[k - 1] {
            return Err(FieldError::new(
                format!("times[{k}]"),
                format!("must be greater than times[{}]", k - 1),
            ));
        }
    }
    Ok(())
}

/// The reference at time `t`: positions into `q` and velocities into
/// `qdot` (both resized to the configurations' length). Inputs as
/// [`validate`] accepts them; with no configuration both are left empty,
/// and times beyond the configurations (or configurations beyond the
/// times) are not used.
pub fn reference_at(
    configurations: &[Vec<f64>],
    times: &[f64],
    t: f64,
    q: &mut Vec<f64>,
    qdot: &mut Vec<f64>,
) {
    q.clear();
    qdot.clear();
    let count = configurations.len().min(times.len());
    let (Some(first), Some(last)) = (
        configurations.first(),
        configurations.get(count.wrapping_sub(1)),
    ) else {
        return;
    };
    let times = &times[..count];
    qdot.resize(first.len(), 0.0);
    let k = times.partition_point(|&s| s <= t);
    let (a, b) = match (k.checked_sub(1), configurations.get(k)) {
        (Some(i), Some(b)) if k < count => (&configurations[i], b),
        _ => {
            q.extend_from_slice(if k == 0 { first } else { last });
            return;
        }
    };
    let (t0, t1) = (times[k - 1], times[k]);
    let (s, ds, _) = super::task::quintic(t, t0, t1 - t0);
    q.extend(a.iter().zip(b).map(|(x, y)| x + (y - x) * s));
    for ((v, x), y) in qdot.iter_mut().zip(a).zip(b) {
        *v = (y - x) * ds;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::presets;

    #[test]
    fn the_reference_rests_at_each_waypoint_and_moves_on_the_segment() {
        let c = vec![vec![0.0, 0.0], vec![1.0, -2.0], vec![1.0, 0.0]];
        let times = [0.5, 1.5, 2.0];
        let (mut q, mut qd) = (Vec::new(), Vec::new());
        for (t, want) in [(0.0, [0.0, 0.0]), (1.5, [1.0, -2.0]), (9.0, [1.0, 0.0])] {
            reference_at(&c, &times, t, &mut q, &mut qd);
            assert_eq!(q, want.to_vec());
            assert_eq!(qd, vec![0.0, 0.0]);
        }
        reference_at(&c, &times, 1.0, &mut q, &mut qd);
        // Halfway through the quintic: s = 1/2, ds = 30/16 per second.
        assert!((q[0] - 0.5).abs() < 1e-12 && (q[1] + 1.0).abs() < 1e-12);
        assert!((qd[0] - 1.875).abs() < 1e-12 && (qd[1] + 3.75).abs() < 1e-12);
        // The velocity is the derivative of the position.
        let h = 1e-6;
        let (mut qa, mut qb, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
        reference_at(&c, &times, 0.8 - h, &mut qa, &mut scratch);
        reference_at(&c, &times, 0.8 + h, &mut qb, &mut scratch);
        reference_at(&c, &times, 0.8, &mut q, &mut qd);
        for j in 0..2 {
            assert!(((qb[j] - qa[j]) / (2.0 * h) - qd[j]).abs() < 1e-6);
        }
    }

    #[test]
    fn empty_or_uneven_inputs_give_an_empty_or_clipped_reference() {
        let (mut q, mut qd) = (vec![9.0], vec![9.0]);
        reference_at(&[], &[], 1.0, &mut q, &mut qd);
        assert!(q.is_empty() && qd.is_empty());
        reference_at(&[vec![1.0]], &[], 1.0, &mut q, &mut qd);
        assert!(q.is_empty());
        let c = vec![vec![0.0], vec![1.0], vec![5.0]];
        reference_at(&c, &[0.0, 1.0], 9.0, &mut q, &mut qd);
        assert_eq!(q, vec![1.0]);
        reference_at(&c[..2], &[0.0, 1.0, 2.0], 9.0, &mut q, &mut qd);
        assert_eq!(q, vec![1.0]);
    }

    #[test]
    fn bad_paths_are_refused_with_the_field_named() {
        // Test code: the preset is built in, so these cannot fail.
        let robot = Robot::from_spec(&presets::preset("planar3").unwrap()).unwrap();
        let ok = vec![vec![0.0, 0.0, 0.0], vec![0.5, 0.5, 0.5]];
        assert!(validate(&robot, &ok, &[0.0, 1.0]).is_ok());
        let field = |c: &[Vec<f64>], t: &[f64]| validate(&robot, c, t).unwrap_err().field;
        assert_eq!(field(&[], &[]), "configurations");
        assert_eq!(field(&ok, &[0.0]), "times");
        assert_eq!(field(&ok, &[1.0, 1.0]), "times[1]");
        assert_eq!(field(&ok, &[-1.0, 1.0]), "times[0]");
        assert_eq!(
            field(&[vec![0.0], ok[0].clone()], &[0.0, 1.0]),
            "configurations[0]"
        );
        assert_eq!(
            field(&[vec![0.0, f64::NAN, 0.0]], &[0.0]),
            "configurations[0][1]"
        );
        assert_eq!(
            field(&[vec![0.0, 99.0, 0.0]], &[0.0]),
            "configurations[0][1]"
        );
    }
}
