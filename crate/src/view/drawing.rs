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

/// A flat-shaded triangle, lit from both sides (planes, rectangles, disks,
/// polygons, box faces).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// The corners (m); the normal follows their order but both faces are lit.
    pub p: [[f32; 3]; 3],
    /// sRGB colour and opacity.
    pub color: [f32; 4],
}

/// A square grid of lines on the ground plane `z = 0`, centred on the origin:
/// every `spacing` within `fine_extent` of the origin, every
/// [`Grid::COARSE`]-th line beyond it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Half the side of the square (m).
    pub half_extent: f32,
    /// Half the side of the square where every line is drawn (m); beyond
    /// it only every [`Grid::COARSE`]-th. Far from the eye the fine lines
    /// crowd into a grey band, and each costs a software rasteriser as much
    /// as a near one.
    pub fine_extent: f32,
    /// Distance between neighbouring lines (m).
    pub spacing: f32,
    /// sRGB colour of the lines.
    pub color: [f32; 4],
    /// sRGB colour of the x and y axis lines through the origin.
    pub axis_color: [f32; 4],
}

impl Grid {
    /// Beyond [`Grid::fine_extent`], one line in this many is drawn.
    pub const COARSE: i32 = 5;
}

impl Default for Grid {
    fn default() -> Self {
        Self {
            half_extent: 1.0,
            fine_extent: 1.0,
            spacing: 0.1,
            color: [0.78, 0.80, 0.84, 1.0],
            axis_color: [0.55, 0.58, 0.64, 1.0],
        }
    }
}

/// One frame's worth of primitives.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
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
    /// Flat triangles (opaque and translucent).
    pub triangles: Vec<Triangle>,
    /// Opaque triangles of closed surfaces, each wound counter-clockwise
    /// seen from outside (link meshes): only those facing the camera are
    /// drawn.
    pub closed: Vec<Triangle>,
}

impl Default for Drawing {
    fn default() -> Self {
        Self {
            background: [0.96, 0.965, 0.975, 1.0],
            grid: Some(Grid::default()),
            capsules: Vec::new(),
            spheres: Vec::new(),
            lines: Vec::new(),
            triangles: Vec::new(),
            closed: Vec::new(),
        }
    }
}

impl Drawing {
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
        self.triangles.clear();
        self.closed.clear();
    }

    /// Adds a closed outline through `points` as lines of `width` pixels.
    pub fn push_loop(&mut self, points: &[[f32; 3]], width: f32, color: [f32; 4]) {
        for (i, &a) in points.iter().enumerate() {
            let b = points[(i + 1) % points.len()];
            self.lines.push(Line { a, b, width, color });
        }
    }

    /// Adds the quadrilateral `corners` (in order around it) as two triangles.
    pub fn push_quad(&mut self, corners: [[f32; 3]; 4], color: [f32; 4]) {
        let [a, b, c, d] = corners;
        self.triangles.push(Triangle {
            p: [a, b, c],
            color,
        });
        self.triangles.push(Triangle {
            p: [a, c, d],
            color,
        });
    }

    /// Adds a rectangle centred at `center` spanned by the unit `axes`
    /// with `half_extents` along them, and its outline.
    pub fn push_rectangle(
        &mut self,
        center: [f32; 3],
        axes: [[f32; 3]; 2],
        half_extents: [f32; 2],
        color: [f32; 4],
        outline: [f32; 4],
    ) {
        let u = scale(axes[0], half_extents[0]);
        let v = scale(axes[1], half_extents[1]);
        let corners = [
            add(center, add(scale(u, -1.0), scale(v, -1.0))),
            add(center, add(u, scale(v, -1.0))),
            add(center, add(u, v)),
            add(center, add(scale(u, -1.0), v)),
        ];
        self.push_quad(corners, color);
        self.push_loop(&corners, 1.5, outline);
    }

    /// Adds a disk of `radius` around `center` facing `normal`, as a fan of
    /// 48 triangles, and its rim.
    pub fn push_disk(
        &mut self,
        center: [f32; 3],
        normal: [f32; 3],
        radius: f32,
        color: [f32; 4],
        outline: [f32; 4],
    ) {
        const SECTORS: usize = 48;
        let (u, v) = orthonormal_pair(normal);
        let rim: Vec<[f32; 3]> = (0..SECTORS)
            .map(|k| {
                let phi = k as f32 / SECTORS as f32 * std::f32::consts::TAU;
                add(
                    center,
                    add(scale(u, radius * phi.cos()), scale(v, radius * phi.sin())),
                )
            })
            .collect();
        for k in 0..SECTORS {
            self.triangles.push(Triangle {
                p: [center, rim[k], rim[(k + 1) % SECTORS]],
                color,
            });
        }
        self.push_loop(&rim, 1.5, outline);
    }

    /// Adds a planar polygon from its `vertices` and a triangulation
    /// (`triangles` indexes `vertices`; an empty one draws a fan from the
    /// first vertex, right for convex polygons), and its outline.
    pub fn push_polygon(
        &mut self,
        vertices: &[[f32; 3]],
        triangles: &[[usize; 3]],
        color: [f32; 4],
        outline: [f32; 4],
    ) {
        if vertices.len() < 3 {
            return;
        }
        if triangles.is_empty() {
            for k in 1..vertices.len() - 1 {
                self.triangles.push(Triangle {
                    p: [vertices[0], vertices[k], vertices[k + 1]],
                    color,
                });
            }
        } else {
            for t in triangles {
                if let (Some(&a), Some(&b), Some(&c)) =
                    (vertices.get(t[0]), vertices.get(t[1]), vertices.get(t[2]))
                {
                    self.triangles.push(Triangle {
                        p: [a, b, c],
                        color,
                    });
                }
            }
        }
        self.push_loop(vertices, 1.5, outline);
    }

    /// Adds an oriented box: `center`, the columns of its rotation `axes`
    /// (unit vectors) and `half_extents` along them; its twelve edges are
    /// drawn as lines of `outline` colour.
    pub fn push_box(
        &mut self,
        center: [f32; 3],
        axes: [[f32; 3]; 3],
        half_extents: [f32; 3],
        color: [f32; 4],
        outline: [f32; 4],
    ) {
        let corner = |sx: f32, sy: f32, sz: f32| {
            add(
                center,
                add(
                    scale(axes[0], sx * half_extents[0]),
                    add(
                        scale(axes[1], sy * half_extents[1]),
                        scale(axes[2], sz * half_extents[2]),
                    ),
                ),
            )
        };
        let c: Vec<[f32; 3]> = (0..8)
            .map(|i| {
                let s = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
                corner(s(1), s(2), s(4))
            })
            .collect();
        // Faces as corner indices (bit 0: x, bit 1: y, bit 2: z), counter-
        // clockwise seen from outside.
        const FACES: [[usize; 4]; 6] = [
            [0, 4, 6, 2],
            [1, 3, 7, 5],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 2, 3, 1],
            [4, 5, 7, 6],
        ];
        for f in FACES {
            self.push_quad([c[f[0]], c[f[1]], c[f[2]], c[f[3]]], color);
        }
        const EDGES: [[usize; 2]; 12] = [
            [0, 1],
            [2, 3],
            [4, 5],
            [6, 7],
            [0, 2],
            [1, 3],
            [4, 6],
            [5, 7],
            [0, 4],
            [1, 5],
            [2, 6],
            [3, 7],
        ];
        for [a, b] in EDGES {
            self.lines.push(Line {
                a: c[a],
                b: c[b],
                width: 1.5,
                color: outline,
            });
        }
    }

    /// Adds the infinite plane `normal · x + offset = 0` as a square of
    /// `half_extent` metres around the point of the plane nearest `near`,
    /// with a few grid lines so its tilt reads. Nothing for a zero normal.
    pub fn push_plane(
        &mut self,
        normal: [f32; 3],
        offset: f32,
        near: [f32; 3],
        half_extent: f32,
        color: [f32; 4],
        outline: [f32; 4],
    ) {
        let len = norm(normal);
        if !(len.is_finite() && len > 1e-9) {
            return;
        }
        let n = scale(normal, 1.0 / len);
        let off = offset / len;
        let center = add(near, scale(n, -(dot(n, near) + off)));
        let (u, v) = orthonormal_pair(n);
        self.push_rectangle(center, [u, v], [half_extent; 2], color, outline);
        for k in 1..4 {
            let t = half_extent * (k as f32 / 2.0 - 1.0);
            for (a, b) in [(u, v), (v, u)] {
                let p = add(center, scale(a, t));
                self.lines.push(Line {
                    a: add(p, scale(b, -half_extent)),
                    b: add(p, scale(b, half_extent)),
                    width: 1.0,
                    color: outline,
                });
            }
        }
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

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Two unit vectors spanning the plane orthogonal to `n` (a unit vector).
fn orthonormal_pair(n: [f32; 3]) -> ([f32; 3], [f32; 3]) {
    let helper = if n[0].abs() > 0.9 {
        [0.0, 1.0, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let u = cross(helper, n);
    let u = scale(u, 1.0 / norm(u).max(1e-12));
    (u, cross(n, u))
}

fn norm(a: [f32; 3]) -> f32 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
