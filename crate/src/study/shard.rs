//! Shards of a study for batch schedulers: shard `i` of `n` runs one
//! contiguous block of the runs, `⌊i N / n⌋ .. ⌊(i + 1) N / n⌋`, so that the
//! `n` shards cover runs `0..N` once each, in blocks whose sizes differ by
//! at most one.

use std::ops::Range;

use crate::error::FieldError;

/// Shard `index` of `count` (`index` in `0..count`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which shard (0-based).
    pub index: u64,
    /// How many shards.
    pub count: u64,
}

impl Shard {
    /// The whole study as one shard.
    pub const ALL: Self = Self { index: 0, count: 1 };

    /// A shard, checked.
    ///
    /// # Errors
    /// `shard: the number of shards must be ≥ 1`, `shard: 4 is outside
    /// 0..4 (shards are numbered from 0)`.
    pub fn new(index: u64, count: u64) -> Result<Self, FieldError> {
        if count == 0 {
            return Err(FieldError::new("shard", "the number of shards must be ≥ 1"));
        }
        if index >= count {
            return Err(FieldError::new(
                "shard",
                format!("{index} is outside 0..{count} (shards are numbered from 0)"),
            ));
        }
        Ok(Self { index, count })
    }

    /// Reads `i/n` (e.g. `3/16`).
    ///
    /// # Errors
    /// `shard: expected i/n …`, then [`Shard::new`]'s.
    pub fn parse(text: &str) -> Result<Self, FieldError> {
        let bad = || {
            FieldError::new(
                "shard",
                format!("expected i/n with whole numbers i in 0..n (e.g. 0/4), got \"{text}\""),
            )
        };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let i = i.trim().parse::<u64>().map_err(|_| bad())?;
        let n = n.trim().parse::<u64>().map_err(|_| bad())?;
        Self::new(i, n)
    }

    /// The runs of this shard among `runs` runs.
    #[must_use]
    pub fn range(&self, runs: u64) -> Range<u64> {
        let at = |k: u64| (u128::from(k) * u128::from(runs) / u128::from(self.count)) as u64;
        at(self.index)..at(self.index + 1)
    }
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::Shard;

    #[test]
    fn shards_cover_every_run_once_in_near_equal_blocks() {
        for runs in [1, 2, 7, 10, 1000, 1_000_000] {
            for count in [1, 2, 3, 7, 16] {
                let mut next = 0;
                for index in 0..count {
                    let r = Shard::new(index, count).unwrap().range(runs);
                    assert_eq!(r.start, next);
                    let len = r.end - r.start;
                    assert!(len == runs / count || len == runs / count + 1);
                    next = r.end;
                }
                assert_eq!(next, runs);
            }
        }
    }

    #[test]
    fn bad_shards_are_refused_with_the_reason() {
        let e = Shard::parse("4/4").unwrap_err().to_string();
        assert!(e.starts_with("shard: 4 is outside 0..4"), "{e}");
        assert!(Shard::parse("0/0").unwrap_err().to_string().contains("≥ 1"));
        for text in ["", "1", "a/2", "-1/2", "1/2/3", "1.5/2"] {
            let e = Shard::parse(text).unwrap_err().to_string();
            assert!(e.contains("expected i/n"), "{text}: {e}");
        }
        assert_eq!(Shard::parse(" 2 / 5").unwrap(), Shard::new(2, 5).unwrap());
    }
}
