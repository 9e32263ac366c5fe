//! Synthetic recordings: the keypoints of a posed body in any layout (the
//! shipped sample, and the tests' ground truth).

use glam::DVec3;

use super::layout::{Anchors, Layout};
use super::{TrackFile, TrackFrame};
use crate::distance::PrimitiveSpec;
use crate::human::{Human, Posed};

fn ends(p: &Posed, k: usize) -> (DVec3, DVec3) {
    match p.parts.get(k).map(|x| &x.shape) {
        Some(PrimitiveSpec::Capsule(c)) => (DVec3::from_array(c.a), DVec3::from_array(c.b)),
        Some(PrimitiveSpec::Sphere(s)) => {
            let c = DVec3::from_array(s.center);
            (c, c)
        }
        _ => (DVec3::ZERO, DVec3::ZERO),
    }
}

/// The keypoints of `human` at each of `times` (s) in `layout`: a track
/// that [`super::import`] maps back onto the same body (given its height,
/// without smoothing) to rounding.
#[must_use]
pub fn synthesize(human: &Human, layout: Layout, times: &[f64]) -> TrackFile {
    let h = human.spec().height;
    let frames = times
        .iter()
        .map(|&t| {
            let p = human.posed_at(t, DVec3::ZERO, DVec3::ZERO);
            // Part indices: see PART_NAMES.
            let (ls, le) = ends(&p, 4);
            let (rs, re) = ends(&p, 7);
            let (_, lw) = ends(&p, 5);
            let (_, rw) = ends(&p, 8);
            let (lh, lk) = ends(&p, 10);
            let (rh, rk) = ends(&p, 13);
            let (_, la) = ends(&p, 11);
            let (_, ra) = ends(&p, 14);
            let (head, _) = ends(&p, 3);
            let left = (ls - rs).normalize_or(DVec3::Y);
            let a = Anchors {
                j: [ls, rs, le, re, lw, rw, lh, rh, lk, rk, la, ra, head, head],
                hand: [ends(&p, 6), ends(&p, 9)],
                foot: [ends(&p, 12), ends(&p, 15)],
                left,
                forward: left.cross(DVec3::Z).normalize_or(DVec3::X),
                height: h,
            };
            TrackFrame {
                t,
                keypoints: layout
                    .names()
                    .iter()
                    .map(|n| Some(a.at(n).to_array()))
                    .collect(),
            }
        })
        .collect();
    TrackFile {
        layout: Some(layout.name().to_owned()),
        frames,
    }
}
