//! The coefficients of the Rosenbrock methods of the Rodas family, in the form of
//! OrdinaryDiffEq.jl's implementation (`OrdinaryDiffEqRosenbrock`, `Rodas4Tableau`,
//! `Rodas5PTableau`), whose digits are copied here:
//!
//! - Rodas5P: G. Steinebach, "Construction of Rosenbrock–Wanner method Rodas5P and numerical
//!   benchmarks within the Julia Differential Equations package", *BIT Numerical Mathematics*
//!   63, 27 (2023): order 5, embedded order 4, stiffly accurate, with a dense output of order 4.
//! - Rodas4: Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., IV.7
//!   (their code RODAS): order 4, embedded order 3, with a dense output of order 3.
//!
//! A step of size h from (t, y) with W = I/(hγ) − J solves, stage after stage,
//!
//! W kᵢ = f(t + cᵢh, y + Σⱼ aᵢⱼ kⱼ) + h dᵢ ∂f/∂t + Σⱼ (Cᵢⱼ/h) kⱼ  (j < i),
//!
//! and y₁ = y + Σ bⱼ kⱼ. The last stages are at t + h and each adds the last increment to the
//! stage before (aᵢ = aᵢ₋₁ + eᵢ₋₁, and b = a_s + e_s): the method is stiffly accurate, and its
//! last increment k_s is the difference between y₁ and the embedded solution, the error
//! estimate. The dense output is u(t + θh) = (1 − θ) y + θ (y₁ + (1 − θ)(K₁ + θ(K₂ + θK₃)))
//! with Kₘ = Σⱼ Hₘⱼ kⱼ (Rodas4: K₃ = 0).

/// A Rosenbrock method with `S` stages and `K` dense-output coefficients.
#[derive(Clone, Debug)]
pub(crate) struct RosenbrockTableau<const S: usize, const K: usize> {
    /// The diagonal γ: W = I/(hγ) − J.
    pub gamma: f64,
    /// Stage i is evaluated at y + Σⱼ aᵢⱼ kⱼ, j < i.
    pub a: [[f64; S]; S],
    /// ... at t + cᵢ h.
    pub c: [f64; S],
    /// The coefficients of h ∂f/∂t.
    pub d: [f64; S],
    /// The coupling Cᵢⱼ of the increments (divided by h where used), j < i.
    pub coupling: [[f64; S]; S],
    /// y₁ = y + Σ bⱼ kⱼ.
    pub b: [f64; S],
    /// The dense output's Kₘ = Σⱼ Hₘⱼ kⱼ.
    pub dense: [[f64; S]; K],
    /// The order of the embedded solution: the error estimate is O(h^(order + 1)), so the step
    /// scales as its (order + 1)-th root.
    pub estimate_order: f64,
}

/// Lower-triangular rows from their given entries (row i has i of them).
fn lower<const S: usize>(rows: &[&[f64]]) -> [[f64; S]; S] {
    let mut m = [[0.0; S]; S];
    for (i, row) in rows.iter().enumerate() {
        m[i + 1][..row.len()].copy_from_slice(row);
    }
    m
}

impl<const S: usize, const K: usize> RosenbrockTableau<S, K> {
    /// Completes the rows of the stages from `given` on (they add the previous increment to
    /// the previous stage) and b (the last stage plus its increment).
    fn accumulate(mut a: [[f64; S]; S], given: usize) -> ([[f64; S]; S], [f64; S]) {
        for i in given..S {
            a[i] = a[i - 1];
            a[i][i - 1] += 1.0;
        }
        let mut b = a[S - 1];
        b[S - 1] += 1.0;
        (a, b)
    }
}

impl RosenbrockTableau<8, 3> {
    /// Rodas5P (Steinebach 2023), as in OrdinaryDiffEq.jl.
    #[allow(clippy::excessive_precision)]
    pub fn rodas5p() -> Self {
        let a = lower::<8>(&[
            &[3.0],
            &[2.849394379747939, 0.45842242204463923],
            &[-6.954028509809101, 2.489845061869568, -10.358996098473584],
            &[
                2.8029986275628964,
                0.5072464736228206,
                -0.3988312541770524,
                -0.04721187230404641,
            ],
            &[
                -7.502846399306121,
                2.561846144803919,
                -11.627539656261098,
                -0.18268767659942256,
                0.030198172008377946,
            ],
        ]);
        let (a, b) = Self::accumulate(a, 6);
        let coupling = lower::<8>(&[
            &[-14.155112264123755],
            &[-17.97296035885952, -2.859693295451294],
            &[147.12150275711716, -1.41221402718213, 71.68940251302358],
            &[
                165.43517024871676,
                -0.4592823456491126,
                42.90938336958603,
                -5.961986721573306,
            ],
            &[
                24.854864614690072,
                -3.0009227002832186,
                47.4931110020768,
                5.5814197821558125,
                -0.6610691825249471,
            ],
            &[
                30.91273214028599,
                -3.1208243349937974,
                77.79954646070892,
                34.28646028294783,
                -19.097331116725623,
                -28.087943162872662,
            ],
            &[
                37.80277123390563,
                -3.2571969029072276,
                112.26918849496327,
                66.9347231244047,
                -40.06618937091002,
                -54.66780262877968,
                -9.48861652309627,
            ],
        ]);
        RosenbrockTableau {
            gamma: 0.21193756319429014,
            a,
            c: [
                0.0,
                0.6358126895828704,
                0.4095798393397535,
                0.9769306725060716,
                0.4288403609558664,
                1.0,
                1.0,
                1.0,
            ],
            d: [
                0.21193756319429014,
                -0.42387512638858027,
                -0.3384627126235924,
                1.8046452872882734,
                2.325825639765069,
                0.0,
                0.0,
                0.0,
            ],
            coupling,
            b,
            dense: [
                [
                    25.948786856663858,
                    -2.5579724845846235,
                    10.433815404888879,
                    -2.3679251022685204,
                    0.524948541321073,
                    1.1241088310450404,
                    0.4272876194431874,
                    -0.17202221070155493,
                ],
                [
                    -9.91568850695171,
                    -0.9689944594115154,
                    3.0438037242978453,
                    -24.495224566215796,
                    20.176138334709044,
                    15.98066361424651,
                    -6.789040303419874,
                    -6.710236069923372,
                ],
                [
                    11.419903575922262,
                    2.8879645146136994,
                    72.92137995996029,
                    80.12511834622643,
                    -52.072871366152654,
                    -59.78993625266729,
                    -0.15582684282751913,
                    4.883087185713722,
                ],
            ],
            estimate_order: 4.0,
        }
    }
}

impl RosenbrockTableau<6, 3> {
    /// Rodas4 (Hairer & Wanner's RODAS), as in OrdinaryDiffEq.jl; its dense output has two
    /// coefficients (the third row is zero).
    #[allow(clippy::excessive_precision)]
    pub fn rodas4() -> Self {
        let a = lower::<6>(&[
            &[1.544000000000000],
            &[0.9466785280815826, 0.2557011698983284],
            &[3.314825187068521, 2.896124015972201, 0.9986419139977817],
            &[
                1.221224509226641,
                6.019134481288629,
                12.53708332932087,
                -0.6878860361058950,
            ],
        ]);
        let (a, b) = Self::accumulate(a, 5);
        let coupling = lower::<6>(&[
            &[-5.668800000000000],
            &[-2.430093356833875, -0.2063599157091915],
            &[-0.1073529058151375, -9.594562251023355, -20.47028614809616],
            &[
                7.496443313967647,
                -10.24680431464352,
                -33.99990352819905,
                11.70890893206160,
            ],
            &[
                8.083246795921522,
                -7.981132988064893,
                -31.52159432874371,
                16.31930543123136,
                -6.058818238834054,
            ],
        ]);
        RosenbrockTableau {
            gamma: 0.25,
            a,
            c: [0.0, 0.386, 0.21, 0.63, 1.0, 1.0],
            d: [0.25, -0.1043, 0.1035, -0.03620000000000023, 0.0, 0.0],
            coupling,
            b,
            dense: [
                [
                    10.12623508344586,
                    -7.487995877610167,
                    -34.80091861555747,
                    -7.992771707568823,
                    1.025137723295662,
                    0.0,
                ],
                [
                    -0.6762803392801253,
                    6.087714651680015,
                    16.43084320892478,
                    24.76722511418386,
                    -6.594389125716872,
                    0.0,
                ],
                [0.0; 6],
            ],
            estimate_order: 3.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The classical order conditions of a Rosenbrock method in the form W kᵢ = f(…) +
    /// Σ (Cᵢⱼ/h) kⱼ (Hairer & Wanner II, IV.7): with the coefficients of the standard form,
    /// αᵢⱼ = aᵢⱼ and γᵢⱼ from C and γ, b = m. Checked here: the first few for the whole
    /// method, which the tables below satisfy to rounding, and consistency of d with γᵢ.
    fn check<const S: usize, const K: usize>(t: &RosenbrockTableau<S, K>, order: u32) {
        // Back to the standard form (Hairer & Wanner's transformation): Γ = (γ I − C·γ)⁻¹·γ…
        // done numerically: with C = I/γ − Γ⁻¹ and A = α Γ⁻¹, Γ lower triangular with γ on
        // its diagonal.
        let n = S;
        let gamma_inv = nalgebra::DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                1.0 / t.gamma
            } else {
                -t.coupling[i][j]
            }
        });
        let big_gamma = gamma_inv.try_inverse().expect("Γ⁻¹ is invertible");
        let a = nalgebra::DMatrix::from_fn(n, n, |i, j| t.a[i][j]);
        let alpha = &a * &big_gamma;
        let b = nalgebra::DVector::from_fn(n, |i, _| t.b[i]);
        let m = big_gamma.transpose() * &b;
        // β = α + Γ (Hairer & Wanner's βᵢⱼ), sums αᵢ = Σⱼ αᵢⱼ, βᵢ' = Σⱼ<ᵢ βᵢⱼ.
        let beta = &alpha + &big_gamma;
        let alpha_i: Vec<f64> = (0..n).map(|i| alpha.row(i).sum()).collect();
        let beta_p: Vec<f64> = (0..n).map(|i| (0..i).map(|j| beta[(i, j)]).sum()).collect();
        let tol = 1e-9;
        // Order 1: Σ bᵢ = 1.
        assert!((m.sum() - 1.0).abs() < tol, "order 1: {}", m.sum());
        // Order 2: Σ bᵢ βᵢ' = 1/2 − γ.
        let o2: f64 = (0..n).map(|i| m[i] * beta_p[i]).sum();
        assert!((o2 - (0.5 - t.gamma)).abs() < tol, "order 2: {o2}");
        // Order 3: Σ bᵢ αᵢ² = 1/3, Σ bᵢ βᵢⱼ βⱼ' = 1/6 − γ + γ².
        let o3a: f64 = (0..n).map(|i| m[i] * alpha_i[i] * alpha_i[i]).sum();
        assert!((o3a - 1.0 / 3.0).abs() < tol, "order 3a: {o3a}");
        let o3b: f64 = (0..n)
            .map(|i| m[i] * (0..i).map(|j| beta[(i, j)] * beta_p[j]).sum::<f64>())
            .sum();
        let g = t.gamma;
        assert!(
            (o3b - (1.0 / 6.0 - g + g * g)).abs() < tol,
            "order 3b: {o3b}"
        );
        if order >= 4 {
            // Order 4: Σ bᵢ αᵢ³ = 1/4.
            let o4: f64 = (0..n).map(|i| m[i] * alpha_i[i].powi(3)).sum();
            assert!((o4 - 0.25).abs() < tol, "order 4: {o4}");
        }
        if order >= 5 {
            // Order 5: Σ bᵢ αᵢ⁴ = 1/5.
            let o5: f64 = (0..n).map(|i| m[i] * alpha_i[i].powi(4)).sum();
            assert!((o5 - 0.2).abs() < tol, "order 5: {o5}");
        }
        // The nodes are the row sums of α (cᵢ = αᵢ), and dᵢ = Σⱼ γᵢⱼ (the row sums of Γ).
        for (i, (alpha, (c, d))) in alpha_i.iter().zip(t.c.iter().zip(&t.d)).enumerate() {
            assert!((alpha - c).abs() < 1e-9, "c{i}");
            let gi: f64 = big_gamma.row(i).sum();
            assert!((gi - d).abs() < 1e-9, "d{i}: {gi} against {d}");
        }
    }

    #[test]
    fn the_tableaus_satisfy_order_conditions() {
        check(&RosenbrockTableau::rodas5p(), 5);
        check(&RosenbrockTableau::rodas4(), 4);
    }
}
