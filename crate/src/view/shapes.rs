//! Obstacle primitives as scene items: solids for the round figures,
//! flat-shaded triangles with an outline for the flat ones, a wire star for
//! a convex hull, and the translucent region of a sensing margin.

use glam::{DQuat, DVec3};

use super::drawing::{Capsule, Drawing, Line, Sphere};
use crate::distance::{
    BoxSpec, CapsuleSpec, ConvexHullSpec, DiskSpec, PlaneSpec, PointSpec, Polygon, PolygonSpec,
    PrimitiveSpec, RectangleSpec, SegmentSpec, SphereSpec, TaperedCapsuleSpec,
};

/// Radius of a point obstacle and thickness of a segment obstacle (m).
pub const THIN: f32 = 0.012;

/// The colours one obstacle is drawn in (sRGB, alpha < 1 is translucent).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Palette {
    /// Volumes: spheres, capsules, boxes, points and segments.
    pub solid: [f32; 4],
    /// Bounded flat figures: rectangles, disks, polygons.
    pub flat: [f32; 4],
    /// The square standing for an infinite plane.
    pub plane: [f32; 4],
    /// Edges and rims of flat figures and boxes.
    pub outline: [f32; 4],
}

impl Palette {
    /// An ordinary obstacle.
    pub const OBSTACLE: Self = Self {
        solid: [0.85, 0.33, 0.28, 1.0],
        flat: [0.85, 0.45, 0.30, 0.55],
        plane: [0.55, 0.62, 0.72, 0.25],
        outline: [0.45, 0.18, 0.12, 1.0],
    };
    /// The obstacle the person selected.
    pub const SELECTED: Self = Self {
        solid: [0.98, 0.78, 0.10, 1.0],
        flat: [0.98, 0.78, 0.10, 0.6],
        plane: [0.98, 0.78, 0.10, 0.6],
        outline: [0.70, 0.45, 0.0, 1.0],
    };
    /// A human figure (skin-coloured volumes).
    pub const HUMAN: Self = Self {
        solid: [0.90, 0.72, 0.58, 1.0],
        ..Self::OBSTACLE
    };
}

/// Colour of sensing-margin regions.
pub const UNCERTAINTY: [f32; 4] = [0.95, 0.60, 0.10, 0.22];

/// `f64` metres to the renderer's `f32`.
#[must_use]
pub fn v(p: [f64; 3]) -> [f32; 3] {
    [p[0] as f32, p[1] as f32, p[2] as f32]
}

/// Adds `shape` to `scene` in `palette`; an infinite plane becomes a square
/// of `plane_extent` metres (half side) around the point of the plane
/// nearest `around`.
pub fn draw_shape(
    scene: &mut Drawing,
    shape: &PrimitiveSpec,
    palette: &Palette,
    around: [f64; 3],
    plane_extent: f64,
) {
    if draw_round(scene, shape, palette.solid) {
        return;
    }
    match shape {
        PrimitiveSpec::Plane(PlaneSpec { normal, offset }) => scene.push_plane(
            v(*normal),
            *offset as f32,
            v(around),
            plane_extent as f32,
            palette.plane,
            palette.outline,
        ),
        PrimitiveSpec::Box(b) => draw_box(scene, b, palette),
        PrimitiveSpec::ConvexHull(ConvexHullSpec { points }) => {
            let c = v(shape.reference_point().to_array());
            for p in points {
                scene.spheres.push(Sphere {
                    center: v(*p),
                    radius: THIN,
                    color: palette.solid,
                });
                scene.lines.push(Line {
                    a: c,
                    b: v(*p),
                    width: 1.5,
                    color: palette.outline,
                });
            }
        }
        _ => draw_flat(scene, shape, palette),
    }
}

/// Points, segments, spheres and (tapered) capsules as one solid each;
/// `false` for any other figure (nothing added).
fn draw_round(scene: &mut Drawing, shape: &PrimitiveSpec, color: [f32; 4]) -> bool {
    let capsule = |a: &[f64; 3], b: &[f64; 3], radius: [f32; 2]| Capsule {
        a: v(*a),
        b: v(*b),
        radius,
        color,
    };
    match shape {
        PrimitiveSpec::Point(PointSpec { p }) => scene.spheres.push(Sphere {
            center: v(*p),
            radius: 1.5 * THIN,
            color,
        }),
        PrimitiveSpec::Sphere(SphereSpec { center, radius }) => scene.spheres.push(Sphere {
            center: v(*center),
            radius: *radius as f32,
            color,
        }),
        PrimitiveSpec::Segment(SegmentSpec { a, b }) => {
            scene.capsules.push(capsule(a, b, [THIN; 2]));
        }
        PrimitiveSpec::Capsule(CapsuleSpec { a, b, radius }) => {
            scene.capsules.push(capsule(a, b, [*radius as f32; 2]));
        }
        PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec { a, b, radius }) => {
            scene
                .capsules
                .push(capsule(a, b, [radius[0] as f32, radius[1] as f32]));
        }
        _ => return false,
    }
    true
}

/// Rectangles, disks and polygons: translucent triangles and an outline.
fn draw_flat(scene: &mut Drawing, shape: &PrimitiveSpec, palette: &Palette) {
    match shape {
        PrimitiveSpec::Rectangle(RectangleSpec {
            center,
            axes,
            half_extents,
        }) => scene.push_rectangle(
            v(*center),
            [v(axes[0]), v(axes[1])],
            [half_extents[0] as f32, half_extents[1] as f32],
            palette.flat,
            palette.outline,
        ),
        PrimitiveSpec::Disk(DiskSpec {
            center,
            normal,
            radius,
        }) => {
            let n = DVec3::from(*normal).normalize_or(DVec3::Z);
            scene.push_disk(
                v(*center),
                v(n.to_array()),
                *radius as f32,
                palette.flat,
                palette.outline,
            );
        }
        PrimitiveSpec::Polygon(PolygonSpec { vertices }) => {
            let points: Vec<[f32; 3]> = vertices.iter().map(|p| v(*p)).collect();
            // The library's triangulation; a fan when the polygon is refused.
            let triangles = Polygon::new(vertices.iter().map(|p| DVec3::from(*p)).collect())
                .map(|p| p.triangles())
                .unwrap_or_default();
            scene.push_polygon(&points, &triangles, palette.flat, palette.outline);
        }
        _ => {}
    }
}

/// An oriented box; a rotation that is not finite or is zero draws it
/// axis-aligned.
fn draw_box(scene: &mut Drawing, b: &BoxSpec, palette: &Palette) {
    let q = b
        .rotation
        .map(DQuat::from_array)
        .filter(|q| q.is_finite() && q.length() > 1e-9)
        .map_or(DQuat::IDENTITY, DQuat::normalize);
    let axes = [DVec3::X, DVec3::Y, DVec3::Z].map(|a| v((q * a).to_array()));
    scene.push_box(
        v(b.center),
        axes,
        v(b.half_extents),
        palette.solid,
        palette.outline,
    );
}

/// Adds the region within `margin` of a round primitive (point, segment,
/// sphere, capsule) as a translucent volume; `false` (nothing added) for the
/// other figures, whose margin is drawn around the witness points instead.
pub fn draw_inflated(scene: &mut Drawing, shape: &PrimitiveSpec, margin: f32) -> bool {
    let before = (scene.capsules.len(), scene.spheres.len());
    if !draw_round(scene, shape, UNCERTAINTY) {
        return false;
    }
    for c in &mut scene.capsules[before.0..] {
        c.radius = if matches!(shape, PrimitiveSpec::Segment(_)) {
            [margin; 2]
        } else {
            [c.radius[0] + margin, c.radius[1] + margin]
        };
    }
    for s in &mut scene.spheres[before.1..] {
        s.radius = if matches!(shape, PrimitiveSpec::Point(_)) {
            margin
        } else {
            s.radius + margin
        };
    }
    true
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;

    #[test]
    fn round_shapes_are_one_solid_each() {
        let shapes = [
            PrimitiveSpec::Point(PointSpec { p: [0.0; 3] }),
            PrimitiveSpec::Sphere(SphereSpec {
                center: [1.0, 0.0, 0.0],
                radius: 0.2,
            }),
            PrimitiveSpec::Segment(SegmentSpec {
                a: [0.0; 3],
                b: [0.0, 0.0, 1.0],
            }),
            PrimitiveSpec::Capsule(CapsuleSpec {
                a: [0.0; 3],
                b: [0.0, 1.0, 0.0],
                radius: 0.1,
            }),
        ];
        let mut scene = Drawing::new();
        for s in &shapes {
            draw_shape(&mut scene, s, &Palette::OBSTACLE, [0.0; 3], 1.0);
        }
        assert_eq!((scene.spheres.len(), scene.capsules.len()), (2, 2));
        assert!(scene.lines.is_empty() && scene.triangles.is_empty());
        assert_eq!(scene.spheres[1].radius, 0.2);
    }

    #[test]
    fn margins_grow_round_shapes_and_skip_flat_ones() {
        let mut scene = Drawing::new();
        let sphere = PrimitiveSpec::Sphere(SphereSpec {
            center: [0.0; 3],
            radius: 0.2,
        });
        let point = PrimitiveSpec::Point(PointSpec { p: [0.0; 3] });
        let segment = PrimitiveSpec::Segment(SegmentSpec {
            a: [0.0; 3],
            b: [1.0, 0.0, 0.0],
        });
        let plane = PrimitiveSpec::Plane(PlaneSpec {
            normal: [0.0, 0.0, 1.0],
            offset: 0.0,
        });
        assert!(draw_inflated(&mut scene, &sphere, 0.05));
        assert!(draw_inflated(&mut scene, &point, 0.05));
        assert!(draw_inflated(&mut scene, &segment, 0.05));
        assert!(!draw_inflated(&mut scene, &plane, 0.05));
        let radii: Vec<f32> = scene.spheres.iter().map(|s| s.radius).collect();
        assert_eq!(radii, [0.25, 0.05]);
        assert_eq!(scene.capsules[0].radius, [0.05; 2]);
        assert!(scene.spheres.iter().all(|s| s.color == UNCERTAINTY));
    }

    #[test]
    fn a_box_has_twelve_triangles_and_twelve_edges() {
        let mut scene = Drawing::new();
        let b = PrimitiveSpec::Box(BoxSpec {
            center: [0.0; 3],
            half_extents: [0.1, 0.2, 0.3],
            rotation: Some([0.0, 0.0, 0.0, 0.0]),
        });
        draw_shape(&mut scene, &b, &Palette::SELECTED, [0.0; 3], 1.0);
        assert_eq!((scene.triangles.len(), scene.lines.len()), (12, 12));
        // The zero rotation falls back to the identity: corners on the axes.
        let xs: Vec<f32> = scene
            .triangles
            .iter()
            .flat_map(|t| t.p.map(|p| p[0].abs()))
            .collect();
        assert!(xs.iter().all(|x| (x - 0.1).abs() < 1e-6));
    }
}
