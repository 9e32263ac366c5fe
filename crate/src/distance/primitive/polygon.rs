//! The planar simple [`Polygon`] (convex or not) and its validation.

use glam::{DVec2, DVec3};

use super::REL_TOL;
use crate::error::{FieldError, finite3};

/// A planar simple polygon (convex or not), given by its vertices in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    pub(super) vertices: Vec<DVec3>,
    pub(super) origin: DVec3,
    u: DVec3,
    v: DVec3,
    normal: DVec3,
    local: Vec<DVec2>,
    convex: bool,
}

impl Polygon {
    /// A polygon from at least three vertices that lie in one plane and
    /// bound a simple (non-self-intersecting) region of non-zero area.
    ///
    /// # Errors
    /// `vertices: polygon needs at least 3 vertices`, `vertices[k][j]: not a
    /// finite number`, `vertices[k]: repeats the previous vertex`,
    /// `vertices: polygon has zero area`, `vertices: polygon is not planar`,
    /// `vertices: polygon is self-intersecting`.
    ///
    /// # Example
    /// ```
    /// use glam::DVec3;
    /// use skeleton_avoidance::distance::Polygon;
    /// let v = |x, y, z| DVec3::new(x, y, z);
    /// let bent = Polygon::new(vec![v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 1.)]);
    /// assert_eq!(bent.unwrap_err().to_string(), "vertices: polygon is not planar");
    /// ```
    pub fn new(vertices: Vec<DVec3>) -> Result<Self, FieldError> {
        let n = vertices.len();
        if n < 3 {
            return Err(FieldError::new(
                "vertices",
                "polygon needs at least 3 vertices",
            ));
        }
        for (k, p) in vertices.iter().enumerate() {
            finite3(&format!("vertices[{k}]"), *p)?;
        }
        let mut scale: f64 = 0.0;
        for p in &vertices {
            scale = scale.max((*p - vertices[0]).length());
        }
        for k in 0..n {
            let prev = vertices[(k + n - 1) % n];
            if (vertices[k] - prev).length() <= REL_TOL * scale {
                return Err(FieldError::new(
                    format!("vertices[{k}]"),
                    "repeats the previous vertex",
                ));
            }
        }
        // Newell's normal: twice the vector area of the polygon.
        let mut area = DVec3::ZERO;
        for k in 0..n {
            area += vertices[k].cross(vertices[(k + 1) % n]);
        }
        let area_len = area.length();
        if area_len.is_nan() || area_len <= REL_TOL * scale * scale {
            return Err(FieldError::new("vertices", "polygon has zero area"));
        }
        let normal = area / area_len;
        let origin = vertices[0];
        for p in &vertices {
            if normal.dot(*p - origin).abs() > REL_TOL * scale.max(1.0) {
                return Err(FieldError::new("vertices", "polygon is not planar"));
            }
        }
        let u = (vertices[1] - origin).normalize();
        let v = normal.cross(u);
        let local: Vec<DVec2> = vertices
            .iter()
            .map(|p| DVec2::new(u.dot(*p - origin), v.dot(*p - origin)))
            .collect();
        for i in 0..n {
            for j in (i + 1)..n {
                if j == i + 1 || (i == 0 && j == n - 1) {
                    continue;
                }
                if segments_touch_2d(local[i], local[(i + 1) % n], local[j], local[(j + 1) % n]) {
                    return Err(FieldError::new("vertices", "polygon is self-intersecting"));
                }
            }
        }
        let convex = (0..n).all(|k| {
            let a = local[k];
            let b = local[(k + 1) % n];
            let c = local[(k + 2) % n];
            (b - a).perp_dot(c - b) >= -REL_TOL * scale * scale
        });
        Ok(Self {
            vertices,
            origin,
            u,
            v,
            normal,
            local,
            convex,
        })
    }

    /// The vertices as given.
    #[must_use]
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Unit normal (counter-clockwise vertex order around it).
    #[must_use]
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// Whether the polygon is convex.
    #[must_use]
    pub fn is_convex(&self) -> bool {
        self.convex
    }

    /// In-plane coordinates of `p` (projected along the normal) and its
    /// signed height above the plane.
    pub(crate) fn to_local(&self, p: DVec3) -> (DVec2, f64) {
        let d = p - self.origin;
        (DVec2::new(self.u.dot(d), self.v.dot(d)), self.normal.dot(d))
    }

    /// The point of the plane with in-plane coordinates `q`.
    pub(crate) fn point_at(&self, q: DVec2) -> DVec3 {
        self.origin + self.u * q.x + self.v * q.y
    }

    /// Vertices in in-plane coordinates.
    pub(crate) fn local(&self) -> &[DVec2] {
        &self.local
    }

    /// A triangulation by ear clipping: index triples into the vertices,
    /// counter-clockwise around the normal.
    #[must_use]
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        let pts = &self.local;
        let mut idx: Vec<usize> = (0..pts.len()).collect();
        let mut out = Vec::with_capacity(pts.len().saturating_sub(2));
        // A vertex on (or within rounding of) a candidate ear's boundary
        // disqualifies it.
        let scale = pts
            .iter()
            .map(|p| (*p - pts[0]).length())
            .fold(0.0, f64::max);
        let eps = 1e-12 * scale * scale;
        let inside = |p: DVec2, a: DVec2, b: DVec2, c: DVec2| {
            (b - a).perp_dot(p - a) >= -eps
                && (c - b).perp_dot(p - b) >= -eps
                && (a - c).perp_dot(p - c) >= -eps
        };
        while idx.len() > 3 {
            let m = idx.len();
            let ear = (0..m).find(|&k| {
                let (i, j, l) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
                let (a, b, c) = (pts[i], pts[j], pts[l]);
                (b - a).perp_dot(c - b) > 0.0
                    && idx
                        .iter()
                        .all(|&o| o == i || o == j || o == l || !inside(pts[o], a, b, c))
            });
            // A simple polygon always has an ear; rounding may hide it, then
            // the most convex corner is clipped.
            let k = ear.unwrap_or_else(|| {
                (0..m)
                    .max_by(|&x, &y| {
                        let turn = |k: usize| {
                            let (a, b, c) = (
                                pts[idx[(k + m - 1) % m]],
                                pts[idx[k]],
                                pts[idx[(k + 1) % m]],
                            );
                            (b - a).perp_dot(c - b)
                        };
                        turn(x).total_cmp(&turn(y))
                    })
                    .unwrap_or(0)
            });
            out.push([idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]]);
            idx.remove(k);
        }
        if idx.len() == 3 {
            out.push([idx[0], idx[1], idx[2]]);
        }
        out
    }

    /// The sides as segments, `vertices[k]`–`vertices[k + 1]`.
    pub(crate) fn sides(&self) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
        let v = &self.vertices;
        (0..v.len()).map(move |k| (v[k], v[(k + 1) % v.len()]))
    }

    /// Whether the in-plane point `q` is inside (even–odd rule; points on the
    /// boundary may answer either way).
    pub(crate) fn contains_local(&self, q: DVec2) -> bool {
        let pts = &self.local;
        let n = pts.len();
        let mut inside = false;
        let mut j = n - 1;
        for i in 0..n {
            let (pi, pj) = (pts[i], pts[j]);
            if (pi.y > q.y) != (pj.y > q.y) {
                let x = pj.x + (q.y - pj.y) * (pi.x - pj.x) / (pi.y - pj.y);
                if q.x < x {
                    inside = !inside;
                }
            }
            j = i;
        }
        inside
    }
}

/// Whether two closed 2-D segments share a point.
fn segments_touch_2d(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let orient = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let on = |p: DVec2, q: DVec2, r: DVec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    (o1 == 0.0 && on(a, b, c))
        || (o2 == 0.0 && on(a, b, d))
        || (o3 == 0.0 && on(c, d, a))
        || (o4 == 0.0 && on(c, d, b))
}
