//! Collocation Runge–Kutta methods: their tableaus (Gauss–Legendre with 1, 2 and 3 stages,
//! Radau IIA with 3) and their collocation polynomial, which is at once the dense output
//! between a step's ends and the source of the next step's starting values.
//!
//! An s-stage collocation method with nodes c₁…c_s finds the polynomial u of degree s with
//! u(t₀) = y₀ and u′(t₀ + cᵢh) = f(t₀ + cᵢh, u(t₀ + cᵢh)); its stage values are
//! Yᵢ = u(t₀ + cᵢh) = y₀ + Zᵢ with Zᵢ = h Σⱼ aᵢⱼ f(Yⱼ), and y₁ = u(t₀ + h) (Hairer, Nørsett &
//! Wanner, *Solving Ordinary Differential Equations I*, II.7). Written through the Zᵢ, u is
//! y₀ + Σᵢ Zᵢ ℓᵢ(θ) with ℓᵢ the Lagrange basis on the nodes {0, c₁…c_s} (the node 0 carrying
//! the value 0), so y₁ = y₀ + Σ dᵢ Zᵢ with dᵢ = ℓᵢ(1) = (bᵀA⁻¹)ᵢ: no evaluation after the
//! stages have converged (Hairer & Wanner, *Solving ODEs II*, IV.8).

use super::observer::Interpolant;
use crate::vector::Vector;

/// The coefficients of an s-stage collocation method.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Tableau<const S: usize> {
    /// The Runge–Kutta matrix A: Zᵢ = h Σⱼ aᵢⱼ f(y₀ + Zⱼ).
    pub a: [[f64; S]; S],
    /// The nodes cᵢ ∈ (0, 1].
    pub c: [f64; S],
    /// y₁ = y₀ + Σ dᵢ Zᵢ: the collocation polynomial's basis at θ = 1.
    pub d: [f64; S],
}

impl<const S: usize> Tableau<S> {
    fn with(a: [[f64; S]; S], c: [f64; S]) -> Self {
        let mut tableau = Tableau { a, c, d: [0.0; S] };
        tableau.d = core::array::from_fn(|i| tableau.basis(i, 1.0));
        tableau
    }

    /// ℓᵢ(θ): the Lagrange basis polynomial on the nodes {0, c₁…c_s} that is 1 at cᵢ and 0 at
    /// the other nodes.
    pub fn basis(&self, i: usize, theta: f64) -> f64 {
        let mut value = theta / self.c[i];
        for (j, cj) in self.c.iter().enumerate() {
            if j != i {
                value *= (theta - cj) / (self.c[i] - cj);
            }
        }
        value
    }

    /// u(t₀ + θh) = y₀ + Σᵢ Zᵢ ℓᵢ(θ): inside the step for θ ∈ [0, 1], an extrapolation
    /// beyond it.
    pub fn polynomial<V: Vector>(&self, y0: &V, z: &[V; S], theta: f64) -> V {
        let weights: [f64; S] = core::array::from_fn(|i| self.basis(i, theta));
        let mut out = *y0;
        for (k, o) in out.as_mut().iter_mut().enumerate() {
            *o += weights
                .iter()
                .zip(z)
                .map(|(w, zi)| w * zi.as_ref()[k])
                .sum::<f64>();
        }
        out
    }

    /// y₁ = y₀ + Σ dᵢ Zᵢ.
    pub fn end<V: Vector>(&self, y0: &V, z: &[V; S]) -> V {
        let mut out = *y0;
        for (k, o) in out.as_mut().iter_mut().enumerate() {
            *o += self
                .d
                .iter()
                .zip(z)
                .map(|(d, zi)| d * zi.as_ref()[k])
                .sum::<f64>();
        }
        out
    }
}

impl Tableau<1> {
    /// The implicit midpoint rule: Gauss–Legendre with one stage, order 2.
    pub fn gauss1() -> Self {
        Tableau::with([[0.5]], [0.5])
    }
}

impl Tableau<2> {
    /// Gauss–Legendre with two stages, order 4 (Hairer, Nørsett & Wanner I, Table II.7.3).
    pub fn gauss2() -> Self {
        let r = 3f64.sqrt() / 6.0;
        Tableau::with([[0.25, 0.25 - r], [0.25 + r, 0.25]], [0.5 - r, 0.5 + r])
    }
}

impl Tableau<3> {
    /// Gauss–Legendre with three stages, order 6 (Hairer, Nørsett & Wanner I, Table II.7.4).
    pub fn gauss3() -> Self {
        let r = 15f64.sqrt();
        Tableau::with(
            [
                [5.0 / 36.0, 2.0 / 9.0 - r / 15.0, 5.0 / 36.0 - r / 30.0],
                [5.0 / 36.0 + r / 24.0, 2.0 / 9.0, 5.0 / 36.0 - r / 24.0],
                [5.0 / 36.0 + r / 30.0, 2.0 / 9.0 + r / 15.0, 5.0 / 36.0],
            ],
            [0.5 - r / 10.0, 0.5, 0.5 + r / 10.0],
        )
    }

    /// Radau IIA with three stages, order 5, stiffly accurate (c₃ = 1, so y₁ = y₀ + Z₃;
    /// Hairer & Wanner II, Table IV.5.6).
    pub fn radau_iia() -> Self {
        let r = 6f64.sqrt();
        Tableau::with(
            [
                [
                    (88.0 - 7.0 * r) / 360.0,
                    (296.0 - 169.0 * r) / 1800.0,
                    (-2.0 + 3.0 * r) / 225.0,
                ],
                [
                    (296.0 + 169.0 * r) / 1800.0,
                    (88.0 + 7.0 * r) / 360.0,
                    (-2.0 - 3.0 * r) / 225.0,
                ],
                [(16.0 - r) / 36.0, (16.0 + r) / 36.0, 1.0 / 9.0],
            ],
            [(4.0 - r) / 10.0, (4.0 + r) / 10.0, 1.0],
        )
    }
}

/// A step's collocation polynomial: the dense output between (t, y₀) and t + h.
pub(crate) struct Collocation<'a, V, const S: usize> {
    pub tableau: &'a Tableau<S>,
    pub t: f64,
    pub h: f64,
    pub y0: V,
    pub z: [V; S],
}

impl<V: Vector, const S: usize> Interpolant<V> for Collocation<'_, V, S> {
    fn at(&self, t: f64) -> V {
        self.tableau
            .polynomial(&self.y0, &self.z, (t - self.t) / self.h)
    }
}

/// The starting values Zᵢ of a step of size `h` from (t1, y1) — the end of the step whose
/// polynomial is `last`, with y1 possibly projected since — extrapolated from that
/// polynomial: u(t1 + cᵢh) − y1. Their error is that of the polynomial, O(h^(s+1)), so the
/// iteration starts close.
pub(crate) fn extrapolate<V: Vector, const S: usize>(
    last: &Collocation<'_, V, S>,
    y1: &V,
    h: f64,
) -> [V; S] {
    let (tableau, t1) = (last.tableau, last.t + last.h);
    // ℓⱼ at each stage's θᵢ, then every stage in one pass over the components: u(t1 + cᵢh)
    // as `Tableau::polynomial` sums it, y₀ + Σⱼ ℓⱼ(θᵢ)·Zⱼ, less y1 (each Zⱼ and y₀ read once
    // for the S stages, not once for each: some 100 instructions a step at n = 3).
    let weights: [[f64; S]; S] = core::array::from_fn(|i| {
        let theta = (t1 - last.t + tableau.c[i] * h) / last.h;
        core::array::from_fn(|j| tableau.basis(j, theta))
    });
    let mut z = [V::zeros(); S];
    let (y0, y1) = (last.y0.as_ref(), y1.as_ref());
    for (k, (y0k, y1k)) in y0.iter().zip(y1).enumerate() {
        for (zi, weights) in z.iter_mut().zip(&weights) {
            let sum = weights
                .iter()
                .zip(&last.z)
                .map(|(w, zj)| w * zj.as_ref()[k])
                .sum::<f64>();
            zi.as_mut()[k] = (y0k + sum) - y1k;
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The simplifying conditions of collocation (Hairer, Nørsett & Wanner I, II.7):
    /// C(s), Σⱼ aᵢⱼ cⱼ^(k−1) = cᵢ^k / k for k ≤ s, and B(p), Σ bᵢ cᵢ^(k−1) = 1/k for k ≤ p
    /// (p = 2s for Gauss, 2s − 1 for Radau), with the weights bᵀ = dᵀA.
    fn check<const S: usize>(tableau: &Tableau<S>, order: i32) {
        for (i, row) in tableau.a.iter().enumerate() {
            for k in 1..=S as i32 {
                let sum: f64 = row
                    .iter()
                    .zip(&tableau.c)
                    .map(|(a, c)| a * c.powi(k - 1))
                    .sum();
                assert!((sum - tableau.c[i].powi(k) / k as f64).abs() < 1e-15);
            }
        }
        let b: [f64; S] =
            core::array::from_fn(|j| (0..S).map(|i| tableau.d[i] * tableau.a[i][j]).sum());
        for k in 1..=order {
            let sum: f64 = b
                .iter()
                .zip(&tableau.c)
                .map(|(b, c)| b * c.powi(k - 1))
                .sum();
            assert!(
                (sum - 1.0 / k as f64).abs() < 1e-14,
                "B({k}): {sum} for a method of order {order}"
            );
        }
        // Not one order more: the orders are exactly these.
        let k = order + 1;
        let sum: f64 = b
            .iter()
            .zip(&tableau.c)
            .map(|(b, c)| b * c.powi(k - 1))
            .sum();
        assert!((sum - 1.0 / k as f64).abs() > 1e-6);
    }

    #[test]
    fn tableaus_satisfy_the_collocation_and_quadrature_conditions() {
        check(&Tableau::gauss1(), 2);
        check(&Tableau::gauss2(), 4);
        check(&Tableau::gauss3(), 6);
        check(&Tableau::radau_iia(), 5);
        // Radau IIA is stiffly accurate: y₁ is the last stage value.
        let d = Tableau::radau_iia().d;
        assert!(d[0].abs() < 1e-14 && d[1].abs() < 1e-14 && (d[2] - 1.0).abs() < 1e-14);
        // The midpoint rule: y₁ = y₀ + 2 Z₁.
        assert_eq!(Tableau::gauss1().d, [2.0]);
    }

    /// The starting values are the polynomial's values less y1, to the bit.
    #[test]
    fn extrapolation_is_the_polynomial_less_the_end() {
        let tableau = Tableau::radau_iia();
        let value = |k: usize| match k % 7 {
            0 => 0.0,
            1 => -0.0,
            _ => (k as f64 * 0.61).sin() * 10f64.powi(k as i32 % 5 - 2),
        };
        let last = Collocation {
            tableau: &tableau,
            t: 0.3,
            h: 0.07,
            y0: core::array::from_fn::<f64, 4, _>(|k| value(k + 40)),
            z: core::array::from_fn(|i| core::array::from_fn(|k| value(4 * i + k))),
        };
        let y1 = core::array::from_fn::<f64, 4, _>(|k| value(k + 20));
        for h in [0.01, 0.07, 0.2] {
            let ours = extrapolate(&last, &y1, h);
            for (i, zi) in ours.iter().enumerate() {
                let theta = (last.t + last.h - last.t + tableau.c[i] * h) / last.h;
                let mut eager = tableau.polynomial(&last.y0, &last.z, theta);
                for (e, y) in eager.iter_mut().zip(&y1) {
                    *e -= y;
                }
                assert_eq!(zi.map(f64::to_bits), eager.map(f64::to_bits), "stage {i}");
            }
        }
    }

    #[test]
    fn the_polynomial_interpolates_the_stages() {
        let tableau = Tableau::gauss2();
        let y0 = [1.0, -2.0];
        let z = [[0.1, 0.2], [0.3, -0.4]];
        assert_eq!(tableau.polynomial(&y0, &z, 0.0), y0);
        for i in 0..2 {
            let at = tableau.polynomial(&y0, &z, tableau.c[i]);
            for k in 0..2 {
                assert!((at[k] - y0[k] - z[i][k]).abs() < 1e-15);
            }
        }
        let end = tableau.end(&y0, &z);
        let at_one = tableau.polynomial(&y0, &z, 1.0);
        for k in 0..2 {
            assert!((end[k] - at_one[k]).abs() < 1e-15);
        }
    }
}
