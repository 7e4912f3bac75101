//! Version-stable random draws built on `RngCore::next_u64` alone, and the sampler of
//! free cells that RRT, RRT* and RRT-Connect share.
//!
//! `rand`'s distributions (`gen_range`, `gen_bool`) may change their algorithms between
//! versions, so the planners use only the raw 64-bit output of ChaCha8 (whose stream is
//! fixed by the cipher) and reduce it with [`below`] and [`coin`].

use planner_api::{Cell, Grid};
use rand_chacha::rand_core::RngCore;
use rand_chacha::ChaCha8Rng;

/// Draws sample cells: the goal with a given probability, else a free cell uniformly.
///
/// Keeps the flat indices of the grid's free cells between searches, so refilling it for
/// a grid of the same size allocates nothing.
#[derive(Debug, Clone, Default)]
pub struct Sampler {
    free: Vec<u32>,
}

impl Sampler {
    /// Refills the population with `grid`'s free cells, in flat-index order.
    pub fn reset(&mut self, grid: &Grid) {
        self.free.clear();
        self.free.extend(
            (0u32..)
                .zip(grid.free_cells())
                .filter_map(|(index, &free)| free.then_some(index)),
        );
    }

    /// The bytes [`Sampler::reset`] allocates for a grid of `n_free` free cells: 4 each.
    pub fn bytes_for(n_free: u64) -> u64 {
        4 * n_free
    }

    /// Number of free cells in the population.
    pub fn n_free(&self) -> usize {
        self.free.len()
    }

    /// A free cell of `grid` drawn uniformly with one [`below`] draw.
    /// Preconditions: [`Sampler::reset`] was called with `grid`, which has a free cell.
    pub fn uniform(&self, rng: &mut impl RngCore, grid: &Grid) -> Cell {
        let n_free = self.free.len() as u64;
        grid.cell(self.free[below(rng, n_free) as usize] as usize)
    }

    /// With probability `goal_bias` (one [`coin`] draw) `(goal, true)`; otherwise a
    /// [`Sampler::uniform`] free cell (which may be the goal) and `false`. Same
    /// preconditions as [`Sampler::uniform`].
    pub fn goal_biased(
        &self,
        rng: &mut impl RngCore,
        grid: &Grid,
        goal: Cell,
        goal_bias: f64,
    ) -> (Cell, bool) {
        if coin(rng, goal_bias) {
            (goal, true)
        } else {
            (self.uniform(rng, grid), false)
        }
    }
}

/// The generator for `seed`: ChaCha8 with the 32-byte key `seed.to_le_bytes()` followed
/// by 24 zero bytes, stream 0, block counter 0.
///
/// The key is spelled out rather than taken from `SeedableRng::seed_from_u64`, whose
/// seed expansion is not part of ChaCha and could change between `rand_core` versions.
pub fn rng_for_seed(seed: u64) -> ChaCha8Rng {
    use rand_chacha::rand_core::SeedableRng;
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    ChaCha8Rng::from_seed(key)
}

/// A uniform integer in `0..n` by Lemire's multiply-shift with rejection ("Fast Random
/// Integer Generation in an Interval", 2019): the high 64 bits of `r * n` are the result;
/// draws whose low 64 bits fall below `2^64 mod n` are redrawn, which makes the result
/// exactly uniform. Precondition: `n >= 1`.
pub fn below(rng: &mut impl RngCore, n: u64) -> u64 {
    let mut m = u128::from(rng.next_u64()) * u128::from(n);
    if (m as u64) < n {
        let threshold = n.wrapping_neg() % n;
        while (m as u64) < threshold {
            m = u128::from(rng.next_u64()) * u128::from(n);
        }
    }
    (m >> 64) as u64
}

/// True with probability `p` (`0 <= p <= 1`): the top 53 bits of one draw as the
/// uniform `u = k / 2^53` in `[0, 1)`, and `u < p`. Exact in `f64`, so `p = 0` never and
/// `p = 1` always holds.
pub fn coin(rng: &mut impl RngCore, p: f64) -> bool {
    let u = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
    u < p
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replays fixed words.
    struct Replay(Vec<u64>);

    impl RngCore for Replay {
        fn next_u32(&mut self) -> u32 {
            self.next_u64() as u32
        }
        fn next_u64(&mut self) -> u64 {
            self.0.remove(0)
        }
        fn fill_bytes(&mut self, _: &mut [u8]) {
            unimplemented!()
        }
        fn try_fill_bytes(&mut self, _: &mut [u8]) -> Result<(), rand_chacha::rand_core::Error> {
            unimplemented!()
        }
    }

    #[test]
    fn below_by_hand() {
        // 2^63 * 3 = 1.5 * 2^64: high word 1.
        assert_eq!(below(&mut Replay(vec![1 << 63]), 3), 1);
        // (2^64 - 1) * 3 = 2 * 2^64 + (2^64 - 3): high word 2.
        assert_eq!(below(&mut Replay(vec![u64::MAX]), 3), 2);
        // 2^64 mod 3 = 1 (2^64 = 4^32 and 4 = 1 mod 3), so r = 0 (low word 0 < 1) is
        // rejected and the next word decides.
        assert_eq!(below(&mut Replay(vec![0, u64::MAX]), 3), 2);
        // n = 1: always 0, one draw, never rejected (threshold 0).
        assert_eq!(below(&mut Replay(vec![0]), 1), 0);
    }

    #[test]
    fn coin_by_hand() {
        assert!(!coin(&mut Replay(vec![0]), 0.0));
        assert!(coin(&mut Replay(vec![u64::MAX]), 1.0));
        // u = 2^52 / 2^53 = 0.5 is not below 0.5; the word just under it is.
        assert!(!coin(&mut Replay(vec![1 << 63]), 0.5));
        assert!(coin(&mut Replay(vec![(1 << 63) - (1 << 11)]), 0.5));
    }

    /// ChaCha8's block function written out (Bernstein's ChaCha with 8 rounds, 64-bit
    /// counter in words 12-13, stream in words 14-15, as `rand_chacha` documents), to pin
    /// the generator's output independently of the crate's version.
    fn chacha8_words(key: [u8; 32], n_blocks: u64) -> Vec<u32> {
        fn quarter(s: &mut [u32; 16], a: usize, b: usize, c: usize, d: usize) {
            s[a] = s[a].wrapping_add(s[b]);
            s[d] = (s[d] ^ s[a]).rotate_left(16);
            s[c] = s[c].wrapping_add(s[d]);
            s[b] = (s[b] ^ s[c]).rotate_left(12);
            s[a] = s[a].wrapping_add(s[b]);
            s[d] = (s[d] ^ s[a]).rotate_left(8);
            s[c] = s[c].wrapping_add(s[d]);
            s[b] = (s[b] ^ s[c]).rotate_left(7);
        }
        let mut out = Vec::new();
        for counter in 0..n_blocks {
            let mut input = [0u32; 16];
            input[..4].copy_from_slice(&[0x6170_7865, 0x3320_646e, 0x7962_2d32, 0x6b20_6574]);
            for (i, chunk) in key.chunks(4).enumerate() {
                input[4 + i] = u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
            }
            input[12] = counter as u32;
            input[13] = (counter >> 32) as u32;
            let mut s = input;
            for _ in 0..4 {
                quarter(&mut s, 0, 4, 8, 12);
                quarter(&mut s, 1, 5, 9, 13);
                quarter(&mut s, 2, 6, 10, 14);
                quarter(&mut s, 3, 7, 11, 15);
                quarter(&mut s, 0, 5, 10, 15);
                quarter(&mut s, 1, 6, 11, 12);
                quarter(&mut s, 2, 7, 8, 13);
                quarter(&mut s, 3, 4, 9, 14);
            }
            out.extend(s.iter().zip(input.iter()).map(|(a, b)| a.wrapping_add(*b)));
        }
        out
    }

    #[test]
    fn generator_matches_an_independent_chacha8() {
        for seed in [0u64, 1, 7, 0xDEAD_BEEF_0123_4567, u64::MAX] {
            let mut key = [0u8; 32];
            key[..8].copy_from_slice(&seed.to_le_bytes());
            // Twelve blocks: rand_chacha buffers four blocks at a time, so this crosses refills.
            let words = chacha8_words(key, 12);
            let mut rng = rng_for_seed(seed);
            for (i, pair) in words.chunks(2).enumerate() {
                let expected = u64::from(pair[0]) | (u64::from(pair[1]) << 32);
                assert_eq!(rng.next_u64(), expected, "seed {seed}, word {i}");
            }
        }
    }
}
