//! Running one corpus function against the reference: points, directions, the norm-wise
//! comparison, and the record of what was checked.

use super::dual::D;

/// Relative tolerance of every comparison (norm-wise, see [`Report::compare`]).
pub const REL_TOL: f64 = 1e-12;
/// Pseudo-random points per corpus function.
pub const POINTS: usize = 24;

/// xorshift64*: deterministic and dependency-free. Each function gets its own stream (seeded
/// from its name), so adding a function to the corpus does not move the others' points.
pub struct Rng(u64);

impl Rng {
    pub fn for_name(name: &str) -> Self {
        // FNV-1a of the name; never zero, which xorshift could not leave.
        let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
        Rng(hash | 1)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    pub fn vector(&mut self, len: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..len).map(|_| self.uniform(lo, hi)).collect()
    }
}

/// A function of the point x (flat).
pub type AtPoint = fn(&[f64]) -> Vec<f64>;
/// A function of x and one more vector (a direction or the weights).
pub type AtPointWith = fn(&[f64], &[f64]) -> Vec<f64>;
/// A function of x and two directions.
pub type AtPointWith2 = fn(&[f64], &[f64], &[f64]) -> Vec<f64>;

/// One corpus function with its generated companions, all over flat vectors. The closures
/// are written by the `case!` macro of the test.
pub struct Case {
    pub name: &'static str,
    /// Number of inputs N (the flattened arguments).
    pub n: usize,
    /// Every input is drawn uniformly from this interval.
    pub domain: (f64, f64),
    /// The user's function as rustc compiled it.
    pub original: AtPoint,
    /// `f_generic::<f64>`: the engine's lowering, emitted back to Rust.
    pub generic_f64: AtPoint,
    /// `f_generic::<D>`: the engine's lowering, differentiated by num-dual.
    pub generic_dual: fn(&[D]) -> Vec<D>,
    /// `f_tangent(x, dir)`.
    pub tangent: AtPointWith,
    /// `f_gradient(x)`, or `f_adjoint(x, weights)` for vector results.
    pub gradient: AtPointWith,
    /// `f_jacobian(x)`, row-major M×N.
    pub jacobian: AtPoint,
    /// `f_hessian(x)`, or `f_hessian(x, weights)` for vector results; N×N.
    pub hessian: AtPointWith,
    /// `f_second(x, dir_u, dir_v)`.
    pub second: AtPointWith2,
}

/// What was compared, and what disagreed.
#[derive(Default)]
pub struct Report {
    /// Number of objects compared (a value, a gradient, a Jacobian...).
    pub objects: usize,
    /// Number of entries compared.
    pub entries: usize,
    pub failures: Vec<String>,
    /// How often directions were redrawn because they were ill-conditioned.
    pub redrawn: usize,
}

impl Report {
    /// Norm-wise relative comparison of a derivative object (vector or matrix, flattened):
    /// every entry must satisfy |o − r| ≤ REL_TOL · max(|r|, maxₖ |rₖ|), so an entry that
    /// is ~0 through cancellation is judged against the object's scale. A NaN anywhere fails.
    pub fn compare(
        &mut self,
        case: &str,
        point: usize,
        what: &str,
        ours: &[f64],
        reference: &[f64],
    ) {
        self.objects += 1;
        self.entries += reference.len();
        if ours.len() != reference.len() {
            self.failures.push(format!(
                "{case} point {point} {what}: {} entries, reference has {}",
                ours.len(),
                reference.len()
            ));
            return;
        }
        let scale = reference.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
        for (k, (&o, &r)) in ours.iter().zip(reference).enumerate() {
            let tolerance = REL_TOL * r.abs().max(scale);
            let error = (o - r).abs();
            let within = error <= tolerance; // false if either is NaN
            if !within {
                self.failures.push(format!(
                    "{case} point {point} {what}[{k}]: ours {o:e}, reference {r:e}, error {error:.3e} > tolerance {tolerance:.3e}"
                ));
            }
        }
    }
}

/// Seed ε₁ with `e1`, ε₂ with `e2` and evaluate the engine's lowering over hyper-duals.
fn dual_eval(case: &Case, x: &[f64], e1: &[f64], e2: &[f64]) -> Vec<D> {
    let xs: Vec<D> = (0..x.len())
        .map(|i| D::seeded(x[i], e1[i], e2[i]))
        .collect();
    (case.generic_dual)(&xs)
}

fn unit(n: usize, i: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[i] = 1.0;
    e
}

/// The reference derivatives of F at a point along the unit directions.
struct UnitDerivatives {
    n: usize,
    m: usize,
    /// ∂Fᵢ/∂xⱼ at `[i * n + j]`.
    jacobian: Vec<f64>,
    /// ∂²Fₖ/∂xᵢ∂xⱼ at `[(k * n + i) * n + j]`.
    hessians: Vec<f64>,
}

impl UnitDerivatives {
    fn at(case: &Case, x: &[f64], m: usize) -> Self {
        let n = x.len();
        let zero = vec![0.0; n];
        let mut jacobian = vec![0.0; m * n];
        for j in 0..n {
            for (i, y) in dual_eval(case, x, &unit(n, j), &zero).iter().enumerate() {
                jacobian[i * n + j] = y.eps1();
            }
        }
        let mut hessians = vec![0.0; m * n * n];
        for i in 0..n {
            for j in 0..n {
                for (k, y) in dual_eval(case, x, &unit(n, i), &unit(n, j))
                    .iter()
                    .enumerate()
                {
                    hessians[(k * n + i) * n + j] = y.eps1eps2();
                }
            }
        }
        UnitDerivatives {
            n,
            m,
            jacobian,
            hessians,
        }
    }

    /// wᵀF', the reference gradient (M = 1) or adjoint.
    fn adjoint(&self, w: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|j| {
                (0..self.m)
                    .map(|i| w[i] * self.jacobian[i * self.n + j])
                    .sum()
            })
            .collect()
    }

    /// ∇²(wᵀF), the reference Hessian.
    fn hessian(&self, w: &[f64]) -> Vec<f64> {
        let nn = self.n * self.n;
        (0..nn)
            .map(|ij| (0..self.m).map(|k| w[k] * self.hessians[k * nn + ij]).sum())
            .collect()
    }

    /// How ill-conditioned the contractions with these directions and weights are: the
    /// largest of the condition numbers of F'·u, F''[u, v], wᵀF' and ∇²(wᵀF) (each taken
    /// norm-wise, as the comparison is).
    fn condition(&self, u: &[f64], v: &[f64], w: &[f64]) -> f64 {
        let (n, m, nn) = (self.n, self.m, self.n * self.n);
        let tangent = (0..m).map(|i| (0..n).map(move |j| self.jacobian[i * n + j] * u[j]));
        let second = (0..m)
            .map(|k| (0..nn).map(move |ij| u[ij / n] * self.hessians[k * nn + ij] * v[ij % n]));
        let adjoint = (0..n).map(|j| (0..m).map(move |i| w[i] * self.jacobian[i * n + j]));
        let hessian = (0..nn).map(|ij| (0..m).map(move |k| w[k] * self.hessians[k * nn + ij]));
        condition(tangent)
            .max(condition(second))
            .max(condition(adjoint))
            .max(condition(hessian))
    }
}

/// Condition number of an object whose entries are sums: max Σ|terms| over max |Σ terms|
/// (1 for an object that is exactly zero).
fn condition<I: Iterator<Item = f64>>(entries: impl Iterator<Item = I>) -> f64 {
    let (mut magnitude, mut value) = (0.0_f64, 0.0_f64);
    for terms in entries {
        let (sum, abs) = terms.fold((0.0, 0.0), |(s, a), t| (s + t, a + t.abs()));
        magnitude = magnitude.max(abs);
        value = value.max(sum.abs());
    }
    if magnitude == 0.0 {
        1.0
    } else {
        magnitude / value
    }
}

/// Directions are redrawn while a contraction would lose more than two digits to
/// cancellation: there the references' own rounding (about κ·ε) approaches the tolerance,
/// and the comparison would judge the rounding luck of two correct implementations.
pub const MAX_CONDITION: f64 = 100.0;

/// Check one function at `POINTS` points; returns the points used.
pub fn run_case(case: &Case, report: &mut Report) -> Vec<Vec<f64>> {
    let mut rng = Rng::for_name(case.name);
    let n = case.n;
    let mut points = Vec::new();
    for p in 0..POINTS {
        let x = rng.vector(n, case.domain.0, case.domain.1);

        // The value: the engine's lowering against rustc's compilation of the same source.
        let value = (case.original)(&x);
        let m = value.len();
        report.compare(case.name, p, "value", &(case.generic_f64)(&x), &value);

        // Directions u, v and weights w (all ones for M = 1), well conditioned.
        let reference = UnitDerivatives::at(case, &x, m);
        let mut draw = || {
            let u = rng.vector(n, -1.0, 1.0);
            let v = rng.vector(n, -1.0, 1.0);
            let w = if m == 1 {
                vec![1.0]
            } else {
                rng.vector(m, -1.0, 1.0)
            };
            (u, v, w)
        };
        let mut redrawn = 0;
        let (u, v, w) = loop {
            let (u, v, w) = draw();
            if reference.condition(&u, &v, &w) <= MAX_CONDITION {
                break (u, v, w);
            }
            redrawn += 1;
            assert!(
                redrawn < 1000,
                "{} point {p}: no well-conditioned directions",
                case.name
            );
        };
        report.redrawn += redrawn;

        // The references: tangent and second from their own hyper-dual evaluation, seeded
        // with the directions; gradient, Jacobian and Hessian from the unit directions.
        let zero = vec![0.0; n];
        let tangent: Vec<f64> = dual_eval(case, &x, &u, &zero)
            .iter()
            .map(|d| d.eps1())
            .collect();
        let second: Vec<f64> = dual_eval(case, &x, &u, &v)
            .iter()
            .map(|d| d.eps1eps2())
            .collect();

        report.compare(case.name, p, "tangent", &(case.tangent)(&x, &u), &tangent);
        let what = if m == 1 { "gradient" } else { "adjoint" };
        report.compare(
            case.name,
            p,
            what,
            &(case.gradient)(&x, &w),
            &reference.adjoint(&w),
        );
        report.compare(
            case.name,
            p,
            "jacobian",
            &(case.jacobian)(&x),
            &reference.jacobian,
        );
        report.compare(
            case.name,
            p,
            "hessian",
            &(case.hessian)(&x, &w),
            &reference.hessian(&w),
        );
        report.compare(case.name, p, "second", &(case.second)(&x, &u, &v), &second);
        points.push(x);
    }
    points
}
