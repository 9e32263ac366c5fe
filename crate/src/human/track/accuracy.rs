//! How closely the fitted body follows the recording: per joint, the
//! distance between the body's joint and the recorded one over the frames
//! (the recording as repaired: gaps filled, jitter smoothed).

use std::collections::BTreeMap;

use glam::DVec3;
use serde::Serialize;

use crate::human::{Human, Posed};
use crate::parsers::track::NEEDED;

/// The fit's error at one joint over the frames (m).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct JointError {
    /// The 95th percentile.
    pub p95: f64,
    /// The largest.
    pub max: f64,
}

/// The body's shoulders, elbows, wrists, hips, knees and ankles, in the
/// order of the first twelve of [`NEEDED`].
#[must_use]
pub fn body_joints(p: &Posed) -> [DVec3; 12] {
    use crate::distance::PrimitiveSpec as S;
    let end = |k: usize, b: bool| match p.parts.get(k).map(|x| &x.shape) {
        Some(S::Capsule(c)) => DVec3::from_array(if b { c.b } else { c.a }),
        _ => DVec3::ZERO,
    };
    [
        end(4, false),
        end(7, false),
        end(4, true),
        end(7, true),
        end(5, true),
        end(8, true),
        end(10, false),
        end(13, false),
        end(10, true),
        end(13, true),
        end(11, true),
        end(14, true),
    ]
}

/// The error at each joint (named as in [`NEEDED`]) of `human` posed at
/// `times[k] − times[0]` against `joints[k]`.
pub(super) fn fit_error(
    human: &Human,
    times: &[f64],
    joints: &[[DVec3; 14]],
) -> BTreeMap<String, JointError> {
    let mut errors: [Vec<f64>; 12] = Default::default();
    for (&t, j) in times.iter().zip(joints) {
        let body = body_joints(&human.posed_at(t - times[0], DVec3::ZERO, DVec3::ZERO));
        for (s, e) in errors.iter_mut().enumerate() {
            e.push((body[s] - j[s]).length());
        }
    }
    let mut out = BTreeMap::new();
    for (name, mut e) in NEEDED.iter().zip(errors) {
        e.sort_by(f64::total_cmp);
        if let Some(&max) = e.last() {
            let rank = ((0.95 * e.len() as f64).ceil() as usize).clamp(1, e.len());
            out.insert(
                (*name).to_owned(),
                JointError {
                    p95: e[rank - 1],
                    max,
                },
            );
        }
    }
    out
}
