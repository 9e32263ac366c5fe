//! One leg in time: a quintic polynomial in the leg's normalised time
//! `u = τ / T ∈ [0, 1]`, from a given state `(t, ṫ, ẗ)` to rest at an end
//! fraction, and the rules that choose its duration `T`.

/// Peak rate of a rest-to-rest quintic leg of span `h` over `T`, in units of
/// `h / T` (reached at mid-leg).
pub(crate) const NOMINAL_PEAK_RATE: f64 = 15.0 / 8.0;

/// Peak acceleration of a rest-to-rest quintic leg of span `h` over `T`, in
/// units of `h / T²`: `10 / √3`, reached at `u = (3 − √3) / 6`.
pub(crate) const NOMINAL_PEAK_ACCEL: f64 = 5.773_502_691_896_258;

/// How far (in `t`) a leg may numerically leave its segment and still count
/// as staying on it.
const SEGMENT_SLACK: f64 = 1e-9;

/// Grid on which the extremes of a leg's derivatives are bracketed.
const GRID: usize = 24;

/// Bisection steps refining each bracketed extreme.
const BISECTIONS: usize = 40;

/// The state of a point along its segment: fraction, rate (1/s) and
/// acceleration (1/s²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct State {
    pub t: f64,
    pub rate: f64,
    pub accel: f64,
}

/// A quintic in `u` that ends at rest: `p(u) = p₁ + (1 − u)³ q(u)` with `q`
/// quadratic (the triple root at `u = 1` is the rest condition), spanning a
/// duration `T` (s). The factored form is exact at arrival; the expanded
/// coefficients `c` serve the range checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Quintic {
    end: f64,
    q: [f64; 3],
    c: [f64; 6],
    duration: f64,
}

/// `Σ c_k u^k` by Horner's rule.
fn horner(c: &[f64], u: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ck| acc * u + ck)
}

/// Coefficients of the derivative (in `u`) of a polynomial of degree ≤ 5.
fn derivative(c: &[f64; 6]) -> [f64; 6] {
    let mut d = [0.0; 6];
    for k in 1..6 {
        d[k - 1] = c[k] * k as f64;
    }
    d
}

/// Smallest and largest value of the polynomial `c` over `u ∈ [0, 1]`:
/// the end values and the values where its derivative vanishes (bracketed
/// by sign changes on a grid, then bisected).
fn range(c: &[f64; 6]) -> (f64, f64) {
    let d = derivative(c);
    let (mut lo, mut hi) = {
        let (a, b) = (horner(c, 0.0), horner(c, 1.0));
        (a.min(b), a.max(b))
    };
    let mut include = |u: f64| {
        let v = horner(c, u);
        lo = lo.min(v);
        hi = hi.max(v);
    };
    let mut u0 = 0.0;
    let mut s0 = horner(&d, u0);
    for k in 1..=GRID {
        let u1 = k as f64 / GRID as f64;
        let s1 = horner(&d, u1);
        if s1 == 0.0 {
            include(u1);
        } else if s0 * s1 < 0.0 {
            let (mut a, mut b, mut sa) = (u0, u1, s0);
            for _ in 0..BISECTIONS {
                let m = 0.5 * (a + b);
                let sm = horner(&d, m);
                if sa * sm <= 0.0 {
                    b = m;
                } else {
                    (a, sa) = (m, sm);
                }
            }
            include(0.5 * (a + b));
        }
        (u0, s0) = (u1, s1);
    }
    (lo, hi)
}

impl Quintic {
    /// The quintic over `duration` seconds from `start` to rest
    /// (zero rate and acceleration) at fraction `end`.
    pub(crate) fn to_rest(start: State, end: f64, duration: f64) -> Self {
        let big_t = duration;
        // Initial conditions in `u`: p(0) = t, p'(0) = ṫ T, p''(0) = ẗ T².
        let v = start.rate * big_t;
        let a = start.accel * big_t * big_t;
        let q0 = start.t - end;
        let q1 = v + 3.0 * q0;
        let q2 = 0.5 * a - 3.0 * q0 + 3.0 * q1;
        // (1 − u)³ = 1 − 3u + 3u² − u³, times q, plus the end.
        let w = [1.0, -3.0, 3.0, -1.0];
        let mut c = [0.0; 6];
        for (i, wi) in w.iter().enumerate() {
            for (j, qj) in [q0, q1, q2].iter().enumerate() {
                c[i + j] += wi * qj;
            }
        }
        c[0] += end;
        Self {
            end,
            q: [q0, q1, q2],
            c,
            duration: big_t,
        }
    }

    /// Duration `T` (s).
    pub(crate) fn duration(&self) -> f64 {
        self.duration
    }

    /// `(1 − u)` and `q, q', q''` at `tau` seconds into the leg.
    fn factors(&self, tau: f64) -> (f64, f64, f64, f64) {
        let u = (tau / self.duration).clamp(0.0, 1.0);
        let [q0, q1, q2] = self.q;
        (1.0 - u, q0 + u * (q1 + u * q2), q1 + 2.0 * q2 * u, 2.0 * q2)
    }

    /// State `tau` seconds into the leg (`tau` clamped to `[0, T]`).
    pub(crate) fn state(&self, tau: f64) -> State {
        let big_t = self.duration;
        let (w, q, dq, ddq) = self.factors(tau);
        let w2 = w * w;
        State {
            t: self.end + w2 * w * q,
            rate: (w2 * (w * dq - 3.0 * q)) / big_t,
            accel: (w * (6.0 * q - 6.0 * w * dq + w2 * ddq)) / (big_t * big_t),
        }
    }

    /// Jerk (1/s³) `tau` seconds into the leg.
    #[cfg(test)]
    pub(crate) fn jerk(&self, tau: f64) -> f64 {
        let (w, q, dq, ddq) = self.factors(tau);
        (-6.0 * q + 18.0 * w * dq - 9.0 * w * w * ddq) / self.duration.powi(3)
    }

    /// Whether the leg stays on its segment (`t ∈ [0, 1]` throughout).
    pub(crate) fn stays_on_segment(&self) -> bool {
        let (lo, hi) = range(&self.c);
        lo >= -SEGMENT_SLACK && hi <= 1.0 + SEGMENT_SLACK
    }

    /// How far the leg's peaks exceed `caps`: the larger of
    /// `max |rate| / caps.rate` and `max |acceleration| / caps.accel`
    /// (≤ 1 when within the caps).
    pub(crate) fn excess(&self, caps: Caps) -> f64 {
        let big_t = self.duration;
        let d1 = derivative(&self.c);
        let (r_lo, r_hi) = range(&d1);
        let (a_lo, a_hi) = range(&derivative(&d1));
        let rate = r_lo.abs().max(r_hi.abs()) / big_t;
        let accel = a_lo.abs().max(a_hi.abs()) / (big_t * big_t);
        (rate / caps.rate).max(accel / caps.accel)
    }
}

/// Bounds on a re-shaped leg's |rate| (1/s) and |acceleration| (1/s²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Caps {
    pub rate: f64,
    pub accel: f64,
}

impl Caps {
    /// The retarget rule's caps: the nominal peaks of a rest-to-rest leg of
    /// span `span` over `time_per_value`, raised to the current |rate| and
    /// |acceleration| when those are already higher (a point cannot shed
    /// them instantly).
    pub(crate) fn retarget(span: f64, time_per_value: f64, now: State) -> Self {
        let t = time_per_value;
        Self {
            rate: (NOMINAL_PEAK_RATE * span / t).max(now.rate.abs()),
            accel: (NOMINAL_PEAK_ACCEL * span / (t * t)).max(now.accel.abs()),
        }
    }
}

/// Number of shorter durations tried for the first leg of a re-plan.
const REPLAN_SHORTER: usize = 12;

/// Ratio between consecutive durations tried.
const DURATION_STEP: f64 = 1.2;

/// The first leg of a route from `start` (possibly moving) to rest at `end`:
/// over `time_per_value` if that keeps the point on its segment, otherwise
/// over the longest duration in `time_per_value / 1.2^k` (`k ≤ 12`) that
/// does (a point coming fast at a node must stop there, so it arrives
/// sooner; a point moving away from the exit turns within the segment).
/// When none does (only a point already at a segment's end and moving off
/// it), the leg starts at rest.
pub(crate) fn first_leg(start: State, end: f64, time_per_value: f64) -> Quintic {
    // Repeated division (not `powi`) keeps the durations bit-identical
    // natively and in wasm.
    let mut duration = time_per_value;
    for _ in 0..=REPLAN_SHORTER {
        let q = Quintic::to_rest(start, end, duration);
        if q.stays_on_segment() {
            return q;
        }
        duration /= DURATION_STEP;
    }
    let rest = State {
        t: start.t.clamp(0.0, 1.0),
        ..State::default()
    };
    Quintic::to_rest(rest, end, time_per_value)
}

/// The re-shaped last leg over exactly `duration`, from `now` to rest at
/// `end`, if it stays on its segment and within `caps`.
pub(crate) fn reshape_on_time(now: State, end: f64, duration: f64, caps: Caps) -> Option<Quintic> {
    let q = Quintic::to_rest(now, end, duration);
    (q.stays_on_segment() && q.excess(caps) <= 1.0 + 1e-9).then_some(q)
}

/// Number of longer (and then shorter) durations tried for a retarget.
const RETARGET_LONGER: usize = 30;
const RETARGET_SHORTER: usize = 12;

/// The re-shaped last leg of a retarget, from `now` to rest at `end`: the
/// shortest duration among `t_min · 1.2^k` (`k = 0 ‥ 30`) whose peaks stay
/// within `caps` and which keeps the point on its segment; failing that,
/// durations below `t_min` (`t_min / 1.2^k`, `k ≤ 12`); failing that, the
/// candidate on the segment that exceeds the caps least; and as a last
/// resort (no candidate stays on the segment) a leg from rest.
pub(crate) fn reshape(now: State, end: f64, t_min: f64, caps: Caps) -> Quintic {
    // Repeated products (not `powi`) keep the durations bit-identical
    // natively and in wasm.
    let longer =
        std::iter::successors(Some(t_min), |d| Some(d * DURATION_STEP)).take(RETARGET_LONGER + 1);
    let shorter = std::iter::successors(Some(t_min / DURATION_STEP), |d| Some(d / DURATION_STEP))
        .take(RETARGET_SHORTER);
    let mut best: Option<(f64, Quintic)> = None;
    for duration in longer.chain(shorter) {
        let q = Quintic::to_rest(now, end, duration);
        if !q.stays_on_segment() {
            continue;
        }
        let excess = q.excess(caps);
        if excess <= 1.0 + 1e-9 {
            return q;
        }
        if best.is_none_or(|(e, _)| excess < e) {
            best = Some((excess, q));
        }
    }
    best.map_or_else(
        || {
            let rest = State {
                t: now.t.clamp(0.0, 1.0),
                ..State::default()
            };
            Quintic::to_rest(rest, end, t_min)
        },
        |(_, q)| q,
    )
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn boundary_conditions_hold_at_both_ends() {
        let start = State {
            t: 0.3,
            rate: 2.0,
            accel: -15.0,
        };
        let q = Quintic::to_rest(start, 0.8, 0.1);
        let s0 = q.state(0.0);
        assert!(close(s0.t, 0.3, 1e-14) && close(s0.rate, 2.0, 1e-12));
        assert!(close(s0.accel, -15.0, 1e-9));
        let s1 = q.state(0.1);
        assert!(close(s1.t, 0.8, 1e-14));
        assert!(close(s1.rate, 0.0, 1e-12) && close(s1.accel, 0.0, 1e-9));
    }

    #[test]
    fn rest_to_rest_peaks_match_the_nominal_constants() {
        let q = Quintic::to_rest(State::default(), 0.5, 0.2);
        let mid = q.state(0.1);
        assert!(close(mid.rate, NOMINAL_PEAK_RATE * 0.5 / 0.2, 1e-12));
        let u = (3.0 - 3f64.sqrt()) / 6.0;
        let a = q.state(u * 0.2).accel;
        assert!(close(a, NOMINAL_PEAK_ACCEL * 0.5 / 0.04, 1e-9));
        let caps = Caps {
            rate: NOMINAL_PEAK_RATE * 0.5 / 0.2,
            accel: NOMINAL_PEAK_ACCEL * 0.5 / 0.04,
        };
        assert!(close(q.excess(caps), 1.0, 1e-9));
        // Jerk is bounded: 60 h / T³ at the ends of a rest-to-rest leg.
        assert!(close(q.jerk(0.0), 60.0 * 0.5 / 0.008, 1e-6));
    }

    #[test]
    fn rest_to_rest_is_monotone_and_stays_on_the_segment() {
        let q = Quintic::to_rest(State::default(), 1.0, 0.1);
        assert!(q.stays_on_segment());
        let mut prev = -1.0;
        for k in 0..=100 {
            let s = q.state(k as f64 * 1e-3);
            assert!(s.t >= prev && s.rate >= -1e-12);
            prev = s.t;
        }
    }

    #[test]
    fn range_finds_interior_extremes() {
        // p(u) = u (1 − u): maximum 1/4 at u = 1/2.
        let (lo, hi) = range(&[0.0, 1.0, -1.0, 0.0, 0.0, 0.0]);
        assert!(close(lo, 0.0, 1e-15) && close(hi, 0.25, 1e-12));
    }

    #[test]
    fn a_fast_point_near_its_exit_arrives_sooner_instead_of_overshooting() {
        // At 0.9, moving at 5/s towards the exit at 1: over 0.1 s it would
        // overshoot (5 · 0.1 > 2.5 · 0.1).
        let start = State {
            t: 0.9,
            rate: 5.0,
            accel: 0.0,
        };
        assert!(!Quintic::to_rest(start, 1.0, 0.1).stays_on_segment());
        let q = first_leg(start, 1.0, 0.1);
        assert!(q.stays_on_segment() && q.duration() < 0.1);
        assert!(close(q.state(0.0).rate, 5.0, 1e-12));
        // From rest the paper's timing is kept.
        let q = first_leg(State::default(), 1.0, 0.1);
        assert!(close(q.duration(), 0.1, 1e-15));
    }

    #[test]
    fn a_point_at_the_end_moving_off_it_starts_at_rest() {
        let start = State {
            t: 1.0,
            rate: 3.0,
            accel: 0.0,
        };
        let q = first_leg(start, 0.0, 0.1);
        assert!(q.stays_on_segment());
        assert!(close(q.state(0.0).rate, 0.0, 1e-15));
    }

    #[test]
    fn reshape_keeps_the_time_left_when_the_caps_allow_it() {
        let start = State {
            t: 0.5,
            rate: 1.0,
            accel: 0.0,
        };
        let caps = Caps::retarget(1.0, 0.1, start);
        let q = reshape(start, 0.55, 0.05, caps);
        assert!(close(q.duration(), 0.05, 1e-15));
        // A far new end at the very end of the leg takes longer, within caps.
        let q = reshape(
            State {
                t: 0.9,
                ..State::default()
            },
            0.1,
            0.1 / 16.0,
            caps,
        );
        assert!(q.excess(caps) <= 1.0 + 1e-9 && q.duration() > 0.05);
    }
}
