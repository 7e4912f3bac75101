//! Chaotic maps that replace PSO's uniform random coefficients, and the seeded generator
//! that starts them.
//!
//! A chaotic sequence `z_{k+1} = f(z_k)` on `(0, 1)` is deterministic once `z_0` is
//! chosen; `z_0` comes from the seeded ChaCha8 generator. In floating point an orbit can
//! collapse onto a fixed point or the interval's ends (the logistic map reaches 0 from
//! 0.5, the tent map's doubling form loses a bit per step), so a value outside
//! `[EDGE, 1 - EDGE]`, or equal to its predecessor, is replaced by a fresh draw from the
//! generator and counted as a reseed.

use rand_chacha::rand_core::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Chaotic values closer than this to 0 or 1 are replaced by a fresh draw.
pub const EDGE: f64 = 1e-10;

/// The chaotic map of the sequence (config key `chaotic_map`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum ChaoticMap {
    /// `z' = 4 z (1 - z)`. Config value `"logistic"`.
    #[default]
    Logistic,
    /// `z' = z / 0.7` below 0.7, else `(10 / 3) (1 - z)` (the tent map in the form of
    /// Gandomi et al.'s chaotic optimisation studies). Config value `"tent"`.
    Tent,
    /// `z' = sin(pi z)`. Config value `"sine"`.
    Sine,
    /// `z' = 2.3 z^2 sin(pi z)`. Config value `"sinusoidal"`.
    Sinusoidal,
    /// `z' = (z + 0.2 - (0.5 / (2 pi)) sin(2 pi z)) mod 1`. Config value `"circle"`.
    Circle,
    /// The Gauss (mouse) map `z' = (1 / z) mod 1`. Config value `"gauss"`.
    Gauss,
}

impl ChaoticMap {
    /// Every map, in declaration order.
    pub const ALL: [ChaoticMap; 6] = [
        ChaoticMap::Logistic,
        ChaoticMap::Tent,
        ChaoticMap::Sine,
        ChaoticMap::Sinusoidal,
        ChaoticMap::Circle,
        ChaoticMap::Gauss,
    ];

    /// One step of the map (values outside `(0, 1)` may come out; see [`Chaos::next`]).
    #[inline]
    pub fn step(self, z: f64) -> f64 {
        use std::f64::consts::PI;
        match self {
            ChaoticMap::Logistic => 4.0 * z * (1.0 - z),
            ChaoticMap::Tent => {
                if z < 0.7 {
                    z / 0.7
                } else {
                    10.0 / 3.0 * (1.0 - z)
                }
            }
            ChaoticMap::Sine => (PI * z).sin(),
            ChaoticMap::Sinusoidal => 2.3 * z * z * (PI * z).sin(),
            ChaoticMap::Circle => {
                (z + 0.2 - 0.5 / (2.0 * PI) * (2.0 * PI * z).sin()).rem_euclid(1.0)
            }
            ChaoticMap::Gauss => (1.0 / z).rem_euclid(1.0),
        }
    }
}

/// The generator for `seed`: ChaCha8 with the 32-byte key `seed.to_le_bytes()` followed by
/// 24 zero bytes (spelled out, as in planner-rrt, so that no `rand` seed expansion is
/// involved).
pub fn rng_for_seed(seed: u64) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    ChaCha8Rng::from_seed(key)
}

/// A uniform value in `[0, 1)`: the top 53 bits of one 64-bit draw as `k / 2^53`.
pub fn unit(rng: &mut impl RngCore) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform value in `[EDGE, 1 - EDGE]`, redrawn until it is.
fn interior(rng: &mut impl RngCore) -> f64 {
    loop {
        let u = unit(rng);
        if (EDGE..=1.0 - EDGE).contains(&u) {
            return u;
        }
    }
}

/// A chaotic sequence with its reseeding generator.
#[derive(Debug, Clone)]
pub struct Chaos {
    map: ChaoticMap,
    z: f64,
    /// How many values were replaced by a fresh draw.
    pub n_reseeds: u64,
}

impl Chaos {
    /// A sequence of `map` whose start value is drawn from `rng`.
    pub fn new(map: ChaoticMap, rng: &mut impl RngCore) -> Chaos {
        Chaos {
            map,
            z: interior(rng),
            n_reseeds: 0,
        }
    }

    /// The next value in `[EDGE, 1 - EDGE]`.
    #[inline]
    pub fn next(&mut self, rng: &mut impl RngCore) -> f64 {
        let z = self.map.step(self.z);
        self.z = if (EDGE..=1.0 - EDGE).contains(&z) && z != self.z {
            z
        } else {
            self.n_reseeds += 1;
            interior(rng)
        };
        self.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_by_hand() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(ChaoticMap::Logistic.step(0.2), 0.64));
        assert!(close(ChaoticMap::Tent.step(0.35), 0.5));
        assert!(close(ChaoticMap::Tent.step(0.85), 0.5));
        assert!(close(ChaoticMap::Sine.step(0.5), 1.0));
        assert!(close(ChaoticMap::Sinusoidal.step(0.5), 0.575));
        assert!(close(ChaoticMap::Circle.step(0.5), 0.7));
        assert!(close(ChaoticMap::Gauss.step(0.3), 1.0 / 0.3 - 3.0));
    }

    #[test]
    fn sequences_stay_inside_and_are_reproducible() {
        for map in ChaoticMap::ALL {
            let run = || {
                let mut rng = rng_for_seed(11);
                let mut chaos = Chaos::new(map, &mut rng);
                let values: Vec<f64> = (0..10_000).map(|_| chaos.next(&mut rng)).collect();
                (values, chaos.n_reseeds)
            };
            let (values, n_reseeds) = run();
            assert_eq!(run(), (values.clone(), n_reseeds), "{map:?}");
            assert!(values.iter().all(|v| (EDGE..=1.0 - EDGE).contains(v)));
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            assert!((0.15..0.85).contains(&mean), "{map:?}: mean {mean}");
        }
        // The logistic map from 0.5 reaches 1 and then 0: both replaced.
        let mut rng = rng_for_seed(0);
        let mut chaos = Chaos {
            map: ChaoticMap::Logistic,
            z: 0.5,
            n_reseeds: 0,
        };
        let v = chaos.next(&mut rng);
        assert_eq!(chaos.n_reseeds, 1);
        assert!((EDGE..=1.0 - EDGE).contains(&v));
    }
}
