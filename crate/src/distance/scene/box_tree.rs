//! The broad phase of the scene query: axis-aligned boxes of the primitives
//! (infinite for planes) and a tree of boxes over the finite ones (a
//! bounding-volume hierarchy, [`BoxTree`]), built by a median split on the
//! widest axis. (`bvh` in this crate names the motion-capture format read by
//! `crate::parsers::track::bvh`, not this tree.)

use glam::DVec3;

use super::super::{LineSegment, Primitive};

/// An axis-aligned box; infinite for planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Aabb {
    pub(super) min: DVec3,
    pub(super) max: DVec3,
}

impl Aabb {
    fn of_points(pts: impl IntoIterator<Item = DVec3>) -> Self {
        let mut b = Self {
            min: DVec3::INFINITY,
            max: DVec3::NEG_INFINITY,
        };
        for p in pts {
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
        b
    }
    pub(super) fn grown(self, r: f64) -> Self {
        Self {
            min: self.min - DVec3::splat(r),
            max: self.max + DVec3::splat(r),
        }
    }
    fn union(self, o: Self) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    pub(super) fn overlaps(&self, o: &Self) -> bool {
        self.min.cmple(o.max).all() && o.min.cmple(self.max).all()
    }
    pub(super) fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }
    fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }
}

pub(super) fn bounds_of(p: &Primitive) -> Aabb {
    let seg = |s: &LineSegment, r: f64| Aabb::of_points([s.a, s.b]).grown(r);
    match p {
        Primitive::Point(q) => Aabb::of_points([*q]),
        Primitive::Segment(s) => seg(s, 0.0),
        Primitive::Sphere(s) => Aabb::of_points([s.center]).grown(s.radius),
        Primitive::Capsule(c) => seg(&c.segment, c.radius),
        Primitive::TaperedCapsule(c) => seg(&c.segment, c.max_radius()),
        Primitive::Plane(_) => Aabb {
            min: DVec3::NEG_INFINITY,
            max: DVec3::INFINITY,
        },
        Primitive::Rectangle(r) => Aabb::of_points(r.corners()),
        Primitive::Disk(d) => {
            let m = d.normal;
            let e = DVec3::new(
                (1.0 - m.x * m.x).max(0.0).sqrt(),
                (1.0 - m.y * m.y).max(0.0).sqrt(),
                (1.0 - m.z * m.z).max(0.0).sqrt(),
            ) * d.radius;
            Aabb {
                min: d.center - e,
                max: d.center + e,
            }
        }
        Primitive::Polygon(poly) => Aabb::of_points(poly.vertices().iter().copied()),
        Primitive::Box(b) => {
            let h = b.half_extents;
            let e = b.axes[0].abs() * h.x + b.axes[1].abs() * h.y + b.axes[2].abs() * h.z;
            Aabb {
                min: b.center - e,
                max: b.center + e,
            }
        }
        Primitive::ConvexHull(h) => Aabb::of_points(h.points().iter().copied()),
    }
}

#[derive(Clone, Copy, Debug)]
enum Node {
    Leaf {
        bounds: Aabb,
        start: usize,
        end: usize,
    },
    Inner {
        bounds: Aabb,
        left: usize,
        right: usize,
    },
}

/// A bounding-volume hierarchy over finite boxes: a binary tree whose
/// leaves hold a few items each.
#[derive(Clone, Debug, Default)]
pub(super) struct BoxTree {
    nodes: Vec<Node>,
    items: Vec<usize>,
}

impl BoxTree {
    const LEAF: usize = 4;

    pub(super) fn build(bounds: &[Aabb], items: Vec<usize>) -> Self {
        let mut tree = Self {
            // A binary tree with at least one item per leaf has fewer
            // than 2n nodes: no regrowth while the scene is rebuilt.
            nodes: Vec::with_capacity(2 * items.len()),
            items,
        };
        if !tree.items.is_empty() {
            let n = tree.items.len();
            tree.split(bounds, 0, n);
        }
        tree
    }

    fn split(&mut self, bounds: &[Aabb], start: usize, end: usize) -> usize {
        let b = self.items[start..end].iter().map(|&i| bounds[i]).fold(
            Aabb {
                min: DVec3::INFINITY,
                max: DVec3::NEG_INFINITY,
            },
            Aabb::union,
        );
        let me = self.nodes.len();
        if end - start <= Self::LEAF {
            self.nodes.push(Node::Leaf {
                bounds: b,
                start,
                end,
            });
            return me;
        }
        self.nodes.push(Node::Leaf {
            bounds: b,
            start,
            end,
        });
        let c = Aabb::of_points(self.items[start..end].iter().map(|&i| bounds[i].center()));
        let ext = c.max - c.min;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        self.items[start..end].select_nth_unstable_by(mid - start, |&i, &j| {
            bounds[i].center()[axis].total_cmp(&bounds[j].center()[axis])
        });
        let left = self.split(bounds, start, mid);
        let right = self.split(bounds, mid, end);
        self.nodes[me] = Node::Inner {
            bounds: b,
            left,
            right,
        };
        me
    }

    pub(super) fn query(&self, q: &Aabb, out: &mut Vec<usize>) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0usize; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            match self.nodes[stack[top]] {
                Node::Leaf { bounds, start, end } => {
                    if bounds.overlaps(q) {
                        out.extend_from_slice(&self.items[start..end]);
                    }
                }
                Node::Inner {
                    bounds,
                    left,
                    right,
                } => {
                    if bounds.overlaps(q) && top + 2 <= stack.len() {
                        stack[top] = left;
                        stack[top + 1] = right;
                        top += 2;
                    }
                }
            }
        }
    }
}
