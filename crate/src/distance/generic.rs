//! parry for the pairs with no closed form here: a convex hull against
//! anything but a plane, and flat figures or boxes against each other.
//! Flat figures become zero-thickness parry shapes (a rectangle a cuboid of
//! zero height, a disk a cylinder of zero height, a polygon the triangle
//! mesh of its ear-clipping triangulation).

use glam::{DMat3, DQuat, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query::{self, ClosestPoints, PointQuery};
use parry3d_f64::shape::{Cuboid, Cylinder, Segment as ParrySegment, Shape, TriMesh};

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
        Core::Polygon(poly) => {
            let v = poly.vertices().to_vec();
            let idx: Vec<[u32; 3]> = poly
                .triangles()
                .iter()
                .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
                .collect();
            (Pose::IDENTITY, Box::new(TriMesh::new(v, idx).ok()?))
        }
        Core::Box(b) => (
            Pose::from_parts(b.center, b.rotation),
            Box::new(Cuboid::new(b.half_extents)),
        ),
        Core::Hull(h) => (Pose::IDENTITY, Box::new(h.shape().clone())),
        Core::Point(_) | Core::Plane(_) => return None,
    })
}

/// Two cores through parry's closest points (and its contact query for the
/// depth when a solid overlaps).
pub(crate) fn generic(a: Core<'_>, b: Core<'_>) -> Result<Closest, DistanceError> {
    let unsupported = || DistanceError::UnsupportedPair {
        a: a.kind(),
        b: b.kind(),
    };
    let (pose_a, sa) = parry_shape(a).ok_or_else(unsupported)?;
    let (pose_b, sb) = parry_shape(b).ok_or_else(unsupported)?;
    match query::closest_points(&pose_a, sa.as_ref(), &pose_b, sb.as_ref(), f64::MAX) {
        Ok(ClosestPoints::WithinMargin(p1, p2)) => Ok(Closest::between(p1, p2, true)),
        Ok(_) => {
            let solid = |c: Core<'_>| matches!(c, Core::Box(_) | Core::Hull(_));
            let contact = query::contact(&pose_a, sa.as_ref(), &pose_b, sb.as_ref(), 0.0)
                .map_err(|_| unsupported())?;
            let Some(c) = contact else {
                return Ok(Closest {
                    d: 0.0,
                    pa: pose_a.translation,
                    pb: pose_a.translation,
                    n: DVec3::ZERO,
                    unique: false,
                });
            };
            if solid(a) || solid(b) {
                Ok(Closest {
                    d: c.dist.min(0.0),
                    pa: c.point1,
                    pb: c.point2,
                    n: c.normal1,
                    unique: true,
                })
            } else {
                Ok(Closest {
                    d: 0.0,
                    pa: c.point1,
                    pb: c.point1,
                    n: c.normal1,
                    unique: false,
                })
            }
        }
        Err(_) => Err(unsupported()),
    }
}
