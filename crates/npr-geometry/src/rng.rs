//! A tiny deterministic random number generator (xorshift64*) for seeded irregular
//! test meshes, so the crate needs no `rand` dependency.

/// xorshift64* (Vigna 2014): fast, deterministic, good enough for jitter and noise.
#[derive(Clone, Debug)]
pub struct XorShift64 {
    state: u64,
}

impl XorShift64 {
    /// A generator from any seed (0 is remapped, xorshift must not start at 0).
    pub fn new(seed: u64) -> Self {
        Self {
            state: splitmix64(seed) | 1,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[-1, 1)`.
    pub fn next_signed(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
}

/// SplitMix64 finaliser: a well-mixed hash of one `u64`, used to derive per-vertex
/// random values from an index or a position so that coincident seam vertices agree.
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform value in `[-1, 1)` determined by `(seed, key)`.
pub fn hashed_signed(seed: u64, key: u64) -> f64 {
    let h = splitmix64(splitmix64(seed) ^ key);
    2.0 * ((h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)) - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_and_in_range() {
        let mut a = XorShift64::new(7);
        let mut b = XorShift64::new(7);
        for _ in 0..1000 {
            let x = a.next_f64();
            assert_eq!(x, b.next_f64());
            assert!((0.0..1.0).contains(&x));
        }
        let s = hashed_signed(1, 2);
        assert!((-1.0..1.0).contains(&s));
        assert_eq!(s, hashed_signed(1, 2));
    }
}
