//! [`PrimitiveSpec`], the description of a primitive as it crosses the
//! JavaScript boundary, and its hand-written deserialisation that keeps the
//! path of a bad value.

use serde::{Deserialize, Serialize};

use crate::error::FieldError;

/// The description of a primitive as it crosses the JavaScript boundary
/// (`{ type: "sphere", center: [x, y, z], radius }`, …). Validate it with
/// [`Primitive::from_spec`](super::Primitive::from_spec).
///
/// It serialises as an internally tagged enum. It deserialises through a flat
/// struct holding every key any figure uses, then checks that the keys fit
/// the `type`: unlike serde's buffered tagged enums, this keeps the path of a
/// bad value (`shape.center[1]: not a finite number`) and refuses unknown keys.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "camelCase", try_from = "PrimitiveFields")]
pub enum PrimitiveSpec {
    /// `{ type: "point", p }`.
    Point(PointSpec),
    /// `{ type: "segment", a, b }`.
    Segment(SegmentSpec),
    /// `{ type: "sphere", center, radius }`.
    Sphere(SphereSpec),
    /// `{ type: "capsule", a, b, radius }`.
    Capsule(CapsuleSpec),
    /// `{ type: "taperedCapsule", a, b, radius: [r0, r1] }`.
    TaperedCapsule(TaperedCapsuleSpec),
    /// `{ type: "plane", normal, offset }`: `normal·x + offset = 0`.
    Plane(PlaneSpec),
    /// `{ type: "rectangle", center, axes: [u, v], halfExtents: [hu, hv] }`.
    Rectangle(RectangleSpec),
    /// `{ type: "disk", center, normal, radius }`.
    Disk(DiskSpec),
    /// `{ type: "polygon", vertices }`.
    Polygon(PolygonSpec),
    /// `{ type: "box", center, halfExtents, rotation? }` (`[x, y, z, w]`,
    /// identity when absent).
    Box(BoxSpec),
    /// `{ type: "convexHull", points }`.
    ConvexHull(ConvexHullSpec),
}

/// Fields of `{ type: "point" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// The point.
    pub p: [f64; 3],
}

/// Fields of `{ type: "segment" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Start.
    pub a: [f64; 3],
    /// End.
    pub b: [f64; 3],
}

/// Fields of `{ type: "sphere" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Radius.
    pub radius: f64,
}

/// Fields of `{ type: "capsule" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CapsuleSpec {
    /// Start.
    pub a: [f64; 3],
    /// End.
    pub b: [f64; 3],
    /// Radius.
    pub radius: f64,
}

/// Fields of `{ type: "taperedCapsule" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaperedCapsuleSpec {
    /// Start.
    pub a: [f64; 3],
    /// End.
    pub b: [f64; 3],
    /// Radius at `a` and at `b`.
    pub radius: [f64; 2],
}

/// Fields of `{ type: "plane" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    /// Normal (any non-zero length).
    pub normal: [f64; 3],
    /// Offset.
    pub offset: f64,
}

/// Fields of `{ type: "rectangle" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct RectangleSpec {
    /// Centre.
    pub center: [f64; 3],
    /// In-plane axes.
    pub axes: [[f64; 3]; 2],
    /// Half extents along the axes.
    pub half_extents: [f64; 2],
}

/// Fields of `{ type: "disk" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Normal.
    pub normal: [f64; 3],
    /// Radius.
    pub radius: f64,
}

/// Fields of `{ type: "polygon" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolygonSpec {
    /// Vertices in order.
    pub vertices: Vec<[f64; 3]>,
}

/// Fields of `{ type: "box" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct BoxSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Half extents.
    pub half_extents: [f64; 3],
    /// Orientation quaternion `[x, y, z, w]` (identity when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<[f64; 4]>,
}

/// Fields of `{ type: "convexHull" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConvexHullSpec {
    /// The points whose hull is taken.
    pub points: Vec<[f64; 3]>,
}

/// A radius: one number, or `[r0, r1]` for a tapered capsule.
#[derive(Clone, Copy, Debug, PartialEq)]
enum RadiusField {
    One(f64),
    Two([f64; 2]),
}

impl<'de> Deserialize<'de> for RadiusField {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RadiusField;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number or [r0, r1]")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<RadiusField, E> {
                Ok(RadiusField::One(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<RadiusField, E> {
                Ok(RadiusField::One(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<RadiusField, E> {
                Ok(RadiusField::One(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RadiusField, A::Error> {
                let r0: f64 = seq
                    .next_element()?
                    .ok_or_else(|| serde::de::Error::invalid_length(0, &self))?;
                let r1: f64 = seq
                    .next_element()?
                    .ok_or_else(|| serde::de::Error::invalid_length(1, &self))?;
                if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    return Err(serde::de::Error::invalid_length(3, &self));
                }
                Ok(RadiusField::Two([r0, r1]))
            }
        }
        d.deserialize_any(V)
    }
}

/// A `type` value, checked while deserialising so that the error names the
/// `type` field.
struct PrimitiveKind(String);

impl<'de> Deserialize<'de> for PrimitiveKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let kind = String::deserialize(d)?;
        if PrimitiveSpec::KINDS.contains(&kind.as_str()) {
            Ok(Self(kind))
        } else {
            Err(serde::de::Error::custom(format!(
                "unknown primitive \"{kind}\" (known: {})",
                PrimitiveSpec::KINDS.join(", ")
            )))
        }
    }
}

/// Every key any primitive uses; see [`PrimitiveSpec`].
#[derive(Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct PrimitiveFields {
    #[serde(rename = "type")]
    kind: PrimitiveKind,
    p: Option<[f64; 3]>,
    a: Option<[f64; 3]>,
    b: Option<[f64; 3]>,
    center: Option<[f64; 3]>,
    radius: Option<RadiusField>,
    normal: Option<[f64; 3]>,
    offset: Option<f64>,
    axes: Option<[[f64; 3]; 2]>,
    half_extents: Option<Vec<f64>>,
    vertices: Option<Vec<[f64; 3]>>,
    rotation: Option<[f64; 4]>,
    points: Option<Vec<[f64; 3]>>,
}

impl PrimitiveFields {
    /// The required and the optional keys of a figure of `kind`.
    fn keys(kind: &str) -> (&'static [&'static str], &'static [&'static str]) {
        match kind {
            "point" => (&["p"], &[]),
            "segment" => (&["a", "b"], &[]),
            "sphere" => (&["center", "radius"], &[]),
            "capsule" | "taperedCapsule" => (&["a", "b", "radius"], &[]),
            "plane" => (&["normal", "offset"], &[]),
            "rectangle" => (&["center", "axes", "halfExtents"], &[]),
            "disk" => (&["center", "normal", "radius"], &[]),
            "polygon" => (&["vertices"], &[]),
            "box" => (&["center", "halfExtents"], &["rotation"]),
            _ => (&["points"], &[]),
        }
    }

    /// Checks that every required key of a `kind` is present and no other
    /// key but its optional ones.
    fn check_keys(&self, kind: &str) -> Result<(), String> {
        let present = [
            ("p", self.p.is_some()),
            ("a", self.a.is_some()),
            ("b", self.b.is_some()),
            ("center", self.center.is_some()),
            ("radius", self.radius.is_some()),
            ("normal", self.normal.is_some()),
            ("offset", self.offset.is_some()),
            ("axes", self.axes.is_some()),
            ("halfExtents", self.half_extents.is_some()),
            ("vertices", self.vertices.is_some()),
            ("rotation", self.rotation.is_some()),
            ("points", self.points.is_some()),
        ];
        let (required, optional) = Self::keys(kind);
        let fields = || {
            required
                .iter()
                .chain(optional)
                .copied()
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (name, is) in present {
            if is && !required.contains(&name) && !optional.contains(&name) {
                return Err(format!(
                    "`{name}` is not a field of a {kind} (its fields: {})",
                    fields()
                ));
            }
            if !is && required.contains(&name) {
                return Err(format!("missing `{name}` (a {kind} needs {})", fields()));
            }
        }
        Ok(())
    }
}

impl TryFrom<PrimitiveFields> for PrimitiveSpec {
    type Error = String;

    fn try_from(f: PrimitiveFields) -> Result<Self, String> {
        let kind = f.kind.0.as_str();
        f.check_keys(kind)?;
        let missing = || String::from("internal: a required field went missing");
        let one = |r: Option<RadiusField>| match r {
            Some(RadiusField::One(x)) => Ok(x),
            _ => Err(format!("`radius` of a {kind} is one number")),
        };
        let half = |h: Option<Vec<f64>>, n: usize| -> Result<Vec<f64>, String> {
            let h = h.ok_or_else(missing)?;
            if h.len() == n {
                Ok(h)
            } else {
                Err(format!(
                    "`halfExtents` of a {kind} has {n} numbers, got {}",
                    h.len()
                ))
            }
        };
        Ok(match kind {
            "point" => Self::Point(PointSpec {
                p: f.p.ok_or_else(missing)?,
            }),
            "segment" => Self::Segment(SegmentSpec {
                a: f.a.ok_or_else(missing)?,
                b: f.b.ok_or_else(missing)?,
            }),
            "sphere" => Self::Sphere(SphereSpec {
                center: f.center.ok_or_else(missing)?,
                radius: one(f.radius)?,
            }),
            "capsule" => Self::Capsule(CapsuleSpec {
                a: f.a.ok_or_else(missing)?,
                b: f.b.ok_or_else(missing)?,
                radius: one(f.radius)?,
            }),
            "taperedCapsule" => Self::TaperedCapsule(TaperedCapsuleSpec {
                a: f.a.ok_or_else(missing)?,
                b: f.b.ok_or_else(missing)?,
                radius: match f.radius {
                    Some(RadiusField::Two(r)) => r,
                    _ => return Err("`radius` of a taperedCapsule is [r0, r1]".to_owned()),
                },
            }),
            "plane" => Self::Plane(PlaneSpec {
                normal: f.normal.ok_or_else(missing)?,
                offset: f.offset.ok_or_else(missing)?,
            }),
            "rectangle" => {
                let h = half(f.half_extents, 2)?;
                Self::Rectangle(RectangleSpec {
                    center: f.center.ok_or_else(missing)?,
                    axes: f.axes.ok_or_else(missing)?,
                    half_extents: [h[0], h[1]],
                })
            }
            "disk" => Self::Disk(DiskSpec {
                center: f.center.ok_or_else(missing)?,
                normal: f.normal.ok_or_else(missing)?,
                radius: one(f.radius)?,
            }),
            "polygon" => Self::Polygon(PolygonSpec {
                vertices: f.vertices.ok_or_else(missing)?,
            }),
            "box" => {
                let h = half(f.half_extents, 3)?;
                Self::Box(BoxSpec {
                    center: f.center.ok_or_else(missing)?,
                    half_extents: [h[0], h[1], h[2]],
                    rotation: f.rotation,
                })
            }
            _ => Self::ConvexHull(ConvexHullSpec {
                points: f.points.ok_or_else(missing)?,
            }),
        })
    }
}

impl PrimitiveSpec {
    /// Every accepted `type` value.
    pub const KINDS: [&'static str; 11] = [
        "point",
        "segment",
        "sphere",
        "capsule",
        "taperedCapsule",
        "plane",
        "rectangle",
        "disk",
        "polygon",
        "box",
        "convexHull",
    ];

    /// Checks a `type` value before the rest is read, so an unknown figure is
    /// reported as such.
    ///
    /// # Errors
    /// `type: unknown primitive "cone"`.
    pub fn check_kind(kind: &str) -> Result<(), FieldError> {
        if Self::KINDS.contains(&kind) {
            Ok(())
        } else {
            Err(FieldError::new(
                "type",
                format!("unknown primitive \"{kind}\""),
            ))
        }
    }

    /// The figure's reference point (m): the centre of spheres, boxes,
    /// rectangles and disks, the middle of segments and capsules, the point
    /// itself, the vertex mean of polygons and hulls, the point of a plane
    /// closest to the origin. Motions move it, `moveObstacle` places it, the
    /// viewer frames it.
    ///
    /// See also [`crate::scenario::reference_point`] for whole figures.
    #[must_use]
    pub fn reference_point(&self) -> glam::DVec3 {
        use glam::DVec3;
        let v = DVec3::from_array;
        let mean = |pts: &[[f64; 3]]| {
            if pts.is_empty() {
                DVec3::ZERO
            } else {
                pts.iter().map(|p| v(*p)).sum::<DVec3>() / pts.len() as f64
            }
        };
        match self {
            Self::Point(s) => v(s.p),
            Self::Segment(SegmentSpec { a, b })
            | Self::Capsule(CapsuleSpec { a, b, .. })
            | Self::TaperedCapsule(TaperedCapsuleSpec { a, b, .. }) => (v(*a) + v(*b)) * 0.5,
            Self::Sphere(SphereSpec { center, .. })
            | Self::Rectangle(RectangleSpec { center, .. })
            | Self::Disk(DiskSpec { center, .. })
            | Self::Box(BoxSpec { center, .. }) => v(*center),
            Self::Plane(s) => {
                let n = v(s.normal);
                let l2 = n.length_squared();
                if l2 > 0.0 {
                    -s.offset * n / l2
                } else {
                    DVec3::ZERO
                }
            }
            Self::Polygon(s) => mean(&s.vertices),
            Self::ConvexHull(s) => mean(&s.points),
        }
    }
}
