//! SplitMix64, the bootstrap's generator (docs/SCORE.md §10.3): a 64-bit state advanced by
//! the golden-ratio increment and mixed by two multiply-xorshift rounds. Written out here so that
//! every front end (and any other implementation of the spec) draws the same indices. A
//! comparison makes one per model and metric, each seeded with `bootstrap_seed`.
//!
//! ```
//! use monitor_host::stats::splitmix::SplitMix64;
//! let mut g = SplitMix64::new(0);
//! assert_eq!(g.next_u64(), 0xe220a8397b1dcdaf);
//! assert_eq!(g.index(10), 4); // (0x6e789e6aa1b965f4 >> 11) * 2^-53 * 10 = 4.31...
//! ```

/// The generator: its state `s`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator seeded with `seed` (the setting `bootstrap_seed`).
    pub fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    /// The next output: `s += 0x9E3779B97F4A7C15`, then the two mixing rounds (wrapping u64).
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// One draw of an index in `0..n`: `floor(((next() >> 11) * 2^-53) * n)`. The top 53 bits
    /// make a double in [0, 1) exactly; the product is below `n`, so the index is in range.
    pub fn index(&mut self, n: usize) -> usize {
        // Below 2^53, so the signed conversion (one instruction) is exact.
        let unit = ((self.next_u64() >> 11) as i64) as f64 * (1.0 / (1u64 << 53) as f64);
        // The product is >= 0, so the cast's truncation is the floor (and needs no libm call,
        // which `f64::floor` is on x86-64 without SSE4.1). `unit * n` < n for every n below
        // 2^53; `min` keeps that true whatever n is.
        ((unit * n as f64) as i64 as usize).min(n.saturating_sub(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published first outputs of SplitMix64 for seed 0 (Vigna's reference `splitmix64.c`).
    #[test]
    fn published_outputs_for_seed_zero() {
        let mut g = SplitMix64::new(0);
        let got: Vec<u64> = (0..4).map(|_| g.next_u64()).collect();
        assert_eq!(
            got,
            [
                0xe220_a839_7b1d_cdaf,
                0x6e78_9e6a_a1b9_65f4,
                0x06c4_5d18_8009_454f,
                0xf88b_b8a8_724c_81ec
            ]
        );
    }

    #[test]
    fn the_state_wraps() {
        let mut g = SplitMix64::new(u64::MAX);
        let mut h = SplitMix64::new(0);
        // u64::MAX + golden = golden - 1: a different stream, computed without overflow panics.
        assert_ne!(g.next_u64(), h.next_u64());
    }

    #[test]
    fn index_is_the_top_53_bits_scaled() {
        let mut g = SplitMix64::new(0);
        let mut h = SplitMix64::new(0);
        for n in [1usize, 2, 3, 7, 220, 1_000_000] {
            let x = h.next_u64();
            let want = (((x >> 11) as f64 / 9_007_199_254_740_992.0) * n as f64).floor() as usize;
            assert_eq!(g.index(n), want);
            assert!(want < n);
        }
        // (0xe220a8397b1dcdaf >> 11) / 2^53 = 0.8833...: index 8 of 10.
        assert_eq!(SplitMix64::new(0).index(10), 8);
    }
}
