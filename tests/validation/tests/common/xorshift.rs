//! A tiny seeded pseudo-random generator (Marsaglia's xorshift64*) for reproducible test
//! points, without a dependency: the same seed gives the same states on every machine.

pub struct XorShift(u64);

impl XorShift {
    /// A generator from a nonzero seed (zero is a fixed point of xorshift, so it is replaced).
    pub fn new(seed: u64) -> Self {
        XorShift(if seed == 0 {
            0x9e37_79b9_7f4a_7c15
        } else {
            seed
        })
    }

    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [lo, hi): the top 53 bits as a fraction.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}
