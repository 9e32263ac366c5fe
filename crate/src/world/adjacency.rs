//! Which pairs of links the self-collision query leaves out (part of the
//! [`super::parts::Model`]).

use crate::avoidance::ControllerConfig;
use crate::error::FieldError;
use crate::kinematics::Robot;
use crate::skeleton::Skeleton;

/// Links that never repel each other: two hops of [`Robot::adjacent`]
/// (the one definition of adjacent links: their segments share a skeleton
/// node). A link is also kept from its neighbour's neighbours because a
/// short link between two long ones keeps their volumes overlapping at the
/// joint. Rows without segments never meet in the query, so the pairs they
/// add through two hops (their parent's other children, already adjacent)
/// change nothing.
fn link_adjacency(robot: &Robot) -> Vec<Vec<bool>> {
    let n = robot.dof() + 1;
    let direct: Vec<Vec<bool>> = (0..n)
        .map(|i| (0..n).map(|j| robot.adjacent(i, j)).collect())
        .collect();
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| direct[i][j] || (0..n).any(|k| direct[i][k] && direct[k][j]))
                .collect()
        })
        .collect()
}

/// Which pairs of links the self-collision query leaves out: adjacent links
/// ([`link_adjacency`]), the robot's and the controller's
/// `selfCollisionExclude`, and pairs no joint can move apart or together
/// ([`fixed_link_pairs`]).
pub(crate) fn self_pairs_left_out(
    robot: &Robot,
    controller: &ControllerConfig,
) -> Result<Vec<Vec<bool>>, FieldError> {
    let mut adjacency = link_adjacency(robot);
    let chosen = robot.link_pairs(
        "controller.selfCollisionExclude",
        &controller.self_collision_exclude,
    )?;
    for (a, b) in robot
        .exclude
        .iter()
        .chain(&chosen)
        .copied()
        .chain(fixed_link_pairs(robot))
    {
        adjacency[a][b] = true;
        adjacency[b][a] = true;
    }
    Ok(adjacency)
}

/// Pairs of links whose segments keep the same distance whatever the
/// joints do (e.g. the Panda's column and the link carrying the shoulder's
/// offset, which only turn about axes through the column's top): no joint
/// motion can change their clearance, so a guard or damper on them could
/// only freeze the arm. Checked on the kinematics: the smallest distance
/// between the two links' spines at 16 seeded configurations within the
/// limits, fixed when it varies by less than 1 µm.
fn fixed_link_pairs(robot: &Robot) -> Vec<(usize, usize)> {
    use crate::distance::{LineSegment, Primitive, distance};
    let n = robot.dof();
    let mut rng = crate::rng::Rng::new(0x5e1f);
    let mut spans: Vec<Vec<(f64, f64)>> =
        vec![vec![(f64::INFINITY, f64::NEG_INFINITY); n + 1]; n + 1];
    for _ in 0..16 {
        let q: Vec<f64> = robot
            .joints
            .iter()
            .map(|j| {
                let (lo, hi) = (j.min.max(-3.0), j.max.min(3.0));
                rng.range(lo, hi)
            })
            .collect();
        let Ok(frames) = robot.forward(&q) else {
            return Vec::new();
        };
        let skeleton = Skeleton::build(robot, &frames);
        let segs: Vec<(usize, Option<LineSegment>)> = skeleton
            .segments
            .iter()
            .map(|s| {
                let (a, b) = skeleton.endpoints(s);
                (s.link, LineSegment::new(a, b).ok())
            })
            .collect();
        let mut closest = vec![vec![f64::INFINITY; n + 1]; n + 1];
        for (i, (la, a)) in segs.iter().enumerate() {
            for (lb, b) in &segs[i + 1..] {
                if let (Some(a), Some(b)) = (a, b)
                    && la != lb
                    && let Ok(d) = distance(&Primitive::Segment(*a), &Primitive::Segment(*b))
                {
                    let (x, y) = ((*la).min(*lb), (*la).max(*lb));
                    closest[x][y] = closest[x][y].min(d.distance);
                }
            }
        }
        for (x, row) in closest.iter().enumerate() {
            for (y, d) in row.iter().enumerate().filter(|(_, d)| d.is_finite()) {
                let span = &mut spans[x][y];
                *span = (span.0.min(*d), span.1.max(*d));
            }
        }
    }
    let mut out = Vec::new();
    for (x, row) in spans.iter().enumerate() {
        for (y, (lo, hi)) in row.iter().enumerate() {
            if lo.is_finite() && hi - lo < 1e-6 {
                out.push((x, y));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;
    use crate::kinematics::presets;

    /// Two hops of "segments share a node", read from the skeleton's nodes.
    fn from_nodes(robot: &Robot, skeleton: &Skeleton) -> Vec<Vec<bool>> {
        let n = robot.dof() + 1;
        let mut direct = vec![vec![false; n]; n];
        for (i, row) in direct.iter_mut().enumerate() {
            row[i] = true;
        }
        for a in &skeleton.segments {
            for b in &skeleton.segments {
                if [a.from, a.to].iter().any(|x| *x == b.from || *x == b.to) {
                    direct[a.link][b.link] = true;
                }
            }
        }
        let with_segments: Vec<bool> = (0..n)
            .map(|l| skeleton.segments.iter().any(|s| s.link == l))
            .collect();
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| direct[i][j] || (0..n).any(|k| direct[i][k] && direct[k][j]))
                    .collect::<Vec<_>>()
            })
            .enumerate()
            .map(|(i, row)| {
                // Only rows with segments meet in the query.
                row.into_iter()
                    .enumerate()
                    .map(|(j, x)| x && with_segments[i] && with_segments[j])
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_robots_adjacency_is_the_one_the_skeleton_shows() {
        for name in presets::NAMES {
            let robot = Robot::from_spec(&presets::preset(name).unwrap()).unwrap();
            let frames = robot.forward(&vec![0.2; robot.dof()]).unwrap();
            let skeleton = Skeleton::build(&robot, &frames);
            let expected = from_nodes(&robot, &skeleton);
            let got = link_adjacency(&robot);
            let links: Vec<usize> = skeleton.segments.iter().map(|s| s.link).collect();
            for &i in &links {
                for &j in &links {
                    assert_eq!(got[i][j], expected[i][j], "{name}: links {i} and {j}");
                }
            }
        }
    }
}
