//! The mobile robot's equations of motion written out by hand, as `hamel::docs::design`
//! states them (with its corrected signs): the reference for tests and the baseline of the
//! benchmark.
//! Written as a careful engineer would: each sine and cosine once, the 2×2 block solved by
//! Cramer's rule, the decoupled yaw equation by one division.

use hamel::models::MobileRobot;

/// ẋ for the state x = (x, y, α, φ₁, φ₂, ω³, ω⁴, ω⁵) and torques u = (τ₁, τ₂).
#[inline]
pub fn robot_rhs(p: &MobileRobot, x: &[f64; 8], u: &[f64; 2], dx: &mut [f64; 8]) {
    let (alpha, w3, w4, w5) = (x[2], x[5], x[6], x[7]);
    let theta = p.r * (x[3] - x[4]) / p.b;
    let (st, ct) = theta.sin_cos();
    let (sa, ca) = alpha.sin_cos();
    let ml = p.m0 * p.l;
    let ml2 = ml * p.l;
    let j5 =
        (p.jx + ml2) * sa * sa + p.jz * ca * ca + 0.75 * p.mw * p.b * p.b + 0.5 * p.mw * p.r * p.r;
    let torque = u[0] + u[1];
    let k_sin2a = (p.jx - p.jz + ml2) * 2.0 * sa * ca;
    // Right-hand sides of the f̃₃, f̃₄, f̃₅ equations with the velocity terms moved over.
    let r3 = -torque + 0.5 * k_sin2a * w5 * w5 + ml * p.g * sa;
    let r4 = torque / p.r + ml * sa * (w3 * w3 + w5 * w5);
    let r5 = p.b * (u[0] - u[1]) / (2.0 * p.r) - k_sin2a * w3 * w5 - ml * sa * w4 * w5;
    let (a, c, d) = (p.jy + ml2, ml * ca, p.m0 + 3.0 * p.mw);
    let inv_det = 1.0 / (a * d - c * c);
    // Kinematics q̇ = Bᵣ ω.
    let roll = w4 / p.r - w3;
    let turn = 0.5 * p.b / p.r * w5;
    dx[0] = ct * w4;
    dx[1] = st * w4;
    dx[2] = w3;
    dx[3] = roll + turn;
    dx[4] = roll - turn;
    dx[5] = (d * r3 - c * r4) * inv_det;
    dx[6] = (a * r4 - c * r3) * inv_det;
    dx[7] = r5 / j5;
}
