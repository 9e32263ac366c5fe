//! The camera: an orbit camera around a target point, in perspective (3D) or
//! looking along a fixed axis in orthographic projection (2D views for planar
//! robots).

use glam::camera::rh::{proj::directx, view::look_at_mat4};
use glam::{Mat4, Vec3, Vec4};

/// How the camera looks at the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Perspective, orbiting the target (yaw about z, pitch above the ground).
    Orbit,
    /// Orthographic, looking down the −z axis (x right, y up on screen).
    Top,
    /// Orthographic, looking along +y (x right, z up).
    Front,
    /// Orthographic, looking along −x (y right, z up).
    Side,
}

impl View {
    /// Parses `"3d"`, `"orbit"`, `"top"`, `"front"`, `"side"`.
    #[must_use]
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "3d" | "orbit" => Some(Self::Orbit),
            "top" | "2d" => Some(Self::Top),
            "front" => Some(Self::Front),
            "side" => Some(Self::Side),
            _ => None,
        }
    }

    /// The name `parse` accepts for this view.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Orbit => "3d",
            Self::Top => "top",
            Self::Front => "front",
            Self::Side => "side",
        }
    }
}

/// Radians of orbit per pixel dragged.
const ORBIT_PER_PIXEL: f32 = 0.008;
/// Pitch stays this far from the poles (rad), so "up" is always defined.
const PITCH_LIMIT: f32 = 1.55;

/// The near clipping plane in front of the eye, as a fraction of the
/// distance to the target (perspective).
const NEAR: f32 = 0.01;

/// An orbit / pan / zoom camera.
///
/// The eye sits `distance` metres from `target`; in the 2D views the same
/// distance sets the visible height, so zoom behaves alike in both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The point looked at and orbited around (m, world frame).
    pub target: Vec3,
    /// Azimuth of the eye about the world z axis (rad; 0 puts the eye on the +x side).
    pub yaw: f32,
    /// Elevation of the eye above the ground plane (rad).
    pub pitch: f32,
    /// Distance from the eye to the target (m), > 0.
    pub distance: f32,
    /// Vertical field of view of the perspective view (rad).
    pub fov_y: f32,
    /// Perspective orbit or one of the orthographic views.
    pub view: View,
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            yaw: -0.6,
            pitch: 0.5,
            distance: 2.5,
            fov_y: 45f32.to_radians(),
            view: View::Orbit,
        }
    }
}

impl Camera {
    /// A camera framing a ball of `radius` metres around `center` in `view`.
    #[must_use]
    pub fn framing(center: Vec3, radius: f32, view: View) -> Self {
        let mut camera = Self {
            target: center,
            view,
            ..Self::default()
        };
        camera.frame(center, radius);
        camera
    }

    /// Moves the target to `center` and the eye so that a ball of `radius`
    /// metres fits the view, whatever the aspect ratio down to 1:1.
    pub fn frame(&mut self, center: Vec3, radius: f32) {
        let radius = if radius.is_finite() && radius > 1e-3 {
            radius
        } else {
            1.0
        };
        self.target = center;
        self.distance = 1.1 * radius / (0.5 * self.fov_y).sin();
    }

    /// Aims at `points` and sets the distance so that their box, seen from
    /// the current direction, fills `fill` (0..1) of the view's width or
    /// height, whichever limits, for a drawing buffer of `aspect` = width /
    /// height. The direction (yaw, pitch, view) is kept; no points, or only
    /// non-finite ones, leave the camera as it is.
    pub fn fit(&mut self, points: &[Vec3], aspect: f32, fill: f32) {
        self.fit_fills(points, aspect, fill, fill);
    }

    /// [`Camera::fit`] into the part of a `width` × `height` view below its
    /// top `top` pixels (where a page lays text over the view): the box
    /// fills `fill` of that part's width or height and is centred in it.
    /// `top` is clamped to half the height.
    pub fn fit_below(&mut self, points: &[Vec3], (width, height): (f32, f32), top: f32, fill: f32) {
        let height = height.max(1.0);
        let top = if top.is_finite() {
            top.clamp(0.0, 0.5 * height)
        } else {
            0.0
        };
        let region = height - top;
        let fill = fill.clamp(0.05, 1.0);
        self.fit_fills(points, width / height, fill, fill * region / height);
        // The region's centre lies top/2 pixels below the view's centre.
        self.pan(0.0, 0.5 * top, height);
    }

    /// [`Camera::fit`] with the share of the view's width (`fill_x`) and
    /// height (`fill_y`) the box may fill.
    fn fit_fills(&mut self, points: &[Vec3], aspect: f32, fill_x: f32, fill_y: f32) {
        let back = self.backward();
        let right = self.up().cross(back).normalize_or(Vec3::X);
        let up = back.cross(right);
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in points.iter().filter(|p| p.is_finite()) {
            let local = Vec3::new(p.dot(right), p.dot(up), p.dot(back));
            lo = lo.min(local);
            hi = hi.max(local);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return;
        }
        let mid = 0.5 * (lo + hi);
        let half = (0.5 * (hi - lo)).max(Vec3::splat(0.02));
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let (fill_x, fill_y) = (fill_x.clamp(0.05, 1.0), fill_y.clamp(0.05, 1.0));
        // Half the visible height at the target that makes the box fill its share.
        let half_height = (half.y / fill_y).max(half.x / (aspect * fill_x));
        self.target = mid.x * right + mid.y * up + mid.z * back;
        // In perspective the near half of the box is closer to the eye: step
        // back by its depth so that it is not drawn larger than planned.
        let depth = if self.view == View::Orbit {
            half.z
        } else {
            0.0
        };
        self.distance = (half_height / (0.5 * self.fov_y).tan() + depth).clamp(1e-3, 1e4);
    }

    /// Unit vector from the target towards the eye.
    #[must_use]
    pub fn backward(&self) -> Vec3 {
        match self.view {
            View::Orbit => {
                let (sy, cy) = self.yaw.sin_cos();
                let (sp, cp) = self.pitch.sin_cos();
                Vec3::new(cp * cy, cp * sy, sp)
            }
            View::Top => Vec3::Z,
            View::Front => Vec3::NEG_Y,
            View::Side => Vec3::X,
        }
    }

    /// The screen's up direction in the world.
    #[must_use]
    pub fn up(&self) -> Vec3 {
        match self.view {
            View::Top => Vec3::Y,
            _ => Vec3::Z,
        }
    }

    /// Eye position (m, world frame).
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.target + self.distance * self.backward()
    }

    /// The world-to-clip matrix for a drawing buffer of `aspect` = width / height.
    #[must_use]
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let view = look_at_mat4(self.eye(), self.target, self.up());
        let proj = match self.view {
            View::Orbit => directx::perspective(
                self.fov_y,
                aspect,
                NEAR * self.distance,
                100.0 * self.distance,
            ),
            _ => {
                let h = self.half_height();
                let w = h * aspect;
                let depth = 100.0 * self.distance.max(1.0);
                directx::orthographic(-w, w, -h, h, -depth, depth)
            }
        };
        proj * view
    }

    /// How far the near clipping plane is in front of the eye (m), in
    /// perspective; `None` for an orthographic view, whose depth range
    /// holds the whole scene.
    #[must_use]
    pub fn near_plane(&self) -> Option<f32> {
        (self.view == View::Orbit).then_some(NEAR * self.distance)
    }

    /// Pixels a metre spans on a view `height` pixels high, seen from
    /// `distance` metres in perspective (at least a millimetre); anywhere
    /// in an orthographic view.
    #[must_use]
    pub fn pixels_per_metre(&self, height: f32, distance: f32) -> f32 {
        let half = if self.view == View::Orbit {
            (0.5 * self.fov_y).tan() * distance.max(1e-3)
        } else {
            self.half_height()
        };
        0.5 * height / half.max(1e-6)
    }

    /// Half the height of the visible region at the target (m).
    #[must_use]
    pub fn half_height(&self) -> f32 {
        self.distance * (0.5 * self.fov_y).tan()
    }

    /// Rotates the eye about the target by a drag of `dx`, `dy` pixels
    /// (3D view only; the 2D views keep their axis).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        if self.view != View::Orbit {
            return;
        }
        self.yaw -= dx * ORBIT_PER_PIXEL;
        self.pitch = (self.pitch + dy * ORBIT_PER_PIXEL).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Moves the target with the scene under the pointer for a drag of `dx`,
    /// `dy` pixels in a drawing buffer `height` pixels high.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let per_pixel = 2.0 * self.half_height() / height.max(1.0);
        let back = self.backward();
        let right = self.up().cross(back).normalize_or(Vec3::X);
        let up = back.cross(right);
        self.target += per_pixel * (-dx * right + dy * up);
    }

    /// Multiplies the distance to the target by `factor` (> 1 zooms out).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(1e-3, 1e4);
        }
    }

    /// Where `point` lands in a `width` × `height` drawing buffer (pixels from
    /// the top-left corner), or `None` when it is behind the eye.
    #[must_use]
    pub fn project(&self, point: Vec3, width: f32, height: f32) -> Option<[f32; 2]> {
        let clip = self.view_proj(width / height) * Vec4::from((point, 1.0));
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some([(ndc.x + 1.0) * 0.5 * width, (1.0 - ndc.y) * 0.5 * height])
    }

    /// The ray through pixel (`x`, `y`) of a `width` × `height` drawing
    /// buffer (pixels from the top-left corner): its origin on the near plane
    /// and its unit direction, for picking. `None` for a degenerate camera.
    #[must_use]
    pub fn ray(&self, x: f32, y: f32, width: f32, height: f32) -> Option<(Vec3, Vec3)> {
        let inverse = self.view_proj(width / height).inverse();
        let ndc_x = 2.0 * x / width.max(1.0) - 1.0;
        let ndc_y = 1.0 - 2.0 * y / height.max(1.0);
        let unproject = |z: f32| {
            let p = inverse * Vec4::new(ndc_x, ndc_y, z, 1.0);
            (p.w.abs() > 1e-12).then(|| p.truncate() / p.w)
        };
        let (near, far) = (unproject(0.0)?, unproject(1.0)?);
        let direction = (far - near).try_normalize()?;
        near.is_finite().then_some((near, direction))
    }
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;

    #[test]
    fn target_projects_to_the_centre() {
        for view in [View::Orbit, View::Top, View::Front, View::Side] {
            let camera = Camera::framing(Vec3::new(0.3, 0.1, 0.2), 1.0, view);
            let p = camera.project(camera.target, 200.0, 100.0).unwrap();
            assert!(
                (p[0] - 100.0).abs() < 1e-3 && (p[1] - 50.0).abs() < 1e-3,
                "{view:?} {p:?}"
            );
        }
    }

    #[test]
    fn fit_fills_the_asked_fraction_of_the_limiting_side() {
        let points = [Vec3::new(1.0, 2.0, 0.0), Vec3::new(1.6, 2.2, 0.0)];
        for (aspect, view) in [(2.0, View::Top), (0.5, View::Top), (1.5, View::Orbit)] {
            let mut camera = Camera::framing(Vec3::ZERO, 5.0, view);
            camera.fit(&points, aspect, 0.6);
            let (w, h) = (100.0 * aspect, 100.0);
            let a = camera.project(points[0], w, h).unwrap();
            let b = camera.project(points[1], w, h).unwrap();
            let share = ((b[0] - a[0]).abs() / w).max((b[1] - a[1]).abs() / h);
            assert!(share > 0.45 && share < 0.61, "{view:?} {aspect}: {share}");
        }
    }

    #[test]
    fn fit_below_frames_the_points_under_the_top_band_and_centres_them() {
        let points = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.8, 0.3, 0.5),
            Vec3::new(-0.2, 0.6, 0.9),
        ];
        let (w, h, top) = (390.0, 600.0, 120.0);
        for view in [View::Top, View::Orbit] {
            let mut camera = Camera::framing(Vec3::ZERO, 5.0, view);
            camera.fit_below(&points, (w, h), top, 0.8);
            let shots: Vec<[f32; 2]> = points
                .iter()
                .map(|p| camera.project(*p, w, h).unwrap())
                .collect();
            let (lo, hi) = shots.iter().fold(
                ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]),
                |(lo, hi), p| {
                    (
                        [lo[0].min(p[0]), lo[1].min(p[1])],
                        [hi[0].max(p[0]), hi[1].max(p[1])],
                    )
                },
            );
            assert!(
                lo[1] > top && hi[1] < h && lo[0] > 0.0 && hi[0] < w,
                "{view:?}: {lo:?} {hi:?}"
            );
            // Centred in the band below `top` (within a few pixels; the
            // perspective box is only nearly symmetric on screen).
            let middle = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
            assert!(
                (middle[0] - 0.5 * w).abs() < 0.06 * w,
                "{view:?}: {middle:?}"
            );
            assert!(
                (middle[1] - 0.5 * (h + top)).abs() < 0.06 * h,
                "{view:?}: {middle:?}"
            );
            // The limiting side is filled to about 0.8 of the band (less in
            // perspective, where the fit steps back by the box's depth).
            let share = ((hi[0] - lo[0]) / w).max((hi[1] - lo[1]) / (h - top));
            assert!(share > 0.55 && share < 0.81, "{view:?}: {share}");
        }
    }

    #[test]
    fn top_view_has_x_right_and_y_up() {
        let camera = Camera::framing(Vec3::ZERO, 1.0, View::Top);
        let x = camera.project(Vec3::X * 0.5, 100.0, 100.0).unwrap();
        let y = camera.project(Vec3::Y * 0.5, 100.0, 100.0).unwrap();
        assert!(x[0] > 50.0 && (x[1] - 50.0).abs() < 1e-3);
        assert!(y[1] < 50.0 && (y[0] - 50.0).abs() < 1e-3);
    }

    #[test]
    fn ray_through_a_projected_point_passes_through_it() {
        for view in [View::Orbit, View::Top, View::Side] {
            let mut camera = Camera::framing(Vec3::ZERO, 1.0, view);
            camera.orbit(40.0, -25.0);
            let point = Vec3::new(0.2, -0.3, 0.1);
            let [x, y] = camera.project(point, 300.0, 200.0).unwrap();
            let (origin, direction) = camera.ray(x, y, 300.0, 200.0).unwrap();
            let along = (point - origin).dot(direction);
            let miss = (origin + along * direction - point).length();
            assert!(along > 0.0 && miss < 1e-4, "{view:?}: miss {miss}");
        }
    }

    #[test]
    fn every_point_of_a_pixel_ray_projects_back_to_the_pixel() {
        for view in [View::Orbit, View::Top, View::Front, View::Side] {
            let mut camera = Camera::framing(Vec3::new(0.1, 0.2, 0.3), 0.8, view);
            camera.orbit(-30.0, 12.0);
            for (x, y) in [(0.0, 0.0), (150.0, 100.0), (299.0, 17.5), (42.0, 199.0)] {
                let (origin, direction) = camera.ray(x, y, 300.0, 200.0).unwrap();
                assert!((direction.length() - 1.0).abs() < 1e-5);
                for t in [0.0, 0.5, 2.0] {
                    let [px, py] = camera
                        .project(origin + t * direction, 300.0, 200.0)
                        .unwrap();
                    let miss = (px - x).hypot(py - y);
                    assert!(miss < 0.05, "{view:?} ({x}, {y}) t={t}: off by {miss} px");
                }
            }
        }
    }

    #[test]
    fn points_behind_the_eye_do_not_project() {
        let camera = Camera::framing(Vec3::ZERO, 1.0, View::Orbit);
        let behind = camera.eye() + camera.backward();
        assert_eq!(camera.project(behind, 100.0, 100.0), None);
    }
}
