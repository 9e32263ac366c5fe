//! Framing: the ball that holds a robot in any pose, whether a robot is
//! drawn in 2D, and the points a view should keep on screen.

use glam::{DAffine3, DVec3};

use super::draw::DrawState;
use crate::distance::PrimitiveSpec;
use crate::kinematics::{Frames, JointType, Robot};

/// A ball around the robot's base that holds the robot in any pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// The base (m, world frame).
    pub center: DVec3,
    /// Radius (m), at least 0.1.
    pub radius: f64,
}

impl Reach {
    /// The reach of `robot`, whose frames at some pose are `frames`: the sum
    /// over every row of `|a| + |d|` (for a prismatic joint the larger of
    /// `|d|` at that pose and at its limits, when they are finite) and the
    /// link's extension past its joint, plus every tool's offset, bounds
    /// how far the spine gets from the base; the largest volume radius is
    /// added once, since every point of a volume lies within its own radius
    /// of the spine. A bound, not the exact workspace. (Summing the radii
    /// as well, as this once did, made the Panda's ball 2.14 m instead of
    /// 1.53 m with its fitted volumes, and the square drawn for a floor
    /// twice as large.)
    #[must_use]
    pub fn of(robot: &Robot, frames: &Frames) -> Self {
        let rows: f64 = robot
            .joints
            .iter()
            .zip(&frames.d)
            .map(|(j, d)| {
                // A prismatic row reaches as far as its limits allow.
                let d = match j.kind {
                    JointType::Prismatic if j.min.is_finite() && j.max.is_finite() => {
                        (j.d + j.min).abs().max((j.d + j.max).abs()).max(d.abs())
                    }
                    _ => d.abs(),
                };
                j.a.abs() + d + j.extension
            })
            .sum();
        let radius = robot
            .joints
            .iter()
            .map(|j| j.radius.max())
            .fold(0.0, f64::max);
        let tools: f64 = robot
            .chains
            .iter()
            .map(|c| c.tool.translation.length())
            .sum();
        Self {
            center: frames.origin(0),
            radius: (rows + tools + radius).max(0.1),
        }
    }

    /// Half the side of the square that stands for an infinite plane (m):
    /// a bit more than the reach, within 0.5 … 5 m.
    #[must_use]
    pub fn plane_extent(&self) -> f64 {
        (1.2 * self.radius).clamp(0.5, 5.0)
    }
}

/// Whether a robot is drawn in 2D: every joint axis is the world z axis and
/// every frame origin lies in one horizontal plane (within 1e-9).
#[must_use]
pub fn is_planar(frames: &[DAffine3]) -> bool {
    let Some(first) = frames.first() else {
        return false;
    };
    frames.iter().all(|f| {
        f.matrix3.z_axis.normalize_or_zero().z.abs() > 1.0 - 1e-9
            && (f.translation.z - first.translation.z).abs() < 1e-9
    })
}

/// The points a view should frame: the skeleton's volumes (each node
/// moved by its volume's radius along ±x, ±y and ±z, so that a fit keeps
/// the volumes whole and not only the spine) and the reference
/// point of every bounded obstacle part the robot can reach (within the
/// reach ball). Infinite planes and parts out of reach (a large floor's
/// centre, a person walking in from afar) are left out so that the robot
/// stays large on screen. Of a person only the forearms and hands are
/// framed (what reaches for the arm; the body standing beside it would
/// make the robot small), and only when the pelvis is within reach.
#[must_use]
pub fn fit_points(state: &DrawState, reach: &Reach) -> Vec<[f64; 3]> {
    let mut points = state.skeleton.nodes.clone();
    let nodes = &state.skeleton.nodes;
    for s in &state.skeleton.segments {
        for (node, r) in [(s.from, s.radius[0]), (s.to, s.radius[1])] {
            let (Some(&[x, y, z]), true) = (nodes.get(node), r.is_finite() && r > 0.0) else {
                continue;
            };
            points.extend([
                [x + r, y, z],
                [x - r, y, z],
                [x, y + r, z],
                [x, y - r, z],
                [x, y, z + r],
                [x, y, z - r],
            ]);
        }
    }
    let within = |p: &PrimitiveSpec| p.reference_point().distance(reach.center) <= reach.radius;
    for o in &state.obstacles {
        let reaching = |k: usize| {
            let name = crate::human::PART_NAMES.get(k).copied().unwrap_or("");
            name.ends_with("Hand") || name.ends_with("Forearm")
        };
        if o.human && !o.parts.first().is_some_and(within) {
            continue;
        }
        for (k, part) in o.parts.iter().enumerate() {
            if matches!(part, PrimitiveSpec::Plane(_)) || (o.human && !reaching(k)) {
                continue;
            }
            if within(part) {
                points.push(part.reference_point().to_array());
            }
        }
    }
    points
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;
    use crate::kinematics::presets;

    fn robot(name: &str) -> Robot {
        Robot::from_spec(&presets::preset(name).unwrap()).unwrap()
    }

    #[test]
    fn planar3_is_planar_and_the_arms_in_3d_are_not() {
        let planar = robot("planar3");
        let f = planar.forward(&[0.3, -0.7, 1.1]).unwrap();
        assert!(is_planar(&f.transforms));
        for name in ["lwr4", "panda", "ur5", "dual-arm"] {
            let r = robot(name);
            let f = r.forward(&vec![0.0; r.dof()]).unwrap();
            assert!(!is_planar(&f.transforms), "{name}");
        }
        assert!(!is_planar(&[]));
    }

    #[test]
    fn a_fit_frames_the_volumes_and_not_only_the_spine() {
        use super::super::draw::{SegmentView, SkeletonView};
        let state = DrawState {
            skeleton: SkeletonView {
                nodes: vec![[0.0, 0.0, 0.0], [0.4, 0.0, 0.0]],
                segments: vec![SegmentView {
                    from: 0,
                    to: 1,
                    radius: [0.08, 0.05],
                }],
            },
            ..DrawState::default()
        };
        let reach = Reach {
            center: DVec3::ZERO,
            radius: 1.0,
        };
        let points = fit_points(&state, &reach);
        let (lo, hi) = points.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(DVec3::from(*p)), hi.max(DVec3::from(*p))),
        );
        // The box of the points holds both end spheres of the volume.
        assert!(
            (lo - DVec3::new(-0.08, -0.08, -0.08)).length() < 1e-12,
            "{lo}"
        );
        assert!((hi - DVec3::new(0.45, 0.08, 0.08)).length() < 1e-12, "{hi}");
    }

    #[test]
    fn planar3_reach_is_its_link_lengths_and_its_largest_volume() {
        let r = robot("planar3");
        let f = r.forward(&[0.0; 3]).unwrap();
        let reach = Reach::of(&r, &f);
        let radius = r.joints.iter().map(|j| j.radius.max()).fold(0.0, f64::max);
        assert!((reach.radius - (0.9 + radius)).abs() < 1e-12, "{reach:?}");
        assert_eq!(reach.center, DVec3::ZERO);
    }
}
