//! The talk's float-only generator (`GPURnd`, Hachisuka 2015, slide "Random number
//! generator"; of "unknown origin" by the talk's own account): four multiplicative
//! congruential generators modulo primes near 2²², each stepped with Schrage's method so every
//! product stays below 2²⁴ and is exact in f32, combined by an alternating sum of the four
//! states over their moduli. The constants are the slide's.
//!
//! Exactness: the states are integers below 2²² held in f32, and every step below is exact in
//! f32 on any device except the quotient `floor(s / q)`: WGSL's division is only good to
//! 2.5 ULP, so the quotient is corrected by one either way from its exact remainder. The state
//! sequence is therefore the same on the GPU and the CPU; the output sums four products with
//! rounding, so GPU draws may differ from these in the last bits (twin tests use a tolerance).

use super::{ONE_BELOW, StreamRng};
use crate::rng::stream_key;
use bvh::bench_rays::pcg_hash;

/// The slide's constants: q = m div a, r = m mod a (Schrage), multipliers a, moduli m.
pub const Q: [f32; 4] = [1225.0, 1585.0, 2457.0, 2098.0];
pub const R: [f32; 4] = [1112.0, 367.0, 92.0, 265.0];
pub const A: [f32; 4] = [3423.0, 2646.0, 1707.0, 1999.0];
pub const M: [f32; 4] = [4_194_287.0, 4_194_277.0, 4_194_191.0, 4_194_167.0];
/// 1 / m rounded to f32: the output multiplies by these (the same constant on both devices,
/// where a division would round differently).
pub const INV_M: [f32; 4] = [1.0 / M[0], 1.0 / M[1], 1.0 / M[2], 1.0 / M[3]];

/// Four lanes of state, each an integer in [1, m − 1] held in f32.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TalkFloat {
    pub state: [f32; 4],
}

/// One Schrage step of lane `i`: `a · s mod m`, exact in f32.
pub fn step_lane(s: f32, i: usize) -> f32 {
    let (q, r, a, m) = (Q[i], R[i], A[i], M[i]);
    let mut beta = (s / q).floor();
    // The remainder is exact (integers below 2²⁴), so it says which way a rounded quotient
    // is off.
    let rem = s - beta * q;
    if rem < 0.0 {
        beta -= 1.0;
    } else if rem >= q {
        beta += 1.0;
    }
    let p = a * (s - beta * q) - beta * r;
    // The slide's `(sign(-p) + 1) / 2 · m` adds m when p < 0; p is never 0 (m is prime).
    if p < 0.0 { p + m } else { p }
}

impl StreamRng for TalkFloat {
    const NAME: &'static str = "talk";

    /// Each lane starts from the stream's PCG key hashed once more per lane, reduced to
    /// [1, m − 1] (0 is the generator's fixed point), so neighbouring streams start far apart.
    fn start(seed: u32, salt: u32, pass: u32, index: u32) -> Self {
        let key = stream_key(seed, salt, pass, index);
        let state = [0u32, 1, 2, 3].map(|i| {
            let m = M[i as usize] as u32;
            (1 + pcg_hash(key.wrapping_add(i)) % (m - 1)) as f32
        });
        TalkFloat { state }
    }

    fn next_f32(&mut self) -> f32 {
        for i in 0..4 {
            self.state[i] = step_lane(self.state[i], i);
        }
        let s = self.state;
        let x = s[0] * INV_M[0] - s[1] * INV_M[1] + s[2] * INV_M[2] - s[3] * INV_M[3];
        (x - x.floor()).min(ONE_BELOW)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Schrage's step equals the integer product modulo m for states across the range.
    #[test]
    fn step_lane_is_exact_modular_multiplication() {
        for i in 0..4 {
            let m = M[i] as u64;
            for s in (1..m)
                .step_by(997)
                .chain([1, m - 1, Q[i] as u64, Q[i] as u64 - 1])
            {
                let expected = (A[i] as u64 * s) % m;
                assert_eq!(step_lane(s as f32, i) as u64, expected, "lane {i}, s = {s}");
            }
        }
    }

    #[test]
    fn streams_start_inside_the_range_and_differ() {
        let a = TalkFloat::start(1, 2, 3, 4);
        let b = TalkFloat::start(1, 2, 3, 5);
        assert_ne!(a, b);
        for rng in [a, b] {
            for (s, m) in rng.state.iter().zip(M) {
                assert!(*s >= 1.0 && *s < m && s.fract() == 0.0);
            }
        }
    }
}
