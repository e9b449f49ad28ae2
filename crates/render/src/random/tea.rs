//! A crypto-hash generator: TEA (Wheeler & Needham 1994) reduced to 8 rounds, as Zafar,
//! Olano & Curtis (2010) found enough for image synthesis, encrypting (element index, draw
//! counter) under a key made from the seed, kernel salt and pass. Integer-only, so both
//! devices draw the same numbers bit for bit.

use super::StreamRng;

/// TEA's key schedule constant, ⌊2³² / φ⌋.
pub const DELTA: u32 = 0x9e37_79b9;
/// Rounds (pairs of Feistel half-rounds).
pub const ROUNDS: u32 = 8;
/// The fixed key words of Zafar et al.'s GPU TEA; the stream's seed, salt and pass are
/// mixed into the first three.
pub const KEY: [u32; 4] = [0xa341_316c, 0xc801_3ea4, 0xad90_777d, 0x7e95_761e];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tea {
    /// Key words 0–2 (word 3 is fixed).
    pub key: [u32; 3],
    pub index: u32,
    pub counter: u32,
}

/// TEA's encryption of (v0, v1) under key `k` in [`ROUNDS`] rounds.
pub fn encrypt(mut v0: u32, mut v1: u32, k: [u32; 4]) -> (u32, u32) {
    let mut sum = 0u32;
    for _ in 0..ROUNDS {
        sum = sum.wrapping_add(DELTA);
        v0 = v0.wrapping_add(
            (v1 << 4).wrapping_add(k[0]) ^ v1.wrapping_add(sum) ^ (v1 >> 5).wrapping_add(k[1]),
        );
        v1 = v1.wrapping_add(
            (v0 << 4).wrapping_add(k[2]) ^ v0.wrapping_add(sum) ^ (v0 >> 5).wrapping_add(k[3]),
        );
    }
    (v0, v1)
}

impl StreamRng for Tea {
    const NAME: &'static str = "tea";

    fn start(seed: u32, salt: u32, pass: u32, index: u32) -> Self {
        Tea {
            key: [KEY[0] ^ seed, KEY[1] ^ salt, KEY[2] ^ pass],
            index,
            counter: 0,
        }
    }

    /// The top 24 bits of the first cipher word.
    fn next_f32(&mut self) -> f32 {
        let k = [self.key[0], self.key[1], self.key[2], KEY[3]];
        let (v0, _) = encrypt(self.index, self.counter, k);
        self.counter = self.counter.wrapping_add(1);
        (v0 >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With 32 rounds this is the published TEA: its first test vector (all-zero key and
    /// block) must come out as 0x41ea3a0a 0x94baa940.
    #[test]
    fn encrypt_follows_tea() {
        fn full(mut v0: u32, mut v1: u32, k: [u32; 4]) -> (u32, u32) {
            let mut sum = 0u32;
            for _ in 0..32 {
                sum = sum.wrapping_add(DELTA);
                v0 = v0.wrapping_add(
                    (v1 << 4).wrapping_add(k[0])
                        ^ v1.wrapping_add(sum)
                        ^ (v1 >> 5).wrapping_add(k[1]),
                );
                v1 = v1.wrapping_add(
                    (v0 << 4).wrapping_add(k[2])
                        ^ v0.wrapping_add(sum)
                        ^ (v0 >> 5).wrapping_add(k[3]),
                );
            }
            (v0, v1)
        }
        assert_eq!(full(0, 0, [0; 4]), (0x41ea_3a0a, 0x94ba_a940));
        // The 8-round loop is the first 8 rounds of the same cipher (same body, fewer turns).
        assert_ne!(encrypt(0, 0, [0; 4]), full(0, 0, [0; 4]));
        assert_ne!(encrypt(0, 1, KEY), encrypt(0, 0, KEY));
    }
}
