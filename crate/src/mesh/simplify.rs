//! Mesh simplification for display: edge collapse ordered by the quadric
//! error metric of Garland & Heckbert ("Surface simplification using
//! quadric error metrics", SIGGRAPH 1997).
//!
//! Every vertex carries the sum of the squared distances to the planes of
//! its triangles (a 4×4 quadric, each plane weighted by its triangle's
//! area); collapsing an edge moves both ends to the point that minimises
//! their summed quadric (or the better end or the midpoint when that point
//! is ill-defined or far away) and costs that quadric's value there. The
//! cheapest edge goes first, until the triangle budget is met or no edge
//! can go. A collapse is refused when it would turn a remaining triangle
//! over or make it a sliver, or when the two ends share more than two
//! neighbours (which would pinch the surface): a closed, consistently wound
//! mesh stays closed and keeps its winding. Edges of an open border carry
//! a plane across them, so borders keep their place.
//!
//! Only the drawing uses it: fitting and coverage always read the meshes
//! as given.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashSet};

use glam::{DMat3, DVec3};

/// A symmetric 4×4 quadric `[a b c d]ᵀ[a b c d]` summed over planes, kept
/// as its upper triangle.
#[derive(Clone, Copy, Debug, Default)]
struct Quadric([f64; 10]);

impl Quadric {
    /// The quadric of the plane `n·x + d = 0`, times `w`.
    fn plane(n: DVec3, d: f64, w: f64) -> Self {
        let (a, b, c) = (n.x, n.y, n.z);
        Self([
            w * a * a,
            w * a * b,
            w * a * c,
            w * a * d,
            w * b * b,
            w * b * c,
            w * b * d,
            w * c * c,
            w * c * d,
            w * d * d,
        ])
    }

    fn add(&mut self, o: &Self) {
        for (x, y) in self.0.iter_mut().zip(o.0) {
            *x += y;
        }
    }

    fn sum(a: &Self, b: &Self) -> Self {
        let mut s = *a;
        s.add(b);
        s
    }

    /// The summed squared distance at `p` (weighted).
    fn error(&self, p: DVec3) -> f64 {
        let q = &self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        q[0] * x * x
            + 2.0 * q[1] * x * y
            + 2.0 * q[2] * x * z
            + 2.0 * q[3] * x
            + q[4] * y * y
            + 2.0 * q[5] * y * z
            + 2.0 * q[6] * y
            + q[7] * z * z
            + 2.0 * q[8] * z
            + q[9]
    }

    /// The point minimising the quadric, when its 3×3 part is well
    /// conditioned.
    fn minimum(&self) -> Option<DVec3> {
        let q = &self.0;
        let m = DMat3::from_cols_array(&[q[0], q[1], q[2], q[1], q[4], q[5], q[2], q[5], q[7]]);
        let scale = q[0].abs() + q[4].abs() + q[7].abs();
        if scale <= 0.0 || m.determinant().abs() <= 1e-9 * scale * scale * scale {
            return None;
        }
        let p = m.inverse() * DVec3::new(-q[3], -q[6], -q[8]);
        p.is_finite().then_some(p)
    }
}

/// A candidate collapse in the queue (cheapest first).
#[derive(Clone, Copy, Debug)]
struct Candidate {
    cost: f64,
    a: u32,
    b: u32,
    stamps: (u32, u32),
    to: DVec3,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Candidate {}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: the max-heap yields the cheapest.
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| (other.a, other.b).cmp(&(self.a, self.b)))
    }
}

/// The working mesh of a simplification.
struct Work {
    pos: Vec<DVec3>,
    quadric: Vec<Quadric>,
    /// Triangles around each vertex (indices into `tris`; dead ones are
    /// skipped where read).
    around: Vec<Vec<u32>>,
    tris: Vec<[u32; 3]>,
    live: Vec<bool>,
    alive_vertex: Vec<bool>,
    stamp: Vec<u32>,
}

impl Work {
    fn new(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let n = vertices.len();
        let mut quadric = vec![Quadric::default(); n];
        let mut around = vec![Vec::new(); n];
        let mut edges: std::collections::HashMap<(u32, u32), u32> =
            std::collections::HashMap::new();
        for (k, t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let cross = (b - a).cross(c - a);
            let area = 0.5 * cross.length();
            if area > 0.0 {
                let n = cross.normalize();
                let q = Quadric::plane(n, -n.dot(a), area);
                for &i in t {
                    quadric[i as usize].add(&q);
                }
            }
            for &i in t {
                around[i as usize].push(k as u32);
            }
            for e in 0..3 {
                let (u, v) = (t[e], t[(e + 1) % 3]);
                *edges.entry((u.min(v), u.max(v))).or_insert(0) += 1;
            }
        }
        // Border edges: a plane through the edge, across its triangle, so
        // that the border does not move.
        for t in triangles {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let normal = (b - a).cross(c - a);
            for e in 0..3 {
                let (u, v) = (t[e], t[(e + 1) % 3]);
                if edges.get(&(u.min(v), u.max(v))) != Some(&1) {
                    continue;
                }
                let (p, r) = (vertices[u as usize], vertices[v as usize]);
                let across = (r - p).cross(normal).normalize_or_zero();
                if across == DVec3::ZERO {
                    continue;
                }
                let w = (r - p).length_squared() * 1e3;
                let q = Quadric::plane(across, -across.dot(p), w);
                quadric[u as usize].add(&q);
                quadric[v as usize].add(&q);
            }
        }
        Self {
            pos: vertices.to_vec(),
            quadric,
            around,
            tris: triangles.to_vec(),
            live: vec![true; triangles.len()],
            alive_vertex: vec![true; n],
            stamp: vec![0; n],
        }
    }

    /// The vertices sharing a live triangle with `v`.
    fn neighbours(&self, v: u32) -> HashSet<u32> {
        let mut out = HashSet::new();
        for &t in &self.around[v as usize] {
            if self.live[t as usize] {
                out.extend(self.tris[t as usize].iter().copied().filter(|&u| u != v));
            }
        }
        out
    }

    /// The collapse of edge `a`–`b`: where to and at what cost.
    fn candidate(&self, a: u32, b: u32) -> Candidate {
        let q = Quadric::sum(&self.quadric[a as usize], &self.quadric[b as usize]);
        let (pa, pb) = (self.pos[a as usize], self.pos[b as usize]);
        let mid = 0.5 * (pa + pb);
        let reach = (pb - pa).length();
        let mut best = [pa, pb, mid]
            .into_iter()
            .map(|p| (q.error(p), p))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .unwrap_or((0.0, mid));
        if let Some(p) = q.minimum().filter(|p| (*p - mid).length() <= reach) {
            let e = q.error(p);
            if e < best.0 {
                best = (e, p);
            }
        }
        Candidate {
            cost: best.0.max(0.0),
            a,
            b,
            stamps: (self.stamp[a as usize], self.stamp[b as usize]),
            to: best.1,
        }
    }

    /// Whether moving `a` and `b` to `to` keeps every remaining triangle
    /// around them facing the way it did, and not a sliver.
    fn keeps_shape(&self, a: u32, b: u32, to: DVec3) -> bool {
        for v in [a, b] {
            for &t in &self.around[v as usize] {
                let tri = self.tris[t as usize];
                if !self.live[t as usize] || (tri.contains(&a) && tri.contains(&b)) {
                    continue;
                }
                let p = tri.map(|i| self.pos[i as usize]);
                let q = tri.map(|i| {
                    if i == a || i == b {
                        to
                    } else {
                        self.pos[i as usize]
                    }
                });
                let before = (p[1] - p[0]).cross(p[2] - p[0]);
                let after = (q[1] - q[0]).cross(q[2] - q[0]);
                let longest = [(q[1] - q[0]), (q[2] - q[1]), (q[0] - q[2])]
                    .iter()
                    .map(|e| e.length_squared())
                    .fold(0.0, f64::max);
                if before.dot(after) <= 0.2 * before.length() * after.length()
                    || after.length() <= 1e-3 * longest
                {
                    return false;
                }
            }
        }
        true
    }

    /// Collapses `b` into `a` at `to`; returns the triangles removed.
    fn collapse(&mut self, a: u32, b: u32, to: DVec3) -> usize {
        let mut removed = 0;
        let moved = std::mem::take(&mut self.around[b as usize]);
        for &t in &moved {
            if !self.live[t as usize] {
                continue;
            }
            let tri = &mut self.tris[t as usize];
            if tri.contains(&a) {
                self.live[t as usize] = false;
                removed += 1;
            } else {
                for i in tri.iter_mut() {
                    if *i == b {
                        *i = a;
                    }
                }
                self.around[a as usize].push(t);
            }
        }
        self.around[a as usize].retain(|&t| self.live[t as usize]);
        self.pos[a as usize] = to;
        let qb = self.quadric[b as usize];
        self.quadric[a as usize].add(&qb);
        self.alive_vertex[b as usize] = false;
        self.stamp[a as usize] += 1;
        removed
    }
}

/// The mesh with at most `target` triangles where edges can go (see the
/// module docs); vertices that no triangle uses any more are dropped. A
/// mesh already within the budget comes back as it is.
#[must_use]
pub fn simplify(
    vertices: &[DVec3],
    triangles: &[[u32; 3]],
    target: usize,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    if triangles.len() <= target
        || triangles
            .iter()
            .flatten()
            .any(|&i| i as usize >= vertices.len())
    {
        return (vertices.to_vec(), triangles.to_vec());
    }
    let mut w = Work::new(vertices, triangles);
    let mut heap = BinaryHeap::new();
    let mut seen = HashSet::new();
    for t in triangles {
        for e in 0..3 {
            let (u, v) = (t[e], t[(e + 1) % 3]);
            if u != v && seen.insert((u.min(v), u.max(v))) {
                heap.push(w.candidate(u.min(v), u.max(v)));
            }
        }
    }
    let mut count = triangles
        .iter()
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .count();
    while count > target {
        let Some(c) = heap.pop() else { break };
        let (a, b) = (c.a, c.b);
        if !w.alive_vertex[a as usize]
            || !w.alive_vertex[b as usize]
            || c.stamps != (w.stamp[a as usize], w.stamp[b as usize])
        {
            continue;
        }
        let (na, nb) = (w.neighbours(a), w.neighbours(b));
        if !na.contains(&b) || na.intersection(&nb).count() > 2 || !w.keeps_shape(a, b, c.to) {
            continue;
        }
        count -= w.collapse(a, b, c.to);
        for n in w.neighbours(a) {
            heap.push(w.candidate(a.min(n), a.max(n)));
        }
    }
    compact(&w)
}

/// The live triangles over the vertices they use, renumbered.
fn compact(w: &Work) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut index = vec![u32::MAX; w.pos.len()];
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (t, live) in w.tris.iter().zip(&w.live) {
        if !*live || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            continue;
        }
        triangles.push(t.map(|i| {
            let slot = &mut index[i as usize];
            if *slot == u32::MAX {
                *slot = vertices.len() as u32;
                vertices.push(w.pos[i as usize]);
            }
            *slot
        }));
    }
    (vertices, triangles)
}

#[cfg(test)]
mod tests;
