//! How finely a capsule or sphere is cut into triangles for the screen: the
//! unit template the renderer places at each solid's end points and radii,
//! and the level of detail that follows the solid's size on screen.
//!
//! A solid whose larger radius spans `r` pixels is drawn with the fewest
//! sectors `n` around its axis whose polygon stays within the tolerance `ε`
//! of the true circle: the sagitta `r (1 − cos(π/n)) ≤ ε`, so
//! `n = ⌈π / acos(1 − ε/r)⌉`, between [`MIN_SECTORS`] and [`MAX_SECTORS`].
//! Each hemisphere gets `⌈n/4⌉` rings (at least two), so a meridian, the
//! outline of a cap seen from the side, is cut no coarser than the equator.
//! A template of `n` sectors and `m` rings has `4 n m` triangles.
//!
//! Why a level per sector count rather than a few fixed levels: on a
//! software rasteriser (SwiftShader in headless Chromium) each triangle
//! costs the browser's GPU process about 2 µs whatever its size, and most
//! solids of a scene are small (skeleton nodes, control points, margins, a
//! person's hands and feet a few pixels across). Three fixed levels of 120,
//! 280 and 504 triangles gave a node sphere 3 px across 120 triangles where
//! 48 keep its outline; the levels per sector count draw `human-panda`
//! with 4 114 triangles instead of 7 141, its larger circles as finely cut
//! as before (the renderer's tolerances: `render/buffers.rs`; the frame
//! rates: the README's benchmarks).

/// How far (px) an outline may stray from the true one on a GPU: a solid's
/// from its circle, a link mesh's from its full surface (`view::meshes`).
pub(crate) const TOLERANCE: f32 = 0.5;

/// The same on a software rasteriser, where every triangle costs the
/// browser's GPU process about 2 µs whatever its size (SwiftShader).
/// Drawing the solids coarser there, with three fixed levels of detail,
/// took planar-transition from 50.4 to 56.9 fps and human-panda from 34.9
/// to 41.3 (interleaved, four rounds, the machine of 2026-11-25). With a
/// level per sector count, 1.5 px left the larger circles of the 2D views
/// visibly polygonal (a node 35 px across in `chattering` got 11 sides):
/// 1 px gives it 14, as many as the fixed levels did, while the small
/// solids, most of a scene, keep their few triangles. On a GPU triangles
/// cost next to nothing and the finer outline is kept.
pub(crate) const SOFTWARE_TOLERANCE: f32 = 1.0;

/// [`SOFTWARE_TOLERANCE`] on a software rasteriser, else [`TOLERANCE`].
pub(crate) fn tolerance(software: bool) -> f32 {
    if software {
        SOFTWARE_TOLERANCE
    } else {
        TOLERANCE
    }
}

/// Fewest sectors a solid is drawn with: a hexagon, within 0.5 px of the
/// circle up to a radius of 3.7 px, within 1 px up to 7.5 px.
pub(crate) const MIN_SECTORS: u32 = 6;

/// Most sectors a solid is drawn with: within 0.5 px of the circle up to
/// a radius of about 160 px, 1 px up to 320 px; larger solids stray a
/// little more.
pub(crate) const MAX_SECTORS: u32 = 40;

/// The fewest sectors (within [`MIN_SECTORS`]..=[`MAX_SECTORS`]) whose
/// polygon keeps a circle of radius `pixels` within `tolerance` pixels.
/// A radius that is not finite gets the most.
pub(crate) fn sectors_for(pixels: f32, tolerance: f32) -> u32 {
    if pixels.is_nan() || pixels == f32::INFINITY {
        return MAX_SECTORS;
    }
    if pixels <= tolerance {
        return MIN_SECTORS;
    }
    let n = (std::f32::consts::PI / (1.0 - tolerance / pixels).acos()).ceil();
    // `n` is at least 2 here (acos ≤ π/2 for a ratio in 0..1).
    (n as u32).clamp(MIN_SECTORS, MAX_SECTORS)
}

/// Rings per hemisphere for `sectors` around the axis: a polar step no
/// coarser than the sector step (90° / rings ≤ 360° / sectors), at least 2.
pub(crate) fn rings_for(sectors: u32) -> u32 {
    sectors.div_ceil(4).max(2)
}

/// A vertex of the capsule template: a unit direction in the capsule's
/// frame (z along the axis) and the end it hangs from (`false`: `a`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TemplateVertex {
    pub dir: [f32; 3],
    pub at_b: bool,
}

/// The capsule template at one level of detail: unit directions with the
/// end they hang from, and triangles (indices into them),
/// counter-clockwise seen from outside.
#[derive(Clone, Debug, Default)]
pub(crate) struct Template {
    pub vertices: Vec<TemplateVertex>,
    pub triangles: Vec<[u16; 3]>,
    /// The radius, as a fraction of the solid's, of the largest ball about
    /// a point of the axis that the drawn solid holds: the least distance
    /// of a face's plane from the centre of the unit sphere drawn with this
    /// template. With equal radii the drawn capsule is that polytope swept
    /// along the axis, so it holds every point nearer to the axis than
    /// `inner` times the radius (`render::occlusion`).
    pub inner: f32,
}

/// The templates of every sector count, built once.
#[derive(Clone, Debug)]
pub(crate) struct Templates(Vec<Template>);

impl Default for Templates {
    fn default() -> Self {
        Self(
            (MIN_SECTORS..=MAX_SECTORS)
                .map(|n| capsule_template(rings_for(n), n))
                .collect(),
        )
    }
}

impl Templates {
    /// The template for a solid whose larger radius spans `pixels` on
    /// screen, kept within `tolerance` pixels.
    pub fn for_radius(&self, pixels: f32, tolerance: f32) -> &Template {
        &self.0[(sectors_for(pixels, tolerance) - MIN_SECTORS) as usize]
    }
}

/// The capsule template as indexed triangles (a vertex grid shared by its
/// neighbours, so each is lit once), with `rings` per hemisphere and
/// `sectors` around the axis.
///
/// Two hemispheres, the one at `a` (pointing along −z) and the one at `b`
/// (along +z), each with its own equator ring, joined by a band: with equal
/// end points and radii it is a sphere. The rows at the poles are single
/// points repeated around the axis, so the triangles of the bands next to
/// them are fans: the quads' other halves would have no area.
fn capsule_template(rings: u32, sectors: u32) -> Template {
    use std::f32::consts::{FRAC_PI_2, PI, TAU};
    // Rows of unit directions, from the −z pole to the +z pole; each row
    // carries the end it belongs to. The two equator rows are the band.
    let polar = |i: u32| i as f32 / rings as f32 * FRAC_PI_2;
    let rows: Vec<(f32, bool)> = (0..=rings)
        .map(|i| (PI - polar(i), false))
        .chain((0..=rings).map(|i| (FRAC_PI_2 - polar(i), true)))
        .collect();
    let columns = sectors + 1; // the seam is duplicated
    let mut vertices = Vec::with_capacity(rows.len() * columns as usize);
    for &(polar, at_b) in &rows {
        let (s, c) = polar.sin_cos();
        for j in 0..columns {
            let phi = j as f32 / sectors as f32 * TAU;
            vertices.push(TemplateVertex {
                dir: [s * phi.cos(), s * phi.sin(), c],
                at_b,
            });
        }
    }
    let last_band = rows.len() as u32 - 2;
    let mut triangles = Vec::with_capacity(4 * (rings * sectors) as usize);
    for r in 0..=last_band {
        for j in 0..sectors {
            let a = (r * columns + j) as u16;
            let b = a + 1;
            let c = a + columns as u16;
            let d = c + 1;
            // Counter-clockwise seen from outside; a and b are one point on
            // the first row, c and d on the last.
            if r != 0 {
                triangles.push([a, b, d]);
            }
            if r != last_band {
                triangles.push([a, d, c]);
            }
        }
    }
    // The band's triangles have no area on the sphere: they are the faces
    // the sweep along the axis adds.
    let inner = triangles
        .iter()
        .filter_map(|tri| {
            let [p, q, r] = tri.map(|k| glam::Vec3::from(vertices[usize::from(k)].dir));
            Some((q - p).cross(r - p).try_normalize()?.dot(p))
        })
        .fold(1.0_f32, f32::min);
    Template {
        vertices,
        triangles,
        inner,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use glam::Vec3;
    use std::collections::HashMap;

    fn sagitta(pixels: f32, sectors: u32) -> f32 {
        pixels * (1.0 - (std::f32::consts::PI / sectors as f32).cos())
    }

    #[test]
    fn sectors_are_the_fewest_within_the_tolerance() {
        for tolerance in [0.5_f32, 1.0] {
            for k in 1..2000 {
                let pixels = k as f32 * 0.25;
                let n = sectors_for(pixels, tolerance);
                assert!((MIN_SECTORS..=MAX_SECTORS).contains(&n));
                if n < MAX_SECTORS {
                    assert!(sagitta(pixels, n) <= tolerance * 1.0001, "{pixels} px: {n}");
                }
                if n > MIN_SECTORS {
                    assert!(
                        sagitta(pixels, n - 1) > tolerance,
                        "{pixels} px: {n} not the fewest"
                    );
                }
            }
        }
        assert_eq!(sectors_for(f32::NAN, 1.0), MAX_SECTORS);
        assert_eq!(sectors_for(f32::INFINITY, 1.0), MAX_SECTORS);
        assert_eq!(sectors_for(-3.0, 1.0), MIN_SECTORS);
        assert_eq!(sectors_for(0.0, 1.0), MIN_SECTORS);
    }

    #[test]
    fn rings_cut_a_meridian_no_coarser_than_the_equator() {
        for n in MIN_SECTORS..=MAX_SECTORS {
            let m = rings_for(n);
            assert!(
                90.0 / m as f32 <= 360.0 / n as f32 + 1e-4,
                "{n} sectors, {m} rings"
            );
            assert!(
                m == 2 || 90.0 / (m - 1) as f32 > 360.0 / n as f32,
                "{n}: {m} rings, not the fewest"
            );
        }
    }

    /// Every template is a closed, outward-facing surface of `4 n m`
    /// triangles, none of them degenerate: each edge is shared by exactly
    /// two triangles running it in opposite directions (positions compared,
    /// the seam and the poles being duplicated vertices), and each normal
    /// points away from the axis' centre.
    #[test]
    fn every_template_is_closed_and_faces_outwards() {
        let templates = Templates::default();
        for n in MIN_SECTORS..=MAX_SECTORS {
            let t = &templates.0[(n - MIN_SECTORS) as usize];
            assert_eq!(t.triangles.len() as u32, 4 * n * rings_for(n));
            // A capsule of length 2 along z, radii 1 and 0.5.
            let place = |k: u16| {
                let v = t.vertices[k as usize];
                let (centre, radius) = if v.at_b {
                    (Vec3::Z, 0.5)
                } else {
                    (-Vec3::Z, 1.0)
                };
                centre + radius * Vec3::from(v.dir)
            };
            let key = |p: Vec3| (p * 1e4).round().to_array().map(|x| x as i64);
            let mut edges: HashMap<_, i32> = HashMap::new();
            for tri in &t.triangles {
                let [p, q, r] = tri.map(place);
                let normal = (q - p).cross(r - p);
                assert!(
                    normal.length() > 1e-6,
                    "{n} sectors: degenerate triangle {tri:?}"
                );
                assert!(
                    normal.dot((p + q + r) / 3.0) > 0.0,
                    "{n} sectors: {tri:?} faces inwards"
                );
                for (a, b) in [(p, q), (q, r), (r, p)] {
                    *edges.entry((key(a), key(b))).or_default() += 1;
                    *edges.entry((key(b), key(a))).or_default() -= 1;
                }
            }
            assert!(
                edges.values().all(|&c| c == 0),
                "{n} sectors: the surface is not closed"
            );
        }
    }

    #[test]
    fn small_solids_get_few_triangles_and_large_ones_many() {
        let templates = Templates::default();
        let triangles = |px| templates.for_radius(px, 0.5).triangles.len();
        assert_eq!(triangles(2.0), 48);
        assert!(triangles(30.0) < triangles(100.0));
        assert_eq!(
            triangles(1e6),
            (4 * MAX_SECTORS * rings_for(MAX_SECTORS)) as usize
        );
    }
}
