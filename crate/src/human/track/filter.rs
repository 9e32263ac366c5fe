//! The jitter filter of recorded keypoints: a first-order low-pass run
//! forwards, then backwards, over the frames (zero phase lag), on frame
//! times that may be uneven.
//!
//! A forward pass alone lags a moving keypoint by its speed times the time
//! constant; the backward pass leads by as much, and the two cancel inside
//! the track. At its ends they do not: each pass starts from a sample the
//! other has not corrected, so a hand still moving when the recording
//! starts or stops would be replayed a speed × τ behind (3 cm at 1 m/s and
//! the default 30 ms). As scipy's `filtfilt` does, the series is therefore
//! extended at each end by its point reflection about the end sample (times
//! reflected too) over about [`PAD_TAUS`] time constants, so that each pass
//! has settled when it reaches a recorded frame; the extension is then
//! dropped. A keypoint moving at constant velocity is kept exactly, to the
//! transient left after the extension (e^−8 of the lag).

use glam::DVec3;

/// Time constants of reflected frames added at each end (as many frames as
/// the series has, at most).
pub const PAD_TAUS: f64 = 8.0;

/// The forward–backward first-order low-pass of time constant `tau` (s)
/// over `series` sampled at `times` (increasing), in place; `tau <= 0` or
/// fewer than three frames leaves it as it is.
pub fn smooth(times: &[f64], series: &mut [DVec3], tau: f64) {
    let n = series.len();
    if tau <= 0.0 || n < 3 || times.len() != n {
        return;
    }
    // Frames reflected at each end: those within PAD_TAUS·τ of that end.
    let span = PAD_TAUS * tau;
    let head = (1..n)
        .take_while(|&k| times[k] - times[0] <= span)
        .count()
        .max(1);
    let tail = (1..n)
        .take_while(|&k| times[n - 1] - times[n - 1 - k] <= span)
        .count()
        .max(1);
    let mut t = Vec::with_capacity(n + head + tail);
    let mut x = Vec::with_capacity(n + head + tail);
    for k in (1..=head).rev() {
        t.push(2.0 * times[0] - times[k]);
        x.push(2.0 * series[0] - series[k]);
    }
    t.extend_from_slice(times);
    x.extend_from_slice(series);
    for k in 1..=tail {
        t.push(2.0 * times[n - 1] - times[n - 1 - k]);
        x.push(2.0 * series[n - 1] - series[n - 1 - k]);
    }
    let alpha = |k: usize| 1.0 - crate::math::exp(-(t[k] - t[k - 1]) / tau);
    for k in 1..x.len() {
        x[k] = x[k - 1] + (x[k] - x[k - 1]) * alpha(k);
    }
    for k in (1..x.len()).rev() {
        x[k - 1] = x[k] + (x[k - 1] - x[k]) * alpha(k);
    }
    series.copy_from_slice(&x[head..head + n]);
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;

    /// Uneven frame times: 60 Hz with every third frame late by 4 ms.
    fn uneven(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| 0.5 + k as f64 / 60.0 + if k % 3 == 1 { 0.004 } else { 0.0 })
            .collect()
    }

    /// Largest error at the first and last three frames, and between them,
    /// of smoothing a keypoint moving at 1.1 m/s over `times`.
    fn ramp_errors(times: &[f64]) -> (f64, f64) {
        let v = DVec3::new(1.0, -0.4, 0.2);
        let raw: Vec<DVec3> = times
            .iter()
            .map(|&t| DVec3::new(0.3, 1.0, 0.9) + v * t)
            .collect();
        let mut smoothed = raw.clone();
        smooth(times, &mut smoothed, 0.03);
        let e: Vec<f64> = raw
            .iter()
            .zip(&smoothed)
            .map(|(a, b)| (*a - *b).length())
            .collect();
        let n = e.len();
        let ends = e[..3]
            .iter()
            .chain(&e[n - 3..])
            .copied()
            .fold(0.0, f64::max);
        (ends, e[3..n - 3].iter().copied().fold(0.0, f64::max))
    }

    #[test]
    fn a_keypoint_at_constant_velocity_is_kept_to_the_ends() {
        // Without the reflected ends the first and last frames were 15 and
        // 24 mm behind (|v|·τ = 33 mm at steady state).
        let even: Vec<f64> = (0..60).map(|k| 0.5 + k as f64 / 60.0).collect();
        let (ends, inside) = ramp_errors(&even);
        assert!(
            ends < 2e-5 && inside < 2e-5,
            "ends {ends} m, inside {inside} m"
        );
        // Uneven steps: a variable-step first-order filter itself leaves
        // about 0.7 mm inside the track; the ends are no worse.
        let (ends, inside) = ramp_errors(&uneven(60));
        assert!(
            inside < 1e-3 && ends < 1.5 * inside,
            "ends {ends} m, inside {inside} m"
        );
    }

    #[test]
    fn jitter_is_reduced_and_a_short_track_is_still_smoothed() {
        let times = uneven(240);
        let mut rng = crate::rng::Rng::new(11);
        let truth = |t: f64| DVec3::new((2.0 * t).sin(), (1.3 * t).cos(), 0.5 * t);
        let raw: Vec<DVec3> = times
            .iter()
            .map(|&t| truth(t) + 0.01 * DVec3::new(rng.normal(), rng.normal(), rng.normal()))
            .collect();
        let mut smoothed = raw.clone();
        smooth(&times, &mut smoothed, 0.03);
        let rms = |s: &[DVec3]| {
            let sum: f64 = s
                .iter()
                .zip(&times)
                .map(|(p, &t)| (*p - truth(t)).length_squared())
                .sum();
            (sum / s.len() as f64).sqrt()
        };
        assert!(
            rms(&smoothed) < 0.6 * rms(&raw),
            "{} vs {}",
            rms(&smoothed),
            rms(&raw)
        );
        // Three frames, fewer than the extension wants: smoothed all the same.
        let mut short = raw[..3].to_vec();
        smooth(&times[..3], &mut short, 0.03);
        assert!(short.iter().all(|p| p.is_finite()));
    }

    #[test]
    fn no_smoothing_or_too_few_frames_leave_the_series() {
        let times = uneven(5);
        let raw: Vec<DVec3> = (0..5).map(|k| DVec3::splat(k as f64 * k as f64)).collect();
        for (tau, n) in [(0.0, 5), (-1.0, 5), (0.03, 2)] {
            let mut s = raw[..n].to_vec();
            smooth(&times[..n], &mut s, tau);
            assert_eq!(s, raw[..n]);
        }
    }
}
