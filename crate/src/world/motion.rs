//! How the parts of the scene move: a part's two axis ends and their
//! velocities ([`PartMotion`]), and the velocity an edit gives a figure that
//! is dragged ([`drag_velocity`]).

use glam::DVec3;

/// How one part of the scene moves: the velocities of the two ends of its
/// axis (a rigid primitive: both the obstacle's velocity).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct PartMotion {
    pub(super) a: DVec3,
    pub(super) b: DVec3,
    pub(super) va: DVec3,
    pub(super) vb: DVec3,
}

impl PartMotion {
    pub(super) fn rigid(v: DVec3) -> Self {
        Self {
            va: v,
            vb: v,
            ..Self::default()
        }
    }

    /// Velocity (m/s) of the material point of the part nearest `p`.
    pub(super) fn velocity_at(&self, p: DVec3) -> DVec3 {
        let ab = self.b - self.a;
        let l2 = ab.length_squared();
        if l2 == 0.0 {
            return self.va;
        }
        let u = ((p - self.a).dot(ab) / l2).clamp(0.0, 1.0);
        self.va + (self.vb - self.va) * u
    }

    /// The fastest point's speed (m/s).
    pub(super) fn peak_speed(&self) -> f64 {
        self.va.length().max(self.vb.length())
    }
}

/// How long the velocity of an edit holds without a further edit (s): a
/// page moves a dragged figure once per frame (16.7 ms at 60 Hz, up to
/// 100 ms on a slow page).
pub(super) const DRAG_HOLD: f64 = 0.1;

/// The velocity edits give a figure moved by `moved` at time `t`, after the
/// previous edit `previous`: the move over the time since that edit; a
/// first edit, or one after a pause of more than `4 × DRAG_HOLD`, starts
/// at rest; a second edit within the same step keeps the estimate.
pub(super) fn drag_velocity(
    previous: Option<(f64, DVec3)>,
    moved: DVec3,
    t: f64,
) -> Option<(f64, DVec3)> {
    match previous {
        Some((at, _)) if t > at && t - at <= 4.0 * DRAG_HOLD => Some((t, moved / (t - at))),
        Some((at, v)) if t <= at => Some((at, v)),
        _ => Some((t, DVec3::ZERO)),
    }
}
