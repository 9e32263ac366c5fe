//! Triangles of a capsule or sphere that lie inside an opaque one are not
//! drawn.
//!
//! Where a person's forearm meets the upper arm, the smaller capsule's cap
//! is inside the larger one, and half of the larger cap inside the forearm;
//! the same at every joint of a body or a chain of obstacles. Those
//! triangles can never be seen (the opaque solid's surface is drawn in
//! front of them, with depth written, before anything translucent), yet a
//! software rasteriser (SwiftShader) spends about 2 µs on each
//! (`view::tessellation`).
//!
//! A triangle is left out when its three corners lie within `inner · r` of
//! the axis of one opaque capsule or sphere of equal radii `r`, `inner`
//! being the fraction of the radius that its drawn polytope holds about
//! every point of its axis ([`Template::inner`]). That set is convex and
//! inside the drawn polytope, so the whole triangle is hidden by the
//! polytope's front faces; surfaces that touch or coincide are kept (a
//! corner exactly on another solid's surface is not inside it). Tapered
//! capsules (the skeleton's volumes, translucent anyway) hide nothing here:
//! their drawn shape is not convex where the band meets a cap. A solid that
//! the camera's near plane may cut (its surface within twice the near
//! distance of the eye) hides nothing either: its inside may show.

use glam::Vec3;

use super::tessellation::Template;

/// An opaque solid of equal radii that may hide other solids' triangles.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Occluder {
    a: Vec3,
    /// Unit axis from `a` to `b` (any unit vector for a sphere).
    axis: Vec3,
    length: f32,
    /// The radius of the set of hidden points about the axis.
    inner: f32,
    /// Bounding sphere.
    centre: Vec3,
    bound: f32,
}

/// What a solid needs to be tested: its end points and radii.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ends {
    pub a: Vec3,
    pub b: Vec3,
    pub radii: [f32; 2],
}

impl Ends {
    /// The centre and radius of a sphere holding the solid.
    fn bounding_sphere(&self) -> (Vec3, f32) {
        let centre = 0.5 * (self.a + self.b);
        (
            centre,
            0.5 * self.a.distance(self.b) + self.radii[0].max(self.radii[1]),
        )
    }

    /// Distance from `p` to the segment `a b`.
    fn axis_distance(&self, p: Vec3) -> f32 {
        let ab = self.b - self.a;
        let t = if ab.length_squared() > 0.0 {
            ((p - self.a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        p.distance(self.a + t * ab)
    }
}

impl Occluder {
    /// The occluder of an opaque solid drawn with `template`, or `None`
    /// when it cannot hide anything safely: tapered, without volume, or
    /// possibly cut by the near plane `near` metres in front of `eye`
    /// (`None` for an orthographic camera, whose depth range holds the
    /// scene).
    pub fn new(solid: Ends, template: &Template, eye: Option<(Vec3, f32)>) -> Option<Self> {
        let [r0, r1] = solid.radii;
        let radius = r0.max(r1);
        if radius.is_nan() || radius <= 0.0 || (r0 - r1).abs() > 1e-6 * radius {
            return None;
        }
        if let Some((eye, near)) = eye
            && solid.axis_distance(eye) <= radius + 2.0 * near
        {
            return None;
        }
        let length = solid.a.distance(solid.b);
        let axis = (solid.b - solid.a).try_normalize().unwrap_or(Vec3::Z);
        let (centre, bound) = solid.bounding_sphere();
        // A hair inside, so that a corner on the surface is not counted in.
        let inner = template.inner * radius * (1.0 - 1e-4);
        Some(Self {
            a: solid.a,
            axis,
            length,
            inner,
            centre,
            bound,
        })
    }

    /// Whether the point `p` lies within the hidden set.
    pub fn hides(&self, p: Vec3) -> bool {
        let t = (p - self.a).dot(self.axis).clamp(0.0, self.length);
        p.distance_squared(self.a + t * self.axis) < self.inner * self.inner
    }

    /// Whether this occluder's bounding sphere meets the solid's.
    fn meets(&self, solid: &Ends) -> bool {
        let (centre, bound) = solid.bounding_sphere();
        centre.distance(self.centre) < bound + self.bound
    }
}

/// The occluders of a frame, and those that may hide part of a given solid.
#[derive(Debug, Default)]
pub(crate) struct Occluders {
    all: Vec<Occluder>,
    /// The indices (into `all`) near the solid being drawn.
    near: Vec<usize>,
}

/// Most occluders a solid is tested against (the bits of a mask).
const MOST: usize = 32;

impl Occluders {
    pub fn clear(&mut self) {
        self.all.clear();
        self.near.clear();
    }

    pub fn push(&mut self, occluder: Option<Occluder>) {
        self.all.extend(occluder);
    }

    /// Chooses the occluders that may hide part of `solid` (at most 32;
    /// the solid itself, whose surface is not inside it, is harmless).
    pub fn select_near(&mut self, solid: &Ends) {
        self.near.clear();
        let near = self.all.iter().enumerate().filter(|(_, o)| o.meets(solid));
        self.near.extend(near.map(|(k, _)| k).take(MOST));
    }

    /// Of the occluders chosen by [`Self::select_near`], a bit for each
    /// that hides `p`.
    pub fn mask(&self, p: Vec3) -> u32 {
        self.near
            .iter()
            .enumerate()
            .filter(|&(_, &k)| self.all[k].hides(p))
            .fold(0, |mask, (bit, _)| mask | 1 << bit)
    }

    /// Whether any occluder is near the solid chosen last.
    pub fn any_near(&self) -> bool {
        !self.near.is_empty()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::rng::Rng;
    use crate::view::tessellation::{MAX_SECTORS, MIN_SECTORS, Templates, sectors_for};

    /// The template's vertices placed on a capsule from `a` to `b`.
    fn place(template: &Template, ends: &Ends) -> Vec<Vec3> {
        let axis = (ends.b - ends.a).try_normalize().unwrap_or(Vec3::Z);
        let helper = if axis.x.abs() > 0.9 { Vec3::Y } else { Vec3::X };
        let u = helper.cross(axis).normalize();
        let v = axis.cross(u);
        template
            .vertices
            .iter()
            .map(|t| {
                let n = u * t.dir[0] + v * t.dir[1] + axis * t.dir[2];
                if t.at_b {
                    ends.b + ends.radii[1] * n
                } else {
                    ends.a + ends.radii[0] * n
                }
            })
            .collect()
    }

    /// Whether `p` is inside every face plane of the drawn (convex) solid.
    fn inside_drawn(template: &Template, vertices: &[Vec3], p: Vec3) -> bool {
        template.triangles.iter().all(|tri| {
            let [a, b, c] = tri.map(|k| vertices[usize::from(k)]);
            match (b - a).cross(c - a).try_normalize() {
                Some(n) => n.dot(p - a) <= 1e-6,
                None => true,
            }
        })
    }

    /// Every point the occluder counts as hidden is inside the polytope
    /// actually drawn, at every level of detail, for capsules and spheres:
    /// checked against the drawn faces' planes, independently of `inner`.
    #[test]
    fn hidden_points_are_inside_the_drawn_solid() {
        let templates = Templates::default();
        let mut rng = Rng::new(7);
        let mut hidden = 0;
        for n in MIN_SECTORS..=MAX_SECTORS {
            // The radius in pixels that asks for n sectors.
            let pixels = (1..4000)
                .map(|k| k as f32 * 0.1)
                .find(|&px| sectors_for(px, 1.0) == n)
                .unwrap();
            let template = templates.for_radius(pixels, 1.0);
            for length in [0.0_f32, 0.3, 2.0] {
                let ends = Ends {
                    a: Vec3::new(0.2, -0.1, 0.4),
                    b: Vec3::new(0.2, -0.1, 0.4) + length * Vec3::new(0.6, 0.0, 0.8),
                    radii: [0.5; 2],
                };
                let drawn = place(template, &ends);
                let occluder = Occluder::new(ends, template, None).unwrap();
                for _ in 0..3000 {
                    let p = ends.a
                        + Vec3::new(
                            rng.range(-1.0, 2.0) as f32,
                            rng.range(-1.0, 1.0) as f32,
                            rng.range(-1.0, 2.0) as f32,
                        );
                    if occluder.hides(p) {
                        hidden += 1;
                        assert!(
                            inside_drawn(template, &drawn, p),
                            "{n} sectors, length {length}: {p} hidden yet outside"
                        );
                    }
                }
                // The drawn surface's own corners are never hidden by it.
                assert!(drawn.iter().all(|&p| !occluder.hides(p)));
            }
        }
        assert!(hidden > 10_000, "too few hidden points tested: {hidden}");
    }

    /// The hidden set is nearly all of the solid: a point halfway between
    /// `inner` and the true surface is outside it, one a little inside is in.
    #[test]
    fn the_hidden_set_is_tight() {
        let templates = Templates::default();
        for pixels in [2.0_f32, 10.0, 50.0, 400.0] {
            let template = templates.for_radius(pixels, 1.0);
            assert!(
                template.inner > 0.7 && template.inner < 1.0,
                "{}",
                template.inner
            );
            let ends = Ends {
                a: Vec3::ZERO,
                b: Vec3::X,
                radii: [1.0; 2],
            };
            let o = Occluder::new(ends, template, None).unwrap();
            let side = Vec3::new(0.5, 0.0, 1.0);
            assert!(o.hides(side * 0.99 * template.inner));
            assert!(!o.hides(side * (0.5 + 0.5 * template.inner)));
        }
    }

    #[test]
    fn tapered_flat_or_near_the_eye_solids_hide_nothing() {
        let template = Templates::default().for_radius(10.0, 1.0).clone();
        let ends = |r0, r1| Ends {
            a: Vec3::ZERO,
            b: Vec3::X,
            radii: [r0, r1],
        };
        assert!(Occluder::new(ends(0.1, 0.1), &template, None).is_some());
        assert!(Occluder::new(ends(0.1, 0.08), &template, None).is_none());
        assert!(Occluder::new(ends(0.0, 0.0), &template, None).is_none());
        assert!(Occluder::new(ends(f32::NAN, f32::NAN), &template, None).is_none());
        // The eye 0.15 m from the axis, the near plane 0.01 m ahead: kept;
        // 0.1 m ahead: the near plane may cut the solid.
        let eye = Vec3::new(0.5, 0.25, 0.0);
        assert!(Occluder::new(ends(0.1, 0.1), &template, Some((eye, 0.01))).is_some());
        assert!(Occluder::new(ends(0.1, 0.1), &template, Some((eye, 0.1))).is_none());
    }

    #[test]
    fn masks_name_the_occluders_near_a_solid() {
        let template = Templates::default().for_radius(10.0, 1.0).clone();
        let sphere = |c: Vec3, r: f32| Ends {
            a: c,
            b: c,
            radii: [r; 2],
        };
        let mut occluders = Occluders::default();
        occluders.push(Occluder::new(sphere(Vec3::ZERO, 1.0), &template, None));
        occluders.push(Occluder::new(sphere(Vec3::X * 10.0, 1.0), &template, None));
        occluders.push(Occluder::new(sphere(Vec3::X * 0.5, 1.0), &template, None));
        // A small sphere at the origin meets the first and third.
        occluders.select_near(&sphere(Vec3::ZERO, 0.1));
        assert!(occluders.any_near());
        assert_eq!(occluders.mask(Vec3::ZERO), 0b11);
        assert_eq!(occluders.mask(Vec3::X * 1.2), 0b10);
        assert_eq!(occluders.mask(Vec3::Y * 5.0), 0);
        occluders.select_near(&sphere(Vec3::Y * 50.0, 0.1));
        assert!(!occluders.any_near());
    }
}
