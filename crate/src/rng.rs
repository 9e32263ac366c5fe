//! A small deterministic random number generator (SplitMix64 seeding a
//! xoshiro256** state) with uniform and Gaussian draws.
//!
//! The core cannot depend on an OS entropy source (it runs in wasm, and traces
//! must be bit-identical natively and in wasm), so every random draw in the
//! library and in its property tests comes from here, from an explicit seed.

/// Deterministic pseudo-random generator; same seed, same sequence, on every
/// target.
#[derive(Clone, Debug)]
pub struct Rng {
    s: [u64; 4],
    spare_normal: Option<f64>,
}

fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A seed for stream `(a, b)` of a family of streams seeded with `seed`:
/// SplitMix64's output function applied to `seed`, then to that result
/// xor `a` (scrambled), then xor `b` (scrambled again). Distinct `(a, b)`
/// give unrelated seeds, and nearby `seed`s do not give nearby streams.
/// A Monte Carlo study seeds obstacle `b` of run `a` with it
/// ([`crate::study`]).
///
/// # Example
/// ```
/// use skeleton_avoidance::rng::derive_seed;
/// assert_ne!(derive_seed(7, 0, 1), derive_seed(7, 1, 0));
/// assert_eq!(derive_seed(7, 3, 2), derive_seed(7, 3, 2));
/// ```
#[must_use]
pub fn derive_seed(seed: u64, a: u64, b: u64) -> u64 {
    let mut st = seed;
    let h = splitmix64(&mut st);
    let mut st = h ^ a.wrapping_mul(0xD1B5_4A32_D192_ED03);
    let h = splitmix64(&mut st);
    let mut st = h ^ b.wrapping_mul(0xAEF1_7502_108E_F2D9);
    splitmix64(&mut st)
}

impl Rng {
    /// A generator seeded with `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        let mut st = seed;
        let s = [
            splitmix64(&mut st),
            splitmix64(&mut st),
            splitmix64(&mut st),
            splitmix64(&mut st),
        ];
        Self {
            s,
            spare_normal: None,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let result = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        result
    }

    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Standard normal draw (Box–Muller, polar form).
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare_normal.take() {
            return z;
        }
        loop {
            let u = 2.0 * self.uniform() - 1.0;
            let v = 2.0 * self.uniform() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                let m = (-2.0 * crate::math::ln(s) / s).sqrt();
                self.spare_normal = Some(v * m);
                return u * m;
            }
        }
    }

    /// A point uniformly distributed in the cube `[-h, h]^3`.
    pub fn vec3(&mut self, h: f64) -> glam::DVec3 {
        glam::DVec3::new(self.range(-h, h), self.range(-h, h), self.range(-h, h))
    }

    /// A unit vector uniformly distributed on the sphere.
    pub fn unit3(&mut self) -> glam::DVec3 {
        loop {
            let v = self.vec3(1.0);
            let n2 = v.length_squared();
            if n2 > 1e-6 && n2 <= 1.0 {
                return v / n2.sqrt();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::Rng;

    #[test]
    fn sequence_is_the_same_on_every_target() {
        // Pinned values: a trace must be bit-identical natively and in wasm.
        let mut r = Rng::new(42);
        let first: Vec<u64> = (0..3).map(|_| r.next_u64()).collect();
        assert_eq!(
            first,
            [
                1_546_998_764_402_558_742,
                6_990_951_692_964_543_102,
                12_544_586_762_248_559_009
            ]
        );
        assert_eq!(Rng::new(42).normal().to_bits(), 0xbfe7_3d2f_eb0f_b377);
    }

    #[test]
    fn derived_seeds_are_pinned_and_distinct() {
        // Pinned: a study's runs must see the same streams on every target.
        assert_eq!(super::derive_seed(2024, 3, 1), 5_135_953_350_461_176_115);
        let mut seen = std::collections::BTreeSet::new();
        for seed in 0..4 {
            for a in 0..50 {
                for b in 0..5 {
                    assert!(seen.insert(super::derive_seed(seed, a, b)));
                }
            }
        }
    }

    #[test]
    fn same_seed_same_sequence() {
        let mut a = Rng::new(7);
        let mut b = Rng::new(7);
        for _ in 0..100 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
    }

    #[test]
    fn normal_has_unit_variance() {
        let mut r = Rng::new(1);
        let n = 20_000;
        let xs: Vec<f64> = (0..n).map(|_| r.normal()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.03, "mean {mean}");
        assert!((var - 1.0).abs() < 0.05, "var {var}");
    }
}
