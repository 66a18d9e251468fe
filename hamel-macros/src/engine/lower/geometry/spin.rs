//! The angular velocity of a rotation along a motion: from the turns it is a product of when
//! they are known (as a hand derivation writes it, and as cheap), otherwise from Ṙ Rᵀ.

use super::{Rotation, Spin, Vec3, add, apply, cross, dot, identity, product, scale, sub};
use crate::engine::graph::{Graph, NodeId};

/// The time derivative of nodes along the motion.
pub type Rate<'r> = dyn FnMut(&mut Graph, &[NodeId]) -> Vec<NodeId> + 'r;

/// The angular velocity ω of `r` in the frame it maps to. For a product of turns about
/// fixed axes (or quaternions), R = F₁ ⋯ Fₖ, ω = Σᵢ (F₁ ⋯ Fᵢ₋₁) ωᵢ with ωᵢ = aᵢ θ̇ᵢ for a turn
/// about aᵢ and 2 (w v̇ − ẇ v + v × v̇)/|q|² for a quaternion q = (w, v); otherwise from
/// Ṙ Rᵀ = [ω]ₓ. `moving[i]`: whether node i moves (depends on t or q).
pub fn angular_velocity(g: &mut Graph, r: &Rotation, moving: &[bool], rate: &mut Rate<'_>) -> Vec3 {
    let fixed = |spin: &Spin| match spin {
        Spin::Axis { axis, .. } => axis.iter().all(|a| !moving[a.index()]),
        Spin::Quaternion(_) => true,
    };
    if let Some(turns) = r
        .turns
        .as_ref()
        .filter(|t| t.iter().all(|t| fixed(&t.spin)))
    {
        let zero = g.zero();
        let mut omega = [zero; 3];
        let mut before = identity(g).matrix;
        for turn in turns {
            let own = turn_spin(g, &turn.spin, rate);
            let carried = apply(g, &before, own);
            omega = add(g, omega, carried);
            before = product(g, &before, &turn.matrix);
        }
        return omega;
    }
    let entries: Vec<NodeId> = r.matrix.iter().flatten().copied().collect();
    let d = rate(g, &entries);
    let rates = [[d[0], d[1], d[2]], [d[3], d[4], d[5]], [d[6], d[7], d[8]]];
    // (Ṙ Rᵀ)_ij = row i of Ṙ · row j of R; ω = (W₂₁, W₀₂, W₁₀).
    let m = &r.matrix;
    [
        dot(g, rates[2], m[1]),
        dot(g, rates[0], m[2]),
        dot(g, rates[1], m[0]),
    ]
}

/// The angular velocity of one turn in the frame it turns in.
fn turn_spin(g: &mut Graph, spin: &Spin, rate: &mut Rate<'_>) -> Vec3 {
    match *spin {
        Spin::Axis { axis, angle } => {
            let rate = rate(g, &[angle])[0];
            scale(g, rate, axis)
        }
        Spin::Quaternion([w, x, y, z]) => {
            let d = rate(g, &[w, x, y, z]);
            let (v, dv) = ([x, y, z], [d[1], d[2], d[3]]);
            let along = scale(g, w, dv);
            let back = scale(g, d[0], v);
            let twist = cross(g, v, dv);
            let sum = sub(g, along, back);
            let sum = add(g, sum, twist);
            let squares = [g.mul(w, w), g.mul(x, x), g.mul(y, y), g.mul(z, z)];
            let norm2 = g.sum(&squares);
            let two = g.constant(2.0);
            let factor = g.div(two, norm2);
            scale(g, factor, sum)
        }
    }
}
