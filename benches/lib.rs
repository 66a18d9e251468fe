//! hamel's benchmarks (`cargo bench -p hamel-benches`): `rhs.rs` times the generated
//! right-hand side against a hand-written closed form (criterion, for trends), `speed.rs`
//! gives the figures of record for the same comparison and for the N-trailer (interleaved),
//! `linearize.rs` the cost of a Jacobian, `expand.rs` the macro's expansion, `long_runs.rs`
//! the integrators over long spans and on a stiff system (figures of record in the file).
//!
//! This library holds what the benchmarks share: the interleaved timing ([`interleave`]) and
//! the seeded samples ([`Uniform`], [`robot_samples`]).

pub mod interleave {
    //! Timing by interleaved batches: short batches (about [`BATCH_SECONDS`]) of each variant
    //! alternate, round after round, and every figure is taken per round — a ratio of two
    //! variants' times in the same round — before the median over the rounds, with the 10th
    //! and 90th percentiles beside it. The machine's speed drifts (frequency, other load) on
    //! a scale longer than a round, so it cancels from the per-round ratios.
    //!
    //! The number of rounds is [`rounds`]: 201, or `HAMEL_BENCH_ROUNDS` for a quick run.

    use std::time::Instant;

    /// Rounds of interleaved batches, unless `HAMEL_BENCH_ROUNDS` says otherwise.
    pub const ROUNDS: usize = 201;
    /// Seconds a batch should take, about.
    pub const BATCH_SECONDS: f64 = 1e-3;

    /// The number of rounds: `HAMEL_BENCH_ROUNDS` if set (at least 1), else [`ROUNDS`].
    pub fn rounds() -> usize {
        match std::env::var("HAMEL_BENCH_ROUNDS") {
            Ok(text) => match text.trim().parse::<usize>() {
                Ok(n) if n > 0 => n,
                _ => panic!("HAMEL_BENCH_ROUNDS must be a positive integer, not {text:?}"),
            },
            Err(_) => ROUNDS,
        }
    }

    /// Mean seconds per call of `f` over a batch of `calls`.
    pub fn batch(calls: usize, f: &mut dyn FnMut()) -> f64 {
        let start = Instant::now();
        for _ in 0..calls {
            f();
        }
        start.elapsed().as_secs_f64() / calls as f64
    }

    /// How many calls of `f` take about [`BATCH_SECONDS`] (after a warm-up batch).
    pub fn calibrate(f: &mut dyn FnMut()) -> usize {
        calibrate_to(f, BATCH_SECONDS)
    }

    /// How many calls of `f` take about `seconds` (after a warm-up batch).
    pub fn calibrate_to(f: &mut dyn FnMut(), seconds: f64) -> usize {
        batch(10, f);
        let once = batch(100, f).max(1e-9);
        ((seconds / once) as usize).max(1)
    }

    /// The median and the 10th and 90th percentiles of a sample.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Spread {
        /// the median
        pub median: f64,
        /// the 10th percentile
        pub p10: f64,
        /// the 90th percentile
        pub p90: f64,
    }

    impl Spread {
        /// The spread of `values` (not empty); NaNs sort last.
        pub fn of(values: &[f64]) -> Spread {
            assert!(!values.is_empty(), "the spread of no values");
            let mut sorted = values.to_vec();
            sorted.sort_by(f64::total_cmp);
            let at = |p: f64| sorted[((sorted.len() - 1) as f64 * p).round() as usize];
            Spread {
                median: at(0.5),
                p10: at(0.1),
                p90: at(0.9),
            }
        }

        /// Each figure multiplied by `factor` (for units).
        pub fn scaled(self, factor: f64) -> Spread {
            Spread {
                median: self.median * factor,
                p10: self.p10 * factor,
                p90: self.p90 * factor,
            }
        }
    }

    /// Seconds per call of each variant, round by round: `result[round][variant]`. Each round
    /// runs one batch of every variant, round-robin, the first variant of a round moving on by
    /// one each round (so that none always runs first, or after the same neighbour).
    pub fn round_robin(variants: &mut [&mut dyn FnMut()]) -> Vec<Vec<f64>> {
        round_robin_batches(variants, BATCH_SECONDS)
    }

    /// [`round_robin`] with batches of about `batch_seconds`: longer ones for variants that
    /// take a millisecond or more a call, so that one interruption does not make a round.
    pub fn round_robin_batches(
        variants: &mut [&mut dyn FnMut()],
        batch_seconds: f64,
    ) -> Vec<Vec<f64>> {
        let calls: Vec<usize> = variants
            .iter_mut()
            .map(|f| calibrate_to(*f, batch_seconds))
            .collect();
        let k = variants.len();
        (0..rounds())
            .map(|round| {
                let mut seconds = vec![0.0; k];
                for j in 0..k {
                    let v = (round + j) % k;
                    seconds[v] = batch(calls[v], variants[v]);
                }
                seconds
            })
            .collect()
    }

    /// The per-round ratio of variant `a`'s time to variant `b`'s, from [`round_robin`]'s
    /// result.
    pub fn ratio(rounds: &[Vec<f64>], a: usize, b: usize) -> Spread {
        let ratios: Vec<f64> = rounds.iter().map(|r| r[a] / r[b]).collect();
        Spread::of(&ratios)
    }

    /// Variant `v`'s seconds per call over the rounds, from [`round_robin`]'s result.
    pub fn seconds(rounds: &[Vec<f64>], v: usize) -> Spread {
        let seconds: Vec<f64> = rounds.iter().map(|r| r[v]).collect();
        Spread::of(&seconds)
    }

    /// Two variants interleaved: the spread of the per-round ratio a/b, and b's median
    /// seconds per call.
    pub fn interleaved(a: &mut dyn FnMut(), b: &mut dyn FnMut()) -> (Spread, f64) {
        let rounds = round_robin(&mut [a, b]);
        (ratio(&rounds, 0, 1), seconds(&rounds, 1).median)
    }

    /// The least-squares slope of `y` against `x` (at least two distinct `x`).
    pub fn slope(x: &[f64], y: &[f64]) -> f64 {
        assert_eq!(x.len(), y.len());
        let n = x.len() as f64;
        let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
        let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
        let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
        sxy / sxx
    }
}

/// Seeded uniform numbers in [−1, 1) (xorshift64*), the same in every run.
pub struct Uniform(u64);

impl Uniform {
    /// A generator from a nonzero seed.
    pub fn new(seed: u64) -> Uniform {
        assert_ne!(seed, 0);
        Uniform(seed)
    }

    /// The next number, in [−1, 1).
    pub fn sample(&mut self) -> f64 {
        let s = &mut self.0;
        *s ^= *s >> 12;
        *s ^= *s << 25;
        *s ^= *s >> 27;
        let bits = s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        (bits as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// The robot benchmarks' 64 seeded states (each component in [−3, 3)) and inputs (in
/// [−1, 1)), the same in every run and in every benchmark.
pub fn robot_samples() -> Vec<([f64; 8], [f64; 2])> {
    let mut rng = Uniform::new(0x9E37_79B9_7F4A_7C15);
    (0..64)
        .map(|_| {
            let x = std::array::from_fn(|_| 3.0 * rng.sample());
            (x, [rng.sample(), rng.sample()])
        })
        .collect()
}
