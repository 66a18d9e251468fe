//! Central differences of a hand-written system's right-hand side, to check Jacobians by.

use hamel_runtime::{HamelSystem, Vector};

/// ∂F/∂x (S × S) and ∂F/∂u (S × M) of `system.rhs` at (t, x, u) by central differences,
/// row-major. The step hⱼ = 10⁻⁵·max(|xⱼ|, 1) balances the truncation error, O(h²) from the
/// third derivative, against rounding, O(ε/h): both about 10⁻¹⁰ relative for the smooth
/// systems of these tests.
pub fn central_differences<S: HamelSystem>(
    system: &S,
    t: f64,
    x: &S::State,
    u: &S::Inputs,
) -> (Vec<f64>, Vec<f64>) {
    let (s, m) = (S::State::LEN, S::Inputs::LEN);
    let rate = |x: &S::State, u: &S::Inputs| {
        let mut dx = S::State::zeros();
        system.rhs(t, x, u, &mut dx).expect("a regular point");
        dx
    };
    // The derivative along component j of `v`, given how to rebuild the arguments.
    let column = |value: f64, at: &dyn Fn(f64) -> S::State| -> Vec<f64> {
        let h = 1e-5 * value.abs().max(1.0);
        let (plus, minus) = (at(value + h), at(value - h));
        let (plus, minus) = (plus.as_ref(), minus.as_ref());
        (0..s).map(|i| (plus[i] - minus[i]) / (2.0 * h)).collect()
    };
    let mut a = vec![0.0; s * s];
    for j in 0..s {
        let d = column(x.as_ref()[j], &|value| {
            let mut y = *x;
            y.as_mut()[j] = value;
            rate(&y, u)
        });
        for i in 0..s {
            a[i * s + j] = d[i];
        }
    }
    let mut b = vec![0.0; s * m];
    for j in 0..m {
        let d = column(u.as_ref()[j], &|value| {
            let mut v = *u;
            v.as_mut()[j] = value;
            rate(x, &v)
        });
        for i in 0..s {
            b[i * m + j] = d[i];
        }
    }
    (a, b)
}

/// max |aᵢ − bᵢ| / max |aᵢ|: how far `b` is from `a`, relative to `a`'s largest entry.
pub fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let largest = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    worst / largest
}
