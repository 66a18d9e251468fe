//! A [`HamelSystem`] with its inputs as an [`Ode`]: the plain state for a conservative
//! system, the state extended by the work done on it otherwise; with the holonomic
//! constraints re-solved after every step when asked.

use std::cell::RefCell;

use crate::assembly;
use crate::error::{Error, Singularity};
use crate::integrate::Ode;
use crate::named::NamedValues;
use crate::recorder::check_inputs;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// The values `system` prepares for its right-hand side ([`HamelSystem::prepare`]).
pub(crate) fn prepared<S: HamelSystem>(system: &S) -> Vec<f64> {
    let mut prepared = vec![0.0; S::PREPARED_LEN];
    system.prepare(&mut prepared);
    prepared
}

/// The name of the work in the extended state's messages.
const WORK: &str = "work";

/// A run's inputs u(t, x), shared by its ODE (every stage) and its recorder (every sample):
/// a function of the time and state, checked to be finite wherever it is evaluated, or
/// constant, checked once.
pub(crate) struct RunInputs<S: HamelSystem, F> {
    function: RefCell<F>,
    constant: Option<S::Inputs>,
}

impl<S: HamelSystem> RunInputs<S, fn(f64, &S::State) -> S::Inputs> {
    /// Constant inputs (checked once, by [`RunInputs::check_start`]).
    pub fn constant(u: S::Inputs) -> Self {
        RunInputs {
            function: RefCell::new(|_, _| S::Inputs::zeros()),
            constant: Some(u),
        }
    }
}

impl<S: HamelSystem, F: FnMut(f64, &S::State) -> S::Inputs> RunInputs<S, F> {
    /// Inputs computed by `f` at each (t, x).
    pub fn function(f: F) -> Self {
        RunInputs {
            function: RefCell::new(f),
            constant: None,
        }
    }

    /// That the inputs at the run's start are finite: the first that is not is named, with
    /// the time and state. Constant inputs are checked here only.
    pub fn check_start(&self, t: f64, x: &S::State) -> Result<(), Error> {
        check_inputs::<S>(&self.unchecked(t, x), t, x)
    }

    /// u(t, x), which must be finite, as [`RunInputs::check_start`] says; constant inputs
    /// were checked there.
    #[inline]
    pub fn at(&self, t: f64, x: &S::State) -> Result<S::Inputs, Error> {
        let u = self.unchecked(t, x);
        if self.constant.is_none() {
            check_inputs::<S>(&u, t, x)?;
        }
        Ok(u)
    }

    /// u(t, x), not checked.
    #[inline]
    fn unchecked(&self, t: f64, x: &S::State) -> S::Inputs {
        match self.constant {
            Some(u) => u,
            None => (self.function.borrow_mut())(t, x),
        }
    }

    /// Whether the inputs are constant and zero.
    pub fn are_zero(&self) -> bool {
        self.constant
            .is_some_and(|u| u.as_ref().iter().all(|v| *v == 0.0))
    }

    /// Whether the inputs depend on the state at all (constant ones do not).
    fn read_state(&self) -> bool {
        self.constant.is_none()
    }
}

/// The reduced ODE ẋ = F(t, x, u(t, x)): the inputs are evaluated at every stage, and a
/// singular matrix in the right-hand side becomes an error naming the time and state.
pub(crate) struct PlainOde<'s, 'i, S: HamelSystem, F> {
    pub system: &'s S,
    /// The right-hand side's parameter-only values, prepared once for the run.
    pub prepared: Vec<f64>,
    /// Shared with the recorder, which records the inputs at the samples.
    pub inputs: &'i RunInputs<S, F>,
    /// Whether to re-solve the dependent coordinates after every step.
    pub project: bool,
    /// The reduced mass matrix's diagonal at the run's start ([`inertia_diagonal`]).
    pub start_inertia: Option<Vec<f64>>,
}

impl<S: HamelSystem, F: FnMut(f64, &S::State) -> S::Inputs> Ode for PlainOde<'_, '_, S, F> {
    type State = S::State;

    fn rhs(&mut self, t: f64, x: &S::State, dx: &mut S::State) -> Result<(), Error> {
        let u = self.inputs.at(t, x)?;
        self.system
            .rhs_prepared(&self.prepared, t, x, &u, dx)
            .map_err(|s| singular_in_run(self.system, s, t, x, self.start_inertia.as_deref()))
    }

    fn jacobian(&mut self, t: f64, x: &S::State, jacobian: &mut [f64]) -> Result<bool, Error> {
        state_jacobian(self.system, self.inputs, (t, x), jacobian, S::State::LEN)?;
        Ok(true)
    }

    fn time_derivative(
        &mut self,
        t: f64,
        x: &S::State,
        dfdt: &mut S::State,
    ) -> Result<bool, Error> {
        state_time_derivative(self.system, self.inputs, (t, x), dfdt.as_mut())
    }

    fn project(&mut self, t: f64, x: &mut S::State) -> Result<bool, Error> {
        if !self.project {
            return Ok(false);
        }
        // A copy, so that the error can name the state the step produced (formed only then).
        let before = *x;
        project_coordinates(self.system, t, x.as_mut(), || S::named_state(&before))
    }

    fn describe(&self, x: &S::State) -> NamedValues {
        S::named_state(x)
    }
}

/// The reduced ODE extended by the work W done on the system, Ẇ = power(t, x, u), for the
/// energy balance E(t) − E(t₀) = W(t). W is left out of the step-size control, so the steps
/// are exactly those of the plain state.
pub(crate) struct BalanceOde<'s, 'i, S: HamelSystem, F> {
    pub system: &'s S,
    /// The right-hand side's parameter-only values, prepared once for the run.
    pub prepared: Vec<f64>,
    pub inputs: &'i RunInputs<S, F>,
    /// Whether to re-solve the dependent coordinates after every step.
    pub project: bool,
    /// The reduced mass matrix's diagonal at the run's start ([`inertia_diagonal`]).
    pub start_inertia: Option<Vec<f64>>,
}

impl<S: HamelSystem, F: FnMut(f64, &S::State) -> S::Inputs> Ode for BalanceOde<'_, '_, S, F> {
    type State = S::Extended;

    /// The state is read, and its derivative written, in place: a copy of the derivative
    /// would read back components the right-hand side has only just stored, and wait for
    /// them (see `integrate::fresh_component`).
    fn rhs(&mut self, t: f64, v: &S::Extended, dv: &mut S::Extended) -> Result<(), Error> {
        let (Some(x), Some(dx)) = (S::State::head(v.as_ref()), S::State::head_mut(dv.as_mut()))
        else {
            return Err(inconsistent_extension::<S>());
        };
        let u = self.inputs.at(t, x)?;
        let power = self
            .system
            .rhs_power_prepared(&self.prepared, t, x, &u, dx)
            .map_err(|s| singular_in_run(self.system, s, t, x, self.start_inertia.as_deref()))?;
        dv.as_mut()[S::State::LEN] = power;
        Ok(())
    }

    fn controlled_components(&self) -> usize {
        S::State::LEN
    }

    /// The state's block, exact, and the work's row ∂power/∂x by forward differences (the
    /// work does not act back on the state: its column is zero). An implicit method's stages
    /// would converge without that row, the work one iteration behind; a Rosenbrock method's
    /// work would lose its order.
    fn jacobian(&mut self, t: f64, v: &S::Extended, jacobian: &mut [f64]) -> Result<bool, Error> {
        let (x, _) = split::<S>(v);
        jacobian.fill(0.0);
        let stride = S::Extended::LEN;
        state_jacobian(self.system, self.inputs, (t, &x), jacobian, stride)?;
        let power = |x: &S::State| {
            let u = self.inputs.at(t, x)?;
            self.system
                .power(t, x, &u)
                .map_err(|s| S::singular(s, t, x))
        };
        let p0 = power(&x)?;
        let n = S::State::LEN;
        for j in 0..n {
            let mut shifted = x;
            let xj = x.as_ref()[j];
            shifted.as_mut()[j] = xj + f64::EPSILON.sqrt() * xj.abs().max(1.0);
            let delta = shifted.as_ref()[j] - xj;
            jacobian[n * stride + j] = (power(&shifted)? - p0) / delta;
        }
        Ok(true)
    }

    /// The state's ∂F/∂t, and the work's ∂power/∂t by a forward difference.
    fn time_derivative(
        &mut self,
        t: f64,
        v: &S::Extended,
        dfdt: &mut S::Extended,
    ) -> Result<bool, Error> {
        let (x, _) = split::<S>(v);
        let n = S::State::LEN;
        if !state_time_derivative(self.system, self.inputs, (t, &x), &mut dfdt.as_mut()[..n])? {
            return Ok(false);
        }
        let power = |t: f64| {
            let u = self.inputs.at(t, &x)?;
            self.system
                .power(t, &x, &u)
                .map_err(|s| S::singular(s, t, &x))
        };
        let shifted = t + f64::EPSILON.sqrt() * t.abs().max(1.0);
        dfdt.as_mut()[n] = (power(shifted)? - power(t)?) / (shifted - t);
        Ok(true)
    }

    fn project(&mut self, t: f64, v: &mut S::Extended) -> Result<bool, Error> {
        if !self.project {
            return Ok(false);
        }
        let before = *v;
        project_coordinates(self.system, t, v.as_mut(), || {
            describe_extended::<S>(&before)
        })
    }

    fn describe(&self, v: &S::Extended) -> NamedValues {
        describe_extended::<S>(v)
    }
}

/// ∂F/∂x of the reduced ODE with the inputs' feedback u(t, x), into the leading rows and
/// columns of `out` (row-major, `stride` columns): the system's exact ∂F/∂x (dual numbers
/// through the generated right-hand side) plus ∂F/∂u·∂u/∂x, with ∂u/∂x by forward differences
/// of the input function (which is arbitrary code): n more calls of it, none for a system
/// without inputs, and exactly zero for inputs that do not read the state.
fn state_jacobian<S: HamelSystem, F: FnMut(f64, &S::State) -> S::Inputs>(
    system: &S,
    inputs: &RunInputs<S, F>,
    (t, x): (f64, &S::State),
    out: &mut [f64],
    stride: usize,
) -> Result<(), Error> {
    let (n, m) = (S::State::LEN, S::Inputs::LEN);
    let u = inputs.at(t, x)?;
    let (jx, ju) = system
        .jacobian(t, x, &u)
        .map_err(|s| S::singular(s, t, x))?;
    check_jacobian_shape::<S>(jx.as_ref().len(), ju.as_ref().len())?;
    for i in 0..n {
        out[i * stride..i * stride + n].copy_from_slice(&jx.as_ref()[i * n..(i + 1) * n]);
    }
    if m == 0 || !inputs.read_state() {
        return Ok(());
    }
    for j in 0..n {
        let mut shifted = *x;
        let xj = x.as_ref()[j];
        shifted.as_mut()[j] = xj + (f64::EPSILON * xj.abs().max(1e-5)).sqrt();
        let delta = shifted.as_ref()[j] - xj;
        let moved = inputs.unchecked(t, &shifted);
        for k in 0..m {
            let du = (moved.as_ref()[k] - u.as_ref()[k]) / delta;
            if du != 0.0 {
                for i in 0..n {
                    out[i * stride + j] += ju.as_ref()[i * m + k] * du;
                }
            }
        }
    }
    Ok(())
}

/// The error for a model whose Jacobians have not the state's and inputs' sizes (a
/// hand-written `HamelSystem` whose `StateJacobian` or `InputJacobian` is not n × n and
/// n × m): named, rather than a slice out of bounds.
fn check_jacobian_shape<S: HamelSystem>(state: usize, input: usize) -> Result<(), Error> {
    jacobian_shape((S::State::LEN, S::Inputs::LEN), (state, input))
}

/// [`check_jacobian_shape`] for n states and m inputs.
fn jacobian_shape((n, m): (usize, usize), (state, input): (usize, usize)) -> Result<(), Error> {
    if state == n * n && input == n * m {
        return Ok(());
    }
    Err(Error::InconsistentModel {
        what: format!(
            "`jacobian` returns ∂F/∂x with {state} entries and ∂F/∂u with {input}, but a state \
             of {n} components and {m} inputs need {} and {} (`StateJacobian` is n × n and \
             `InputJacobian` n × m, row by row)",
            n * n,
            n * m
        ),
    })
}

/// ∂F/∂t of the reduced ODE with the inputs' feedback u(t, x), into `out` (n entries): the
/// system's ∂F/∂t plus ∂F/∂u·∂u/∂t, ∂u/∂t by a forward difference of the input function over
/// √ε·max(|t|, 1) (the exact ∂F/∂u evaluated only for inputs that change with t). `false`
/// when the system does not give ∂F/∂t (a hand-written one): the integrator then differences
/// the whole right-hand side in t.
fn state_time_derivative<S: HamelSystem, F: FnMut(f64, &S::State) -> S::Inputs>(
    system: &S,
    inputs: &RunInputs<S, F>,
    (t, x): (f64, &S::State),
    out: &mut [f64],
) -> Result<bool, Error> {
    let (n, m) = (S::State::LEN, S::Inputs::LEN);
    let u = inputs.at(t, x)?;
    let Some(ft) = system
        .time_derivative(t, x, &u)
        .map_err(|s| S::singular(s, t, x))?
    else {
        return Ok(false);
    };
    out[..n].copy_from_slice(ft.as_ref());
    // Constant inputs do not change with t.
    if m == 0 || !inputs.read_state() {
        return Ok(true);
    }
    let shifted = t + f64::EPSILON.sqrt() * t.abs().max(1.0);
    let moved = inputs.unchecked(shifted, x);
    let du: Vec<f64> = (0..m)
        .map(|k| (moved.as_ref()[k] - u.as_ref()[k]) / (shifted - t))
        .collect();
    if du.iter().all(|d| *d == 0.0) {
        return Ok(true);
    }
    let (jx, ju) = system
        .jacobian(t, x, &u)
        .map_err(|s| S::singular(s, t, x))?;
    check_jacobian_shape::<S>(jx.as_ref().len(), ju.as_ref().len())?;
    for (i, o) in out.iter_mut().enumerate().take(n) {
        *o += (0..m).map(|k| ju.as_ref()[i * m + k] * du[k]).sum::<f64>();
    }
    Ok(true)
}

/// The extended state (x, 0) of a state x, or the error for a model whose `Extended` is not
/// one longer than its `State`.
pub(crate) fn extend<S: HamelSystem>(x: &S::State) -> Result<S::Extended, Error> {
    let n = S::State::LEN;
    if S::Extended::LEN != n + 1 {
        return Err(inconsistent_extension::<S>());
    }
    let mut v = S::Extended::zeros();
    v.as_mut()[..n].copy_from_slice(x.as_ref());
    Ok(v)
}

/// The error for a model whose `Extended` is not one longer than its `State`.
#[cold]
fn inconsistent_extension<S: HamelSystem>() -> Error {
    Error::InconsistentModel {
        what: format!(
            "`Extended` has {} components, but the state has {} and the work adds one",
            S::Extended::LEN,
            S::State::LEN
        ),
    }
}

/// The state and the work of an extended state (checked by [`extend`] to be one longer).
pub(crate) fn split<S: HamelSystem>(v: &S::Extended) -> (S::State, f64) {
    let n = S::State::LEN;
    let mut x = S::State::zeros();
    x.as_mut().copy_from_slice(&v.as_ref()[..n]);
    (x, v.as_ref()[n])
}

fn describe_extended<S: HamelSystem>(v: &S::Extended) -> NamedValues {
    let (x, work) = split::<S>(v);
    let mut named = S::named_state(&x);
    named.0.push((WORK.to_string(), work));
    named
}

/// Re-solves the dependent coordinates in the leading n components of `state` at time t;
/// whether that changed them. An assembly error names the whole state (`named`, formed only
/// then) instead of the coordinates alone.
pub(crate) fn project_coordinates<S: HamelSystem>(
    system: &S,
    t: f64,
    state: &mut [f64],
    named: impl FnOnce() -> NamedValues,
) -> Result<bool, Error> {
    if S::K == 0 {
        return Ok(false);
    }
    let n = S::Coordinates::LEN;
    let mut q = S::Coordinates::zeros();
    q.as_mut().copy_from_slice(&state[..n]);
    let solved = assembly::newton(system, t, &q).map_err(|e| match e {
        Error::Assembly {
            constraint,
            coordinate,
            t,
            failure,
            residual,
            configuration: _,
        } => Error::Assembly {
            constraint,
            coordinate,
            t,
            failure,
            residual,
            configuration: named(),
        },
        other => other,
    })?;
    if solved == q {
        return Ok(false);
    }
    state[..n].copy_from_slice(solved.as_ref());
    Ok(true)
}

/// The reduced mass matrix's diagonal at (t, x): M_kk = E(s = e_k) + E(s = −e_k) − 2 E(s = 0)
/// for each speed k (the energy's part even in the speeds, ½ sᵀM s, at a unit speed), or
/// `None` where the energy is not defined.
pub(crate) fn inertia_diagonal<S: HamelSystem>(
    system: &S,
    t: f64,
    x: &S::State,
) -> Option<Vec<f64>> {
    let n = S::Coordinates::LEN;
    let at = |k: Option<(usize, f64)>| {
        let mut state = *x;
        state.as_mut()[n..].fill(0.0);
        if let Some((k, s)) = k {
            state.as_mut()[n + k] = s;
        }
        system.energy(t, &state).ok()
    };
    let rest = at(None)?;
    (0..S::Speeds::LEN)
        .map(|k| Some(at(Some((k, 1.0)))? + at(Some((k, -1.0)))? - 2.0 * rest))
        .collect()
}

/// A singularity met during a run as an error. A singular mass matrix is a pivot zero beside
/// the matrix's trace; that is a speed whose inertia vanished, or another speed's inertia
/// that grew without bound (a slope that becomes infinite) and left the pivot zero beside
/// it. One matrix cannot tell the two apart (diag(1, 10⁻¹⁴) is diag(10¹⁴, 1) scaled); the
/// run's start can: the speed whose diagonal entry changed most since, in either direction,
/// is the one to name.
fn singular_in_run<S: HamelSystem>(
    system: &S,
    s: Singularity,
    t: f64,
    x: &S::State,
    start: Option<&[f64]>,
) -> Error {
    let Singularity::MassMatrix { speed, .. } = s else {
        return S::singular(s, t, x);
    };
    let (Some(start), Some(now)) = (start, inertia_diagonal(system, t, x)) else {
        return S::singular(s, t, x);
    };
    let growth: Vec<f64> = now.iter().zip(start).map(|(n, s)| n / s).collect();
    if growth.iter().any(|g| !(g.is_finite() && *g > 0.0)) {
        return S::singular(s, t, x);
    }
    let (grown, largest) = growth
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((speed, 1.0));
    // The failing speed's own shrinking against the largest growth, on a log scale.
    if grown != speed && largest.ln() > -growth[speed].ln() {
        return Error::UnboundedInertia {
            t,
            speed: S::SPEEDS
                .get(grown)
                .map_or_else(|| format!("#{grown}"), |n| (*n).to_string()),
            value: now[grown],
            growth: largest,
            state: S::named_state(x),
        };
    }
    S::singular(s, t, x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hand-written model whose `StateJacobian` has 15 entries for a state of 4: an error
    /// naming the sizes (it was a slice out of bounds, a panic).
    #[test]
    fn a_jacobian_of_the_wrong_shape_is_named() {
        assert_eq!(jacobian_shape((4, 1), (16, 4)), Ok(()));
        for wrong in [(15, 4), (16, 3), (4, 16)] {
            match jacobian_shape((4, 1), wrong) {
                Err(e @ Error::InconsistentModel { .. }) => {
                    let message = e.to_string();
                    assert!(
                        message.contains(&format!("∂F/∂x with {} entries", wrong.0))
                            && message.contains("need 16 and 4"),
                        "{message}"
                    );
                }
                other => panic!("{wrong:?}: {other:?}"),
            }
        }
    }
}
