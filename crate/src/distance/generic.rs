//! parry for the pairs with no closed form here: a convex hull against
//! anything but a plane, and disks and boxes against flat figures and boxes.
//! Flat figures become zero-thickness parry shapes (a rectangle a cuboid of
//! zero height, a disk a cylinder of zero height, a polygon the triangles of
//! its ear-clipping triangulation, each measured on its own).

use glam::{DMat3, DQuat, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query::{self, ClosestPoints, PointQuery};
use parry3d_f64::shape::{Cuboid, Cylinder, Segment as ParrySegment, Shape, Triangle};

use super::{Closest, ConvexHull, Core, DistanceError};

/// Point against a solid convex hull: negative inside.
pub(crate) fn point_hull(p: DVec3, h: &ConvexHull) -> Closest {
    let proj = h.shape().project_point(&Pose::IDENTITY, p, false);
    let c = Closest::between(p, proj.point, true);
    if proj.is_inside {
        Closest {
            d: -c.d,
            n: -c.n,
            ..c
        }
    } else {
        c
    }
}

/// The parry shape and pose of a core, if it has one.
pub(crate) fn parry_shape(core: Core<'_>) -> Option<(Pose, Box<dyn Shape>)> {
    Some(match core {
        Core::Segment(a, b) => (Pose::IDENTITY, Box::new(ParrySegment::new(a, b))),
        Core::Rectangle(r) => {
            let rot = DQuat::from_mat3(&DMat3::from_cols(r.axes[0], r.axes[1], r.normal));
            (
                Pose::from_parts(r.center, rot.normalize()),
                Box::new(Cuboid::new(DVec3::new(
                    r.half_extents[0],
                    r.half_extents[1],
                    0.0,
                ))),
            )
        }
        Core::Disk(d) => (
            Pose::from_parts(d.center, DQuat::from_rotation_arc(DVec3::Y, d.normal)),
            Box::new(Cylinder::new(0.0, d.radius)),
        ),
        Core::Box(b) => (
            Pose::from_parts(b.center, b.rotation),
            Box::new(Cuboid::new(b.half_extents)),
        ),
        Core::Hull(h) => (Pose::IDENTITY, Box::new(h.shape().clone())),
        Core::Point(_) | Core::Plane(_) | Core::Polygon(_) => return None,
    })
}

/// Two cores through parry's closest points (and its contact query for the
/// depth when a solid overlaps); a polygon is measured triangle by triangle.
pub(crate) fn generic(a: Core<'_>, b: Core<'_>) -> Result<Closest, DistanceError> {
    let unsupported = || DistanceError::UnsupportedPair {
        a: a.kind(),
        b: b.kind(),
    };
    let parts_a = parts(a).ok_or_else(unsupported)?;
    let parts_b = parts(b).ok_or_else(unsupported)?;
    let solid =
        matches!(a, Core::Box(_) | Core::Hull(_)) || matches!(b, Core::Box(_) | Core::Hull(_));
    let mut best: Option<Closest> = None;
    for (pa, sa) in &parts_a {
        for (pb, sb) in &parts_b {
            let c = pair(pa, sa.as_ref(), pb, sb.as_ref(), solid).ok_or_else(unsupported)?;
            if best.is_none_or(|x| c.d < x.d) {
                best = Some(c);
            }
        }
    }
    best.ok_or_else(unsupported)
}

/// A core as parry shapes: one, or a polygon's triangles.
fn parts(core: Core<'_>) -> Option<Vec<(Pose, Box<dyn Shape>)>> {
    if let Core::Polygon(poly) = core {
        let v = poly.vertices();
        return Some(
            poly.triangles()
                .into_iter()
                .map(|[i, j, k]| {
                    let t: Box<dyn Shape> = Box::new(Triangle::new(v[i], v[j], v[k]));
                    (Pose::IDENTITY, t)
                })
                .collect(),
        );
    }
    parry_shape(core).map(|p| vec![p])
}

/// One pair of parry shapes.
fn pair(
    pose_a: &Pose,
    sa: &dyn Shape,
    pose_b: &Pose,
    sb: &dyn Shape,
    solid: bool,
) -> Option<Closest> {
    match query::closest_points(pose_a, sa, pose_b, sb, f64::MAX) {
        Ok(ClosestPoints::WithinMargin(p1, p2)) => Some(Closest::between(p1, p2, true)),
        Ok(_) => {
            let Some(c) = query::contact(pose_a, sa, pose_b, sb, 0.0).ok()? else {
                let p = pose_a.translation;
                return Some(Closest {
                    d: 0.0,
                    pa: p,
                    pb: p,
                    n: DVec3::ZERO,
                    unique: false,
                });
            };
            Some(if solid {
                Closest {
                    d: c.dist.min(0.0),
                    pa: c.point1,
                    pb: c.point2,
                    n: c.normal1,
                    unique: true,
                }
            } else {
                Closest {
                    d: 0.0,
                    pa: c.point1,
                    pb: c.point1,
                    n: c.normal1,
                    unique: false,
                }
            })
        }
        Err(_) => None,
    }
}
