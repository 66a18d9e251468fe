//! The linear-quadratic regulator of a linearization: u = u₀ − K (x − x₀) minimizing
//! ∫ δx'Q δx + δu'R δu, with K from the stabilizing solution of the Riccati equation
//! ([`solve_care`]), and the feedback law it gives a nonlinear run ([`StateFeedback`]).

use core::marker::PhantomData;

use nalgebra::{Complex, DMatrix, Schur};

use super::riccati::{Riccati, solve_care};
use super::{Controller, index_of};
use crate::error::Error;
use crate::linearization::Linearization;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// An LQR design on a [`Linearization`] δẋ = A δx + B δu: the gain K = R⁻¹B'P, the Riccati
/// solution P and the closed loop's eigenvalues (those of A − BK).
#[derive(Clone, Debug, PartialEq)]
pub struct Lqr {
    states: Vec<String>,
    inputs: Vec<String>,
    /// x₀ over `states` and u₀ over `inputs` (zeros for a linearization without an
    /// operating point).
    x0: Vec<f64>,
    u0: Vec<f64>,
    riccati: Riccati,
    closed_loop: Vec<Complex<f64>>,
}

impl Lqr {
    /// The regulator of `linearization` with the state weight `q` (S × S, symmetric positive
    /// semi-definite, over the linearization's states) and the input weight `r` (M × M,
    /// symmetric positive definite).
    ///
    /// Errors: those of [`solve_care`] — sizes that do not fit, weights that are not
    /// symmetric or (semi-)definite, no stabilizing solution ([`Error::NoStabilizingSolution`]
    /// says why) — and [`Error::EigenAnalysis`] should the closed loop's Schur form not
    /// converge.
    pub fn new(
        linearization: &Linearization,
        q: &DMatrix<f64>,
        r: &DMatrix<f64>,
    ) -> Result<Lqr, Error> {
        let (a, b) = (linearization.a_matrix(), linearization.b_matrix());
        let riccati = solve_care(a, b, q, r)?;
        let closed = a - b * &riccati.gain;
        let n = closed.nrows();
        let schur = Schur::try_new(closed, f64::EPSILON, 100 * n.max(1)).ok_or_else(|| {
            Error::EigenAnalysis {
                reason: "nalgebra's Schur decomposition of A - BK did not converge".to_string(),
            }
        })?;
        let mut closed_loop: Vec<Complex<f64>> =
            schur.complex_eigenvalues().iter().copied().collect();
        closed_loop.sort_by(|l, m| m.re.total_cmp(&l.re).then(m.im.total_cmp(&l.im)));
        let point = linearization.operating_point();
        let values = |named: Option<&crate::named::NamedValues>, len: usize| {
            named.map_or_else(|| vec![0.0; len], |v| v.0.iter().map(|(_, x)| *x).collect())
        };
        Ok(Lqr {
            states: linearization.states().to_vec(),
            inputs: linearization.inputs().to_vec(),
            x0: values(point.map(|p| &p.state), a.nrows()),
            u0: values(point.map(|p| &p.inputs), b.ncols()),
            riccati,
            closed_loop,
        })
    }

    /// The gain K (M × S): δu = −K δx.
    pub fn gain(&self) -> &DMatrix<f64> {
        &self.riccati.gain
    }

    /// The Riccati equation's stabilizing solution P, with its residual and steps.
    pub fn riccati(&self) -> &Riccati {
        &self.riccati
    }

    /// The eigenvalues of A − BK, the least stable first: all in the left half plane.
    pub fn closed_loop_eigenvalues(&self) -> &[Complex<f64>] {
        &self.closed_loop
    }

    /// The states the gain's columns are for.
    pub fn states(&self) -> &[String] {
        &self.states
    }

    /// The inputs the gain's rows are for.
    pub fn inputs(&self) -> &[String] {
        &self.inputs
    }

    /// The feedback law for runs of the model `S`, u = u₀ − K (x − x₀) on the states and
    /// inputs of the design, found in `S`'s by name; `S`'s other inputs are zero.
    ///
    /// Errors: [`Error::UnknownName`] for a state or input of the design that `S` does not
    /// have.
    pub fn feedback<S: HamelSystem>(&self) -> Result<StateFeedback<S>, Error> {
        let state_names = super::owned(S::STATE);
        let input_names = super::owned(S::INPUTS);
        let states = self
            .states
            .iter()
            .map(|s| index_of(&state_names, "state", s))
            .collect::<Result<_, _>>()?;
        let inputs = self
            .inputs
            .iter()
            .map(|u| index_of(&input_names, "input", u))
            .collect::<Result<_, _>>()?;
        Ok(StateFeedback {
            states,
            inputs,
            x0: self.x0.clone(),
            u0: self.u0.clone(),
            gain: self.riccati.gain.clone(),
            system: PhantomData,
        })
    }
}

/// A linear state feedback u = u₀ − K (x − x₀) on some of a model's states and inputs, from
/// [`Lqr::feedback`]: a [`Controller`] for [`crate::Simulation::run_controlled`].
#[derive(Clone, Debug)]
pub struct StateFeedback<S> {
    states: Vec<usize>,
    inputs: Vec<usize>,
    x0: Vec<f64>,
    u0: Vec<f64>,
    gain: DMatrix<f64>,
    system: PhantomData<fn() -> S>,
}

impl<S: HamelSystem> Controller<S> for StateFeedback<S> {
    fn control(&self, _t: f64, x: &S::State) -> Result<S::Inputs, Error> {
        let x = x.as_ref();
        let mut u = S::Inputs::zeros();
        for (row, &j) in self.inputs.iter().enumerate() {
            let correction: f64 = self
                .states
                .iter()
                .enumerate()
                .map(|(col, &i)| self.gain[(row, col)] * (x[i] - self.x0[col]))
                .sum();
            u.as_mut()[j] = self.u0[row] - correction;
        }
        Ok(u)
    }
}
