//! The bodies of a model must be bodies some matter could make: a positive mass, and an
//! inertia tensor that is symmetric positive semi-definite with principal moments satisfying
//! the triangle inequalities (each at most the sum of the other two), an orientation that is a
//! rotation and a shape of positive size (`check_shapes`). Checked when a state is built, when
//! a run starts and when the model is linearized, so that a negative moment of inertia is an
//! error naming the body instead of an indefinite mass matrix, or a step size underflow,
//! somewhere in a run.

use super::check_shapes::{impossible_shape, not_a_rotation};
use super::{Body, Inertia};
use crate::error::{Error, Num};

/// Rounding allowed in the inequalities, relative to the largest principal moment: a thin
/// disk's moments m r²/4 + m r²/4 = m r²/2 are equal to the last bit, and a thin rod has a
/// zero moment.
const ROUNDING: f64 = 1e-12;

/// Check each body, named by `names` (in the same order; `body3` when there are fewer).
///
/// ```
/// use hamel_runtime::geometry::{Body, Inertia, Vector3, Rotation3, check_bodies};
/// let disk = Body::new(1.0, Inertia::principal(0.25, 0.5, 0.25), Vector3::zeros(), Rotation3::identity());
/// assert!(check_bodies(&[disk], &["wheel"]).is_ok());
/// let impossible = Body { inertia: Inertia::principal(0.1, 0.5, 0.1), ..disk };
/// let error = check_bodies(&[disk, impossible], &["wheel", "frame"]).unwrap_err();
/// assert!(error.to_string().contains("`frame`"));
/// ```
pub fn check_bodies(bodies: &[Body], names: &[&str]) -> Result<(), Error> {
    for (i, body) in bodies.iter().enumerate() {
        let name = || {
            names
                .get(i)
                .map_or_else(|| format!("body{i}"), |n| (*n).to_string())
        };
        if let Some(reason) = unphysical(body) {
            return Err(Error::UnphysicalBody {
                body: name(),
                reason,
            });
        }
        if let Some(why) = not_a_rotation(&body.orientation) {
            return Err(Error::ImpossibleGeometry {
                what: format!("the orientation of body `{}`", name()),
                reason: why,
            });
        }
        if let Some(reason) = body.shape.as_ref().and_then(impossible_shape) {
            return Err(Error::ImpossibleGeometry {
                what: format!("the shape of body `{}`", name()),
                reason,
            });
        }
    }
    Ok(())
}

/// What makes the body impossible, if anything.
fn unphysical(body: &Body) -> Option<String> {
    let m = body.mass;
    if !m.is_finite() || m <= 0.0 {
        return Some(format!(
            "its mass is {}; a body's mass must be positive",
            Num(m)
        ));
    }
    let Inertia {
        xx,
        yy,
        zz,
        xy,
        yz,
        zx,
    } = body.inertia;
    if ![xx, yy, zz, xy, yz, zx].iter().all(|v| v.is_finite()) {
        return Some(format!(
            "its inertia {:?} has an entry that is not a finite number",
            body.inertia
        ));
    }
    if second_moment_is_positive(&body.inertia) {
        return None;
    }
    // Off the hot path: the principal moments, to say what is wrong.
    let tensor = nalgebra::Matrix3::new(xx, xy, zx, xy, yy, yz, zx, yz, zz);
    let mut moments: Vec<f64> = tensor.symmetric_eigenvalues().iter().copied().collect();
    moments.sort_by(f64::total_cmp);
    let (small, middle, large) = (moments[0], moments[1], moments[2]);
    let principal = format!(
        "its principal moments of inertia are {}, {} and {}",
        Num(small),
        Num(middle),
        Num(large)
    );
    if small < 0.0 {
        return Some(format!(
            "{principal}: a moment of inertia cannot be negative (the inertia tensor must be \
             positive semi-definite)"
        ));
    }
    Some(format!(
        "{principal}: the largest exceeds the sum of the other two, which no distribution of \
         mass gives (the triangle inequality of the principal moments)"
    ))
}

/// Whether the second moment of the mass, J = ½ tr(I) 1 − I (J = Σ m r rᵀ), is positive
/// semi-definite, to rounding: its eigenvalues are ½ (I₂ + I₃ − I₁) and its kin, so this is
/// the triangle inequalities of the principal moments, and with them I = tr(J) 1 − J is
/// positive semi-definite too. Every principal minor of J must be non-negative (a few
/// dozen operations, where the eigenvalues would cost a hundred times more).
fn second_moment_is_positive(i: &Inertia) -> bool {
    let half = 0.5 * (i.xx + i.yy + i.zz);
    let (a, b, c) = (half - i.xx, half - i.yy, half - i.zz);
    // The tensor's products are the negated products of J.
    let (p, q, r) = (-i.xy, -i.yz, -i.zx);
    let scale = i.xx.abs().max(i.yy.abs()).max(i.zz.abs());
    let tolerance = ROUNDING * scale;
    let minors2 = [a * b - p * p, b * c - q * q, a * c - r * r];
    let det = a * (b * c - q * q) - p * (p * c - q * r) + r * (p * q - b * r);
    [a, b, c].iter().all(|&d| d >= -tolerance)
        && minors2.iter().all(|&m| m >= -tolerance * scale)
        && det >= -tolerance * scale * scale
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Rotation3, Vector3};

    fn body(mass: f64, inertia: Inertia) -> Body {
        Body::new(mass, inertia, Vector3::zeros(), Rotation3::identity())
    }

    #[test]
    fn physical_bodies_pass_and_each_impossible_one_is_named_with_its_reason() {
        let rod = body(2.0, Inertia::principal(0.0, 1.0, 1.0));
        let point = Body::point_mass(1.0, Vector3::x());
        let frame = body(85.0, Inertia::new(9.2, 11.0, 2.8, 0.0, 0.0, 2.4));
        assert!(check_bodies(&[rod, point, frame], &[]).is_ok());
        let cases = [
            (body(0.0, Inertia::principal(1.0, 1.0, 1.0)), "mass is 0"),
            (body(-1.0, Inertia::principal(1.0, 1.0, 1.0)), "mass is -1"),
            (
                body(1.0, Inertia::principal(-0.1, 1.0, 1.0)),
                "cannot be negative",
            ),
            (
                body(1.0, Inertia::new(1.0, 1.0, 1.0, 2.0, 0.0, 0.0)),
                "cannot be negative",
            ),
            (
                body(1.0, Inertia::principal(0.1, 0.1, 0.5)),
                "triangle inequality",
            ),
            (
                body(f64::NAN, Inertia::principal(1.0, 1.0, 1.0)),
                "mass is NaN",
            ),
        ];
        for (b, reason) in cases {
            let message = check_bodies(&[rod, b], &["rod", "hull"])
                .unwrap_err()
                .to_string();
            assert!(message.contains("`hull`"), "{message}");
            assert!(message.contains(reason), "{message}");
        }
    }
}
