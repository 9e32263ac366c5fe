//! What the renderer draws in one frame: plain data, rebuilt by the caller.
//!
//! Everything is in the world frame (m, z up) as `f32`; colours are
//! sRGB-encoded `[r, g, b, a]` in `0..=1` (as in CSS), `a < 1` makes a
//! translucent volume.

/// A tapered capsule: the set of points within a radius of the segment
/// `a`–`b`, the radius varying linearly from `radius[0]` at `a` to
/// `radius[1]` at `b`. A cone-like arrow head is a capsule with
/// `radius[1] = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// First end point (m).
    pub a: [f32; 3],
    /// Second end point (m).
    pub b: [f32; 3],
    /// Radius at `a` and at `b` (m).
    pub radius: [f32; 2],
    /// sRGB colour and opacity.
    pub color: [f32; 4],
}

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (m).
    pub center: [f32; 3],
    /// Radius (m).
    pub radius: f32,
    /// sRGB colour and opacity.
    pub color: [f32; 4],
}

/// A straight line drawn with a constant width on screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// First end point (m).
    pub a: [f32; 3],
    /// Second end point (m).
    pub b: [f32; 3],
    /// Width on screen (pixels of the drawing buffer).
    pub width: f32,
    /// sRGB colour and opacity.
    pub color: [f32; 4],
}

/// A square grid of lines on the ground plane `z = 0`, centred on the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Half the side of the square (m).
    pub half_extent: f32,
    /// Distance between neighbouring lines (m).
    pub spacing: f32,
    /// sRGB colour of the lines.
    pub color: [f32; 4],
    /// sRGB colour of the x and y axis lines through the origin.
    pub axis_color: [f32; 4],
}

impl Default for Grid {
    fn default() -> Self {
        Self {
            half_extent: 1.0,
            spacing: 0.1,
            color: [0.78, 0.80, 0.84, 1.0],
            axis_color: [0.55, 0.58, 0.64, 1.0],
        }
    }
}

/// One frame's worth of primitives.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Background colour (sRGB, alpha ignored).
    pub background: [f32; 4],
    /// The ground grid, if any.
    pub grid: Option<Grid>,
    /// Tapered capsules (opaque and translucent).
    pub capsules: Vec<Capsule>,
    /// Spheres (opaque and translucent).
    pub spheres: Vec<Sphere>,
    /// Lines (distance lines, arrow shafts, frame axes).
    pub lines: Vec<Line>,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            background: [0.96, 0.965, 0.975, 1.0],
            grid: Some(Grid::default()),
            capsules: Vec::new(),
            spheres: Vec::new(),
            lines: Vec::new(),
        }
    }
}

impl Scene {
    /// An empty scene with the default background and ground grid.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Removes every primitive, keeping the background and the grid.
    pub fn clear(&mut self) {
        self.capsules.clear();
        self.spheres.clear();
        self.lines.clear();
    }

    /// Adds an arrow from `from` to `to`: a shaft line of `width` pixels and a
    /// cone head (a capsule tapering to zero) a fifth of the length, at most
    /// `head` metres long. A zero-length arrow adds nothing.
    pub fn push_arrow(
        &mut self,
        from: [f32; 3],
        to: [f32; 3],
        width: f32,
        head: f32,
        color: [f32; 4],
    ) {
        let d = sub(to, from);
        let len = norm(d);
        if len.is_nan() || len <= 1e-6 {
            return;
        }
        let head_len = (0.2 * len).min(head);
        let base = add(to, scale(d, -head_len / len));
        self.lines.push(Line {
            a: from,
            b: base,
            width,
            color,
        });
        self.capsules.push(Capsule {
            a: base,
            b: to,
            radius: [0.35 * head_len, 0.0],
            color,
        });
    }

    /// Adds the three axes of a frame at `origin` whose unit axes are the
    /// columns `x`, `y`, `z`, drawn red, green and blue, `length` metres long.
    pub fn push_axes(&mut self, origin: [f32; 3], axes: [[f32; 3]; 3], length: f32, width: f32) {
        const COLORS: [[f32; 4]; 3] = [
            [0.86, 0.16, 0.16, 1.0],
            [0.18, 0.66, 0.24, 1.0],
            [0.16, 0.36, 0.90, 1.0],
        ];
        for (axis, color) in axes.iter().zip(COLORS) {
            let b = add(origin, scale(*axis, length));
            self.lines.push(Line {
                a: origin,
                b,
                width,
                color,
            });
        }
    }
}

fn add(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn norm(a: [f32; 3]) -> f32 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
