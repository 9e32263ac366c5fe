//! The skeleton: nodes and tapered segments built from the DH table (paper §II,
//! fig. 1). (Construction being written.)

use glam::DVec3;

/// Which translation of its DH row a segment spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum SpinePart {
    /// The `d` translation, along the row's z axis.
    D,
    /// The `a` translation, along the row's x axis.
    A,
    /// An extra spine piece behind the joint (counterbalance, motor): `a' < 0`.
    Extension,
}

/// One segment of the skeleton, between two nodes, with the radius of the
/// volume of revolution around it varying linearly from `radius[0]` at `from`
/// to `radius[1]` at `to` (a tapered capsule).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Index of the start node.
    pub from: usize,
    /// Index of the end node.
    pub to: usize,
    /// The DH row (1-based link index) whose translation this segment spans.
    pub link: usize,
    /// Which translation of the row.
    pub part: SpinePart,
    /// Radius at `from` and at `to` (m).
    pub radius: [f64; 2],
}

/// Nodes (Cartesian points, m, world frame) and the segments between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    /// Node positions.
    pub nodes: Vec<DVec3>,
    /// Segments between nodes.
    pub segments: Vec<Segment>,
}

impl Skeleton {
    /// End points of segment `s`.
    #[must_use]
    pub fn endpoints(&self, s: &Segment) -> (DVec3, DVec3) {
        (self.nodes[s.from], self.nodes[s.to])
    }
}
