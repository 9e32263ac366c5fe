//! Obstacles: their figures ([`ShapeSpec`], the composite [`HumanSpec`]),
//! how they move ([`Motion`]), the [`ObstacleSpec`] that joins both, and the
//! geometry a motion needs ([`reference_point`], [`translated`],
//! [`primitives`]).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::nested;
use crate::distance::{Primitive, PrimitiveSpec};
use crate::error::{FieldError, finite, finite3, positive};

pub use crate::human::HumanSpec;

/// The figure of an obstacle: an environment primitive or a human.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSpec {
    /// A primitive (DESIGN `distance(a, b)` shapes).
    Primitive(PrimitiveSpec),
    /// `{ "type": "human", … }`.
    Human(HumanSpec),
}

#[derive(Serialize)]
#[serde(tag = "type", rename_all = "camelCase")]
enum HumanTagged {
    Human(HumanSpec),
}

impl<'de> Deserialize<'de> for ShapeSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        if v.get("type").and_then(|t| t.as_str()) == Some("human") {
            // Read the fields directly (not through the tagged enum, which
            // buffers them and loses the path of a bad value).
            let mut fields = v;
            if let Some(map) = fields.as_object_mut() {
                map.remove("type");
            }
            Ok(Self::Human(nested(fields)?))
        } else {
            Ok(Self::Primitive(nested(v)?))
        }
    }
}

impl Serialize for ShapeSpec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Primitive(p) => p.serialize(s),
            Self::Human(h) => HumanTagged::Human(h.clone()).serialize(s),
        }
    }
}

/// How the times of a list of timed points must grow.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimeOrder {
    /// Equal consecutive times allowed (a jump between waypoints).
    NonDecreasing,
    /// Strictly increasing (a trajectory to interpolate).
    Increasing,
}

/// Checks timed points: at least one, one time per point, finite values,
/// times ordered as `order` says.
pub(crate) fn check_timed_points(
    points: &[[f64; 3]],
    times: &[f64],
    order: TimeOrder,
) -> Result<(), FieldError> {
    if points.is_empty() {
        return Err(FieldError::new("points", "needs at least one point"));
    }
    if points.len() != times.len() {
        return Err(FieldError::new(
            "times",
            format!(
                "expected {} times (one per point), got {}",
                points.len(),
                times.len()
            ),
        ));
    }
    for (k, p) in points.iter().enumerate() {
        finite3(&format!("points[{k}]"), DVec3::from_array(*p))?;
    }
    for (k, t) in times.iter().enumerate() {
        finite(&format!("times[{k}]"), *t)?;
        if k > 0 {
            match order {
                TimeOrder::NonDecreasing if *t < times[k - 1] => {
                    return Err(FieldError::new(format!("times[{k}]"), "must not decrease"));
                }
                TimeOrder::Increasing if *t <= times[k - 1] => {
                    return Err(FieldError::new(format!("times[{k}]"), "must increase"));
                }
                _ => {}
            }
        }
    }
    Ok(())
}

fn translate3(p: [f64; 3], t: DVec3) -> [f64; 3] {
    (DVec3::from_array(p) + t).to_array()
}

/// The point a motion moves and `moveObstacle` places: the floor point of
/// a human, [`PrimitiveSpec::reference_point`] of a primitive (the centre
/// of spheres, boxes, rectangles and disks, the middle of segments and
/// capsules, the vertex mean of polygons and hulls, the point of a plane
/// closest to the origin).
#[must_use]
pub fn reference_point(shape: &ShapeSpec) -> DVec3 {
    match shape {
        ShapeSpec::Human(h) => DVec3::from_array(h.position),
        ShapeSpec::Primitive(p) => p.reference_point(),
    }
}

/// The same figure translated by `t` (m).
#[must_use]
pub fn translated(shape: &ShapeSpec, t: DVec3) -> ShapeSpec {
    let mut out = shape.clone();
    match &mut out {
        ShapeSpec::Human(h) => h.position = translate3(h.position, t),
        ShapeSpec::Primitive(p) => match p {
            PrimitiveSpec::Point(s) => s.p = translate3(s.p, t),
            PrimitiveSpec::Segment(s) => {
                s.a = translate3(s.a, t);
                s.b = translate3(s.b, t);
            }
            PrimitiveSpec::Sphere(s) => s.center = translate3(s.center, t),
            PrimitiveSpec::Capsule(s) => {
                s.a = translate3(s.a, t);
                s.b = translate3(s.b, t);
            }
            PrimitiveSpec::TaperedCapsule(s) => {
                s.a = translate3(s.a, t);
                s.b = translate3(s.b, t);
            }
            PrimitiveSpec::Plane(s) => s.offset -= DVec3::from_array(s.normal).dot(t),
            PrimitiveSpec::Rectangle(s) => s.center = translate3(s.center, t),
            PrimitiveSpec::Disk(s) => s.center = translate3(s.center, t),
            PrimitiveSpec::Polygon(s) => s.vertices.iter_mut().for_each(|p| *p = translate3(*p, t)),
            PrimitiveSpec::Box(s) => s.center = translate3(s.center, t),
            PrimitiveSpec::ConvexHull(s) => {
                s.points.iter_mut().for_each(|p| *p = translate3(*p, t))
            }
        },
    }
    out
}

/// The primitives of a figure (one, or the parts of a human at rest).
///
/// # Errors
/// The primitive's own validation (`radius: must be > 0`, …), or the
/// human's ([`HumanSpec::compile`]: `height: must be > 0`, …).
pub fn primitives(shape: &ShapeSpec) -> Result<Vec<Primitive>, FieldError> {
    match shape {
        ShapeSpec::Primitive(p) => Ok(vec![Primitive::from_spec(p)?]),
        ShapeSpec::Human(h) => {
            h.compile()?;
            h.parts().iter().map(Primitive::from_spec).collect()
        }
    }
}

/// How an obstacle moves: a translation of the whole figure over time.
///
/// It is read through a flat struct of every key (see `tagged.rs`), so that
/// an error names the exact place (`motion.points[1]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(
    tag = "type",
    rename_all = "camelCase",
    try_from = "super::tagged::MotionFields"
)]
pub enum Motion {
    /// Does not move (default).
    #[default]
    Static,
    /// Constant velocity (m/s) from `t = 0`.
    Linear {
        /// Velocity (m/s).
        velocity: [f64; 3],
    },
    /// Piecewise-linear translation through `points` (displacements from
    /// the figure as given, m) at `times` (s, non-decreasing; equal
    /// consecutive times make a jump). Before the first time the first
    /// point, after the last the last one, unless `loop` repeats the
    /// sequence with period `times[last] − times[0]`.
    Waypoints {
        /// Displacements (m).
        points: Vec<[f64; 3]>,
        /// Times (s).
        times: Vec<f64>,
        /// Repeat (default false).
        #[serde(default, rename = "loop")]
        repeat: bool,
    },
    /// The reference point turns about the line through `center` along
    /// `axis` once every `period` seconds (the figure translates, it does
    /// not rotate).
    Circular {
        /// A point of the axis (m).
        center: [f64; 3],
        /// Axis direction (right hand).
        axis: [f64; 3],
        /// Period (s, > 0).
        period: f64,
    },
}

impl Motion {
    /// Checks every value.
    ///
    /// # Errors
    /// `points: …`, `times[2]: must not decrease`, `axis: must not be
    /// zero`, `period: must be > 0`.
    pub fn validate(&self) -> Result<(), FieldError> {
        match self {
            Self::Static => Ok(()),
            Self::Linear { velocity } => {
                finite3("velocity", DVec3::from_array(*velocity)).map(|_| ())
            }
            Self::Waypoints {
                points,
                times,
                repeat,
            } => {
                check_timed_points(points, times, TimeOrder::NonDecreasing)?;
                if *repeat && times.last().copied().unwrap_or(0.0) <= times[0] {
                    return Err(FieldError::new(
                        "loop",
                        "a looping motion needs times spanning a positive period",
                    ));
                }
                Ok(())
            }
            Self::Circular {
                center,
                axis,
                period,
            } => {
                finite3("center", DVec3::from_array(*center))?;
                let a = finite3("axis", DVec3::from_array(*axis))?;
                if a.length_squared() == 0.0 {
                    return Err(FieldError::new("axis", "must not be zero"));
                }
                positive("period", *period)?;
                Ok(())
            }
        }
    }

    /// Displacement (m) at time `t` of a figure whose reference point is
    /// `reference` at rest.
    #[must_use]
    pub fn offset(&self, t: f64, reference: DVec3) -> DVec3 {
        match self {
            Self::Static => DVec3::ZERO,
            Self::Linear { velocity } => DVec3::from_array(*velocity) * t,
            Self::Waypoints {
                points,
                times,
                repeat,
            } => {
                let v = |k: usize| DVec3::from_array(points[k]);
                let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
                    return DVec3::ZERO;
                };
                let mut t = t;
                if *repeat && last > first && t > last {
                    t = first + (t - first).rem_euclid(last - first);
                }
                if t <= first {
                    return v(0);
                }
                // The last k with times[k] ≤ t (jumps take the later point).
                let k = times.partition_point(|&s| s <= t);
                if k >= times.len() {
                    return v(times.len() - 1);
                }
                let (t0, t1) = (times[k - 1], times[k]);
                let u = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
                v(k - 1) + (v(k) - v(k - 1)) * u
            }
            Self::Circular {
                center,
                axis,
                period,
            } => {
                let axis = DVec3::from_array(*axis).normalize_or_zero();
                let r = reference - DVec3::from_array(*center);
                // Rodrigues' rotation of r about the unit axis.
                let (s, c) = crate::math::sin_cos(std::f64::consts::TAU * t / period);
                r * c + axis.cross(r) * s + axis * axis.dot(r) * (1.0 - c) - r
            }
        }
    }
}

/// An obstacle of a scenario.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct ObstacleSpec {
    /// Unique, non-empty id.
    pub id: String,
    /// The figure (at rest, world frame).
    pub shape: ShapeSpec,
    /// How it moves (default static).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<Motion>,
}

impl ObstacleSpec {
    /// Checks the id, the figure and the motion.
    ///
    /// # Errors
    /// `id: must not be empty`, `shape.radius: must be > 0`, `motion.period: …`.
    pub fn validate(&self) -> Result<(), FieldError> {
        super::bounds::check_value("", self)?;
        if self.id.is_empty() {
            return Err(FieldError::new("id", "must not be empty"));
        }
        primitives(&self.shape).map_err(|e| e.within("shape"))?;
        if let Some(m) = &self.motion {
            m.validate().map_err(|e| e.within("motion"))?;
        }
        Ok(())
    }
}

/// A unit quaternion from `[x, y, z, w]`.
///
/// # Errors
/// Not finite or not of unit length (within 1e-6).
pub fn unit_quat(field: &str, q: [f64; 4]) -> Result<DQuat, FieldError> {
    for (k, c) in q.iter().enumerate() {
        finite(&format!("{field}[{k}]"), *c)?;
    }
    let q = DQuat::from_array(q);
    let n = q.length();
    if (n - 1.0).abs() > crate::kinematics::UNIT_QUAT_TOLERANCE {
        return Err(FieldError::new(
            field,
            format!("quaternion [x, y, z, w] must have unit length, got |q| = {n}"),
        ));
    }
    Ok(q / n)
}
