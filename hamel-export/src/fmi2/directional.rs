//! `fmi2GetDirectionalDerivative`: Δunknowns = ∂unknowns/∂knowns · Δknowns.
//!
//! The knowns may be states, inputs, parameters and the time; the unknowns the derivatives
//! `der(x)`, the outputs y, the energy and the constraint residuals. The derivatives and the
//! outputs are exact to rounding: one pass of the generated code in dual numbers along the
//! direction (the same code as the right-hand side, every branch as it takes it). The
//! constraint rows vanish identically on the reduced state (their derivative is exactly
//! zero). The energy and the holonomic constraints exist in `f64` only in the generated code:
//! their derivatives are central differences along the direction (about 1e-10 relative).

use super::instance::{Instance, Outcome, Refusal, State};
use super::variables::Role;
use crate::model::Model;
use crate::passes;
use crate::primal::Which;
use hamel_runtime::{Parameters, Vector};

impl<M: Model> Instance<M> {
    /// `fmi2GetDirectionalDerivative` at the present point.
    pub fn directional_derivative(
        &self,
        unknowns: &[u32],
        knowns: &[u32],
        seeds: &[f64],
        out: &mut [f64],
    ) -> Outcome {
        let s = self.table.sizes;
        let x = self.current()?;
        let z = self.point(&x);
        let mut direction = M::array(0.0);
        for (vr, seed) in knowns.iter().zip(seeds) {
            let role = self.table.role(*vr).ok_or_else(|| unknown_reference(*vr))?;
            if !seed.is_finite() {
                return Err(Refusal::error(format!(
                    "the seed of {} is {seed}, not a finite number",
                    self.name(role)
                )));
            }
            let at = match role {
                Role::State(i) => i,
                Role::Input(i) => s.u() + i,
                Role::Parameter(i) => s.p() + i,
                Role::Time => s.t(),
                _ => {
                    return Err(Refusal::error(format!(
                        "{} is not a known of a directional derivative (states, inputs, \
                         parameters and the time are)",
                        self.name(role)
                    )));
                }
            };
            direction.as_mut()[at] += seed;
        }
        let mut rhs = None;
        let mut outputs = None;
        let mut monitors = None;
        for (vr, value) in unknowns.iter().zip(out.iter_mut()) {
            let role = self.table.role(*vr).ok_or_else(|| unknown_reference(*vr))?;
            *value = match role {
                Role::Derivative(i) => {
                    if rhs.is_none() {
                        rhs = Some(self.forward(Which::Rhs, &z, &direction)?);
                    }
                    rhs.as_ref().map_or(f64::NAN, |d| d.as_ref()[i])
                }
                Role::Output(i) => {
                    if outputs.is_none() {
                        outputs = Some(self.forward(Which::Outputs, &z, &direction)?);
                    }
                    outputs.as_ref().map_or(f64::NAN, |d| d.as_ref()[i])
                }
                Role::Constraint(_) => 0.0,
                Role::Energy | Role::Holonomic(_) => {
                    if monitors.is_none() {
                        monitors = Some(self.monitors_difference(&z, &direction)?);
                    }
                    let at = match role {
                        Role::Holonomic(i) => 1 + self.table.p + i,
                        _ => 0,
                    };
                    monitors.as_ref().map_or(f64::NAN, |m: &Vec<f64>| m[at])
                }
                _ => {
                    return Err(Refusal::error(format!(
                        "{} is not an unknown of a directional derivative (the derivatives, \
                         the outputs, the energy and the constraint residuals are)",
                        self.name(role)
                    )));
                }
            };
        }
        Ok(())
    }

    /// One pass of `which` in dual numbers at z along `direction`.
    fn forward(
        &self,
        which: Which,
        z: &M::Array<f64>,
        direction: &M::Array<f64>,
    ) -> Result<M::Array<f64>, Refusal> {
        let mut out = M::array(0.0);
        passes::forward::<M>(which, z.as_ref(), direction.as_ref(), out.as_mut())
            .map_err(|f| Refusal::discard(f.message))?;
        Ok(out)
    }

    /// The energy and the constraint residuals' derivatives along `direction`, by central
    /// differences with the step that balances truncation and rounding (∛ε of the scale).
    fn monitors_difference(
        &self,
        z: &M::Array<f64>,
        direction: &M::Array<f64>,
    ) -> Result<Vec<f64>, Refusal> {
        let size = direction
            .as_ref()
            .iter()
            .fold(0.0f64, |m, d| m.max(d.abs()));
        let count = 1 + self.table.p + self.table.k;
        if size == 0.0 {
            return Ok(vec![0.0; count]);
        }
        let scale = z
            .as_ref()
            .iter()
            .zip(direction.as_ref())
            .filter(|(_, d)| **d != 0.0)
            .fold(1.0f64, |m, (v, _)| m.max(v.abs()));
        let h = f64::EPSILON.cbrt() * scale / size;
        let at = |sign: f64| -> Result<Vec<f64>, Refusal> {
            let mut shifted = *z;
            for (v, d) in shifted.as_mut().iter_mut().zip(direction.as_ref()) {
                *v += sign * h * d;
            }
            self.monitors_at(shifted.as_ref())
        };
        let (plus, minus) = (at(1.0)?, at(-1.0)?);
        Ok(plus
            .iter()
            .zip(&minus)
            .map(|(a, b)| (a - b) / (2.0 * h))
            .collect())
    }

    /// The energy and the constraint residuals at z = (x, u, p, t).
    fn monitors_at(&self, z: &[f64]) -> Result<Vec<f64>, Refusal> {
        let s = self.table.sizes;
        let mut system = M::System::default();
        for (name, value) in <M::System as Parameters>::NAMES
            .iter()
            .zip(&z[s.p()..s.t()])
        {
            system
                .set(name, *value)
                .map_err(|e| Refusal::error(e.to_string()))?;
        }
        let mut x = State::<M>::zeros();
        x.as_mut().copy_from_slice(&z[..s.nx]);
        let t = z[s.t()];
        self.monitors(&system, t, &x).map_err(|r| {
            Refusal::discard(format!(
                "{} (met while differencing the energy along the direction)",
                r.message
            ))
        })
    }
}

fn unknown_reference(vr: u32) -> Refusal {
    Refusal::error(format!("unknown value reference {vr}"))
}
