//! Bodies that no matter makes, seen in the numbers a model writes: a mass or a moment of
//! inertia, a shape's size or its axle written as numbers the run-time check
//! (`hamel::geometry::check_bodies`) would refuse whatever the parameters. They are compile
//! errors at the body, so that no program builds a model every run of which fails; sizes made
//! of the parameters are checked at run time.

use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::Lowerer;
use crate::engine::lower::geometry::{Body, ShapeKind};
use crate::system::spec::Spec;

use super::rows::row_source;

/// Rounding allowed in the triangle inequalities of written moments, relative to the largest
/// (a thin disk's m r²/4 + m r²/4 = m r²/2 to the last bit): the run-time check's.
const ROUNDING: f64 = 1e-12;

/// Reports each body of `#[bodies]` whose written numbers no matter makes; whether there was
/// none.
pub fn check_written(lowerer: &mut Lowerer<'_, '_>, spec: &Spec<'_>, bodies: &[Body]) -> bool {
    let Some((f, _)) = spec.geometry.bodies else {
        return true;
    };
    let mut ok = true;
    for (i, body) in bodies.iter().enumerate() {
        let Some(reason) = impossible(lowerer.graph, body) else {
            continue;
        };
        ok = false;
        let name = spec
            .body_names
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("body{i}"));
        lowerer.push_error(syn::Error::new_spanned(
            row_source(f, i),
            format!("body `{name}` {reason}"),
        ));
    }
    ok
}

/// What is impossible about the numbers written for `body`, if anything.
fn impossible(g: &Graph, body: &Body) -> Option<String> {
    if let Some(m) = g.const_value(body.mass)
        && !(m.is_finite() && m > 0.0)
    {
        return Some(format!(
            "has the mass {m}, written as a number: a body's mass must be positive"
        ));
    }
    let names = ["I_xx", "I_yy", "I_zz"];
    for (name, &moment) in names.iter().zip(&body.inertia[..3]) {
        if let Some(v) = g.const_value(moment)
            && !(v.is_finite() && v >= 0.0)
        {
            return Some(format!(
                "has the moment of inertia {name} = {v}, written as a number: a moment of \
                 inertia cannot be negative"
            ));
        }
    }
    let written: Option<Vec<f64>> = body.inertia.iter().map(|&n| g.const_value(n)).collect();
    if let Some(i) = written
        && !second_moment_is_positive(&i)
    {
        return Some(format!(
            "has the inertia ({}), written as numbers (I_xx, I_yy, I_zz, I_xy, I_yz, I_zx): no \
             distribution of mass gives it (its principal moments must be non-negative, each at \
             most the sum of the other two)",
            i.iter().map(f64::to_string).collect::<Vec<_>>().join(", ")
        ));
    }
    let shape = body.shape.as_deref()?;
    let sizes: &[(&str, usize)] = match shape.kind {
        ShapeKind::Disk | ShapeKind::Sphere => &[("radius", 0)],
        ShapeKind::Torus => &[("radius", 0)],
        ShapeKind::Ellipsoid => &[
            ("semi-axis along x", 0),
            ("semi-axis along y", 1),
            ("semi-axis along z", 2),
        ],
    };
    let kind = shape.kind.name();
    for &(what, k) in sizes {
        if let Some(v) = g.const_value(shape.sizes[k])
            && !(v.is_finite() && v > 0.0)
        {
            return Some(format!(
                "has the shape of a {kind} whose {what} is {v}, written as a number: a shape's \
                 size must be positive"
            ));
        }
    }
    if shape.kind == ShapeKind::Torus
        && let Some(v) = g.const_value(shape.sizes[1])
        && !(v.is_finite() && v >= 0.0)
    {
        return Some(format!(
            "has the shape of a torus whose tube's radius is {v}, written as a number: it \
             cannot be negative"
        ));
    }
    if matches!(shape.kind, ShapeKind::Disk | ShapeKind::Torus) && zero_vector(g, &shape.axle) {
        return Some(format!(
            "has the shape of a {kind} whose axle is the zero vector, which has no direction: \
             give the axle in the body's axes, `Vector3::y()`"
        ));
    }
    None
}

/// Whether `v` is written as numbers that make no direction (zero, or not finite).
fn zero_vector(g: &Graph, v: &[NodeId; 3]) -> bool {
    let Some(values) = v
        .iter()
        .map(|&n| g.const_value(n))
        .collect::<Option<Vec<f64>>>()
    else {
        return false;
    };
    values.iter().any(|x| !x.is_finite()) || values.iter().all(|&x| x == 0.0)
}

/// The run-time check's test (`hamel::geometry::check_bodies`): the second moment of the mass,
/// J = ½ tr(I) 1 − I, positive semi-definite to rounding (every principal minor non-negative),
/// which is the triangle inequalities of the principal moments with none negative.
fn second_moment_is_positive(i: &[f64]) -> bool {
    let [xx, yy, zz, xy, yz, zx] = [i[0], i[1], i[2], i[3], i[4], i[5]];
    let half = 0.5 * (xx + yy + zz);
    let (a, b, c) = (half - xx, half - yy, half - zz);
    let (p, q, r) = (-xy, -yz, -zx);
    let scale = xx.abs().max(yy.abs()).max(zz.abs());
    let tolerance = ROUNDING * scale;
    let minors2 = [a * b - p * p, b * c - q * q, a * c - r * r];
    let det = a * (b * c - q * q) - p * (p * c - q * r) + r * (p * q - b * r);
    [a, b, c].iter().all(|&d| d >= -tolerance)
        && minors2.iter().all(|&m| m >= -tolerance * scale)
        && det >= -tolerance * scale * scale
}
