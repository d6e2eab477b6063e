//! A small seeded PRNG (xorshift64*) so every simulated noise sample is
//! reproducible from the scenario's seed. The one seeded generator of the
//! workspace: hal-sim's tests draw their random sequences from it too (the
//! core crate's tests use proptest's).

#[derive(Debug, Clone)]
/// The generator: xorshift64* state, never zero.
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A generator whose sequence follows from `seed` alone (any seed, 0 included).
    pub fn new(seed: u64) -> Self {
        // A zero state would stay zero; splitmix the seed into a non-zero one.
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        Rng { state: if z == 0 { 1 } else { z } }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// Uniform integer in 0..n (n > 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }
}
