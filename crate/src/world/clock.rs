//! Simulated time without accumulated rounding: after `k` steps of the same
//! `dt` from time `t₀`, the time is `t₀ + k·dt` computed once, not a sum of
//! `k` rounded additions (8 s at 1 ms is `8`, not `8.000000000001005`).

/// The world's step counter since the last change of step (or of time).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Clock {
    /// Time when the current run of equal steps began (s).
    base: f64,
    /// Their step (s).
    dt: f64,
    /// How many of them were taken.
    steps: u64,
}

impl Clock {
    /// The time after one more step of `dt` from `t`. A new step length, or
    /// a `t` that is not where this clock left it, starts a new run at `t`.
    pub(super) fn advance(&mut self, t: f64, dt: f64) -> f64 {
        // Exact comparisons on purpose: any other step or time starts afresh.
        #[allow(clippy::float_cmp)]
        let same_run = self.steps > 0 && dt == self.dt && t == self.now();
        if !same_run {
            *self = Self {
                base: t,
                dt,
                steps: 0,
            };
        }
        self.steps += 1;
        self.now()
    }

    fn now(&self) -> f64 {
        self.base + self.steps as f64 * self.dt
    }
}

#[cfg(test)]
mod tests {
    use super::Clock;

    #[test]
    fn equal_steps_land_on_multiples_of_dt() {
        let mut c = Clock::default();
        let mut t = 0.0;
        for _ in 0..8000 {
            t = c.advance(t, 0.001);
        }
        assert_eq!(t, 8.0);
        let mut sum = 0.0;
        for _ in 0..8000 {
            sum += 0.001;
        }
        assert_ne!(sum, 8.0, "a running sum drifts: {sum}");
    }

    #[test]
    fn a_new_step_or_time_starts_a_new_run() {
        let mut c = Clock::default();
        let t = c.advance(0.0, 0.25);
        let t = c.advance(t, 0.5);
        assert_eq!(t, 0.75);
        assert_eq!(c.advance(10.0, 0.5), 10.5);
        assert_eq!(c.advance(10.5, 0.5), 11.0);
    }
}
