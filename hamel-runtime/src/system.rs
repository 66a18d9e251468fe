//! The traits a model implements: [`Parameters`] (generated from the parameter struct) and
//! [`HamelSystem`] (generated from the model's impl block by `#[hamel_system]`).

use crate::assembly;
use crate::builder::StateBuilder;
use crate::error::{Error, Singularity};
use crate::linearization::{self, Linearization};
use crate::named::NamedValues;
use crate::vector::Vector;

/// A model's parameters: a struct of named `f64` fields.
#[diagnostic::on_unimplemented(
    message = "`{Self}` does not describe its parameters",
    label = "annotate the parameter struct `{Self}` with `#[hamel_system]`",
    note = "`#[hamel_system]` goes on both the parameter struct and the model's impl block"
)]
pub trait Parameters {
    /// Field names, in declaration order.
    const NAMES: &'static [&'static str];
    /// The fields' doc comments (empty where there is none), for `--help` texts.
    const DOCS: &'static [&'static str];
    /// The parameter struct's own doc comment, its lines kept (empty where there is none):
    /// the model's description, which the Python package makes its class's docstring.
    const DOC: &'static str = "";

    /// The value of the parameter `name`.
    fn get(&self, name: &str) -> Option<f64>;

    /// Set a parameter by name; an unknown name is an error that lists the known ones, a
    /// value that is not a finite number an [`Error::InvalidParameter`] (the parameter keeps
    /// its value).
    fn set(&mut self, name: &str, value: f64) -> Result<(), Error>;

    /// Every parameter must be a finite number.
    fn validate(&self) -> Result<(), Error> {
        for name in Self::NAMES {
            let value = self.get(name).unwrap_or(f64::NAN);
            if !value.is_finite() {
                return Err(Error::InvalidParameter {
                    name: (*name).to_string(),
                    value,
                });
            }
        }
        Ok(())
    }

    /// The unit of the parameter `name`, as its doc comment ends: `/// wheelbase (m)` gives
    /// `m`. `None` for an unknown name or a comment without a unit in parentheses at its end.
    fn parameter_unit(name: &str) -> Option<&'static str> {
        let i = Self::NAMES.iter().position(|n| *n == name)?;
        unit_in_doc(Self::DOCS.get(i)?)
    }

    /// All parameters with their names (for `Debug`-style reports).
    fn parameter_values(&self) -> NamedValues {
        let values: Vec<f64> = Self::NAMES
            .iter()
            .map(|n| self.get(n).unwrap_or(f64::NAN))
            .collect();
        NamedValues::new(Self::NAMES, &values)
    }
}

/// A nonholonomic mechanical system with n coordinates and p constraints, reduced by Hamel's
/// equations to an ODE of dimension 2n − p in the state x = (q, ω_{p+1}, …, ω_n): the
/// coordinates and the quasi-velocities that are not constrained.
///
/// The constraint rows may be affine in the velocities and depend on the time,
/// A_c(q, t) q̇ + a_c(q, t) = 0; k of the p rows may be the time derivatives of holonomic
/// constraints f(t, q) = 0, each of which determines one coordinate ([`Self::DEPENDENT`]).
/// Every method that can depend on the time takes it.
///
/// Implemented by `#[hamel_system]`; the methods are straight-line code generated from the
/// model's Lagrangian, constraints and forces.
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a hamel model",
    label = "`{Self}` needs `#[hamel_system(coordinates(..))]` on its impl block",
    note = "put `#[hamel_system(coordinates(..))]` on the impl block of `{Self}` that holds all its role functions (`#[kinetic_energy]`, `#[constraints]`, `#[quasi_velocities]`, ..)"
)]
pub trait HamelSystem: Parameters {
    /// `[f64; n]`
    type Coordinates: Vector;
    /// `[f64; n − p]`: the free quasi-velocities ("speeds").
    type Speeds: Vector;
    /// `[f64; p]`
    type Constraints: Vector;
    /// `[f64; 2n − p]`
    type State: Vector;
    /// `[f64; m]`: the inputs (motor torques, ...).
    type Inputs: Vector;
    /// `[f64; k]`: the holonomic constraints f(t, q).
    type Holonomic: Vector;
    /// `[f64; k·n]`: ∂f/∂q, row by row.
    type HolonomicJacobian: Vector;
    /// `[f64; 2n − p + 1]`: the state and, last, the work done on the system since the start
    /// (what a simulation integrates to check the energy balance).
    type Extended: Vector;
    /// `[[f64; n − p]; n − p]`
    type MassMatrix: Copy + core::fmt::Debug;
    /// `[[[f64; n − p]; n − p]; n]`: γʲ_{l,k} for j = 1…n and l, k = p+1…n.
    type Gamma: Copy + core::fmt::Debug;
    /// `[f64; (2n − p)²]`: ∂F/∂x of the right-hand side, row by row.
    type StateJacobian: Vector;
    /// `[f64; (2n − p)·m]`: ∂F/∂u, row by row.
    type InputJacobian: Vector;

    /// n, the number of generalized coordinates.
    const N: usize;
    /// p, the number of constraints, holonomic ones included (the state has 2n − p
    /// components).
    const P: usize;
    /// m, the number of inputs.
    const M: usize;
    /// k, the number of holonomic constraints (the last k of the p constraint rows are their
    /// time derivatives).
    const K: usize;

    /// Names of the coordinates q.
    const COORDINATES: &'static [&'static str];
    /// Names of the free quasi-velocities.
    const SPEEDS: &'static [&'static str];
    /// Names of the constraints: the rows of the constraint function, then those of the
    /// holonomic function, as named in `#[hamel_system(constraints(..))]` (`blade`), or by
    /// default after the functions and the rows' indices (`blade0`, `contact0_x`).
    const CONSTRAINTS: &'static [&'static str];
    /// Names of the inputs.
    const INPUTS: &'static [&'static str];
    /// Names of the state components: the coordinates, then the speeds.
    const STATE: &'static [&'static str];
    /// The coordinates the holonomic constraints determine (indices into q), one per
    /// holonomic constraint, in the model's order.
    const DEPENDENT: &'static [usize];
    /// Whether the energy is an integral of the motion: no forces, no affine part in the
    /// rows, nothing that depends on the time explicitly. Otherwise a simulation checks the
    /// energy balance E(t) − E(t₀) = ∫ P dt with the power [`Self::power`].
    const CONSERVATIVE: bool;
    /// Whether the power [`Self::power`] vanishes identically when every input is zero: the
    /// model is driven by its inputs alone (motor torques), with no other force, no affine
    /// part in the rows and no explicit time dependence doing work. A run with zero constant
    /// inputs then does no work on it, and its energy balance is its energy drift
    /// ([`crate::Simulation::run_constant`] integrates no work). `#[hamel_system]` finds it on
    /// the power's expression; the default, `false`, claims nothing.
    const POWER_VANISHES_WITHOUT_INPUTS: bool = false;
    /// Whether the reduced ODE is reversible: ρ(q, ω) = (q, −ω) maps its solutions to
    /// solutions run backwards in time, so that a symmetric integrator
    /// ([`crate::GaussLegendre`], [`crate::ImplicitMidpoint`]) is ρ-reversible on it and keeps
    /// its energy error bounded over long runs. `#[hamel_system]` sets it when the model is
    /// [`Self::CONSERVATIVE`], its Lagrangian is a quadratic form in the velocities plus a part
    /// without them (the kinetic energy, the bodies', L or L̃ as written: no term linear in
    /// q̇), and every row — constraints, holonomic ones, quasi-velocities — is homogeneous in q̇
    /// and does not depend on the time. It is about the model whatever its inputs: a model with
    /// `#[forces]` is not reversible even when they vanish. The default, for a hand-written
    /// implementation, is `false`.
    const REVERSIBLE: bool = false;

    /// The units of the model's named quantities, as `#[hamel_system(units(x = "m", ..))]`
    /// gives them: pairs of a name (a coordinate, speed or input, `t`, or `energy`) and its
    /// unit. Figures label their axes with them ([`Self::unit`]).
    const UNITS: &'static [(&'static str, &'static str)] = &[];

    /// How many values of the right-hand side depend on the parameters alone
    /// ([`Self::prepare`]); 0 for a system that prepares nothing.
    const PREPARED_LEN: usize = 0;

    /// Whether det A(q, t) — the constraint rows over the quasi-velocity rows — depends on the
    /// parameters alone, so that no motion can cross a configuration where A is singular and
    /// a simulation need not watch for one ([`crate::Simulation::watch_singular_crossings`]).
    /// `#[hamel_system]` knows it when it derives B from A; the default, `false`, keeps the
    /// watch.
    const TRANSFORMATION_DETERMINANT_CONSTANT: bool = false;

    /// The unit of a named quantity ([`Self::UNITS`]): a coordinate, speed or input, `t`,
    /// or `energy`; `energy_balance` has the energy's. `None` where the model states none.
    fn unit(name: &str) -> Option<&'static str> {
        let name = if name == "energy_balance" {
            "energy"
        } else {
            name
        };
        Self::UNITS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, u)| *u)
    }

    /// The right-hand side ẋ = F(t, x, u) of the reduced ODE. No heap allocation.
    fn rhs(
        &self,
        t: f64,
        x: &Self::State,
        u: &Self::Inputs,
        dx: &mut Self::State,
    ) -> Result<(), Singularity>;

    /// Computes the values of the right-hand side that depend on the parameters alone
    /// (products and quotients of masses and lengths, a constant block of the mass
    /// matrix and its inverse) into `prepared`, which must have [`Self::PREPARED_LEN`]
    /// entries: once per parameter set, for [`Self::rhs_prepared`]. A slice of another
    /// length is left as it is.
    fn prepare(&self, prepared: &mut [f64]) {
        let _ = prepared;
    }

    /// [`Self::rhs`] reading the values [`Self::prepare`] computed instead of computing
    /// them: the same result, bit for bit, for the parameters they were prepared with. A
    /// simulation prepares once and calls this at every stage. With a `prepared` of the
    /// wrong length it is [`Self::rhs`]. No heap allocation.
    fn rhs_prepared(
        &self,
        prepared: &[f64],
        t: f64,
        x: &Self::State,
        u: &Self::Inputs,
        dx: &mut Self::State,
    ) -> Result<(), Singularity> {
        let _ = prepared;
        self.rhs(t, x, u, dx)
    }

    /// [`Self::rhs_prepared`] and [`Self::power`] at once: ẋ into `dx` (the same bits as
    /// `rhs_prepared`), the power returned (as `power` to rounding: it may read values the
    /// right-hand side shares). `#[hamel_system]` computes them in one pass, the power
    /// reading the q̇ the right-hand side computes (a simulation of a model that is not
    /// conservative calls this at every stage, to integrate the work done); the default
    /// calls the two. No heap allocation.
    fn rhs_power_prepared(
        &self,
        prepared: &[f64],
        t: f64,
        x: &Self::State,
        u: &Self::Inputs,
        dx: &mut Self::State,
    ) -> Result<f64, Singularity> {
        self.rhs_prepared(prepared, t, x, u, dx)?;
        self.power(t, x, u)
    }

    /// The generalized velocities q̇ = B(q, t)(ω − a(q, t)) of a state, ω = (0, speeds).
    fn generalized_velocities(
        &self,
        t: f64,
        x: &Self::State,
    ) -> Result<Self::Coordinates, Singularity>;

    /// The energy E = q̇·∂L/∂q̇ − L of a state (T + V when the kinetic energy is a quadratic
    /// form in q̇).
    fn energy(&self, t: f64, x: &Self::State) -> Result<f64, Singularity>;

    /// The rate of change of the energy along the motion, from its causes:
    /// dE/dt = f·q̇ − λᵀa_c − ∂L/∂t (the power of the forces, of the constraint forces of
    /// affine or moving constraints, and of an explicit time dependence of L).
    fn power(&self, t: f64, x: &Self::State, u: &Self::Inputs) -> Result<f64, Singularity>;

    /// The Lagrange multipliers λ of d/dt ∂L/∂q̇ − ∂L/∂q = f + A_cᵀ λ, one per constraint
    /// row, as generated: no check of the arguments (see [`Self::constraint_forces`], which
    /// checks them first).
    fn multipliers(
        &self,
        t: f64,
        x: &Self::State,
        u: &Self::Inputs,
    ) -> Result<Self::Constraints, Singularity>;

    /// The constraint forces: the Lagrange multipliers λ of
    /// d/dt ∂L/∂q̇ − ∂L/∂q = f + A_cᵀ λ, one per constraint row ([`Self::multipliers`]). The
    /// generalized reaction force is A_cᵀ λ; λ_j has the units of a force (or torque)
    /// divided by those of row j's velocity terms per unit velocity, e.g. newtons for a row
    /// that is a velocity in m/s.
    ///
    /// Errors: [`Error::NonFiniteArgument`] naming a time, state component or input that is
    /// not finite; [`Error::InvalidParameter`]; [`Error::HolonomicViolation`] naming the
    /// holonomic constraint the configuration misses (by more than
    /// [`crate::HOLONOMIC_TOLERANCE`] of its scale, as for [`Self::state_from_speeds`]): the
    /// multipliers of a state no motion passes through mean nothing; the singularity met,
    /// named with the time and state ([`Self::singular`]).
    fn constraint_forces(
        &self,
        t: f64,
        x: &Self::State,
        u: &Self::Inputs,
    ) -> Result<Self::Constraints, Error> {
        check_arguments::<Self>("constraint_forces", t, x, u)?;
        self.validate()?;
        assembly::check(self, t, &Self::coordinates_of(x))?;
        self.multipliers(t, x, u)
            .map_err(|s| Self::singular(s, t, x))
    }

    /// The constraint rows A_c(q, t) q̇ + a_c(q, t) (zero on every admissible motion).
    fn constraint_residual(
        &self,
        t: f64,
        q: &Self::Coordinates,
        qd: &Self::Coordinates,
    ) -> Self::Constraints;

    /// The free quasi-velocities ω_{p+1…n} = A_f(q, t) q̇ + a_f(q, t).
    fn speeds(&self, t: f64, q: &Self::Coordinates, qd: &Self::Coordinates) -> Self::Speeds;

    /// The holonomic constraints f(t, q) (zero on every admissible configuration).
    fn holonomic_residual(&self, t: f64, q: &Self::Coordinates) -> Self::Holonomic;

    /// ∂f/∂q at (t, q), row-major (k rows of n).
    fn holonomic_jacobian(&self, t: f64, q: &Self::Coordinates) -> Self::HolonomicJacobian;

    /// The reduced mass matrix M_kl = ∂²L̃/∂ω_k∂ω_l (k, l > p) at a state.
    fn mass_matrix(&self, t: f64, x: &Self::State) -> Result<Self::MassMatrix, Singularity>;

    /// The coefficients γʲ_{l,k} of Hamel's equations at a configuration.
    fn gamma(&self, t: f64, q: &Self::Coordinates) -> Result<Self::Gamma, Singularity>;

    /// max |(A(q, t)·B(q, t) − I)ᵢⱼ| and |A·Q₀ + a| when the model gives the inverse in
    /// closed form: how far the given inverse is from being one (zero when B is computed
    /// from A).
    fn inverse_defect(&self, t: f64, q: &Self::Coordinates) -> Result<f64, Singularity>;

    /// The Jacobians ∂F/∂x and ∂F/∂u of the right-hand side at (t, x, u), row-major: dual
    /// numbers run through the generated right-hand side (`rhs_generic`), so they are exact
    /// to rounding, through the unrolled factorizations and their pivot choices.
    fn jacobian(
        &self,
        t: f64,
        x: &Self::State,
        u: &Self::Inputs,
    ) -> Result<(Self::StateJacobian, Self::InputJacobian), Singularity>;

    /// ∂F/∂t of the right-hand side at (t, x, u), for the Rosenbrock integrators: generated as
    /// one more pass of dual numbers with t seeded (`time_derivative_by_duals`), or zeros
    /// without a pass for a right-hand side that does not depend on t. `None`, the default of
    /// a hand-written implementation, lets the integrators difference F in t.
    fn time_derivative(
        &self,
        _t: f64,
        _x: &Self::State,
        _u: &Self::Inputs,
    ) -> Result<Option<Self::State>, Singularity> {
        Ok(None)
    }

    /// The linearization δẋ = A δx + B δu of the right-hand side at the operating point
    /// (t, x, u), with the state and input names (from [`Self::jacobian`]), and the holonomic
    /// constraints' ∂f/∂q there, with which [`Linearization::reduce`] eliminates dependent
    /// coordinates.
    ///
    /// Errors: [`Error::NonFiniteOperatingPoint`] naming a time (`t`), state component or
    /// input that is not finite; [`Error::InvalidParameter`]; a body or contact that cannot be
    /// ([`Error::UnphysicalBody`], [`Error::ImpossibleGeometry`], as [`Self::check_bodies`]
    /// finds them); [`Error::HolonomicViolation`]
    /// when the configuration does not satisfy a holonomic constraint (to
    /// [`crate::HOLONOMIC_TOLERANCE`] of its scale, as for [`Self::state_from_speeds`]); the
    /// singularity met, named with the time and state ([`Self::singular`]);
    /// [`Error::NonFiniteDerivative`] naming a derivative that is not finite;
    /// [`Error::InconsistentModel`] for a hand-written implementation whose sizes disagree.
    fn linearize(&self, t: f64, x: &Self::State, u: &Self::Inputs) -> Result<Linearization, Error> {
        linearization::linearize(self, t, x, u)
    }

    /// That the model's rigid bodies (`#[bodies]`) at (t, q) are bodies matter could make: a
    /// positive mass, an inertia tensor positive semi-definite whose principal moments satisfy
    /// the triangle inequalities ([`crate::geometry::check_bodies`]); an
    /// [`Error::UnphysicalBody`] names the first that is not. And that their orientations,
    /// shapes and contacts (`#[contacts]`) are geometry a body can have: rotations, shapes
    /// of positive size, surfaces of positive radius, points that exist
    /// ([`crate::geometry::check_contacts`]); an [`Error::ImpossibleGeometry`] names the
    /// first that is not. `#[hamel_system]` implements it for a model with `#[bodies]`; the
    /// default checks nothing.
    fn check_bodies(&self, t: f64, q: &Self::Coordinates) -> Result<(), Error> {
        let _ = (t, q);
        Ok(())
    }

    /// Check the parameters and the bodies they make ([`Self::check_bodies`]), and that a
    /// closed-form inverse B really inverts A at (t, q).
    fn check_configuration(&self, t: f64, q: &Self::Coordinates) -> Result<(), Error> {
        self.validate()?;
        check_finite(Self::COORDINATES, q.as_ref(), "")?;
        self.check_bodies(t, q)?;
        let defect = self.inverse_defect(t, q).map_err(|s| {
            s.at(
                t,
                NamedValues::new(Self::COORDINATES, q.as_ref()),
                Self::COORDINATES,
                Self::SPEEDS,
            )
        })?;
        // A NaN defect (a NaN parameter slipped through) is a mismatch too.
        if defect.is_nan() || defect > INVERSE_TOLERANCE {
            return Err(Error::InverseMismatch {
                defect,
                configuration: NamedValues::new(Self::COORDINATES, q.as_ref()),
            });
        }
        Ok(())
    }

    /// The configuration that satisfies the holonomic constraints f(t, q) = 0 at time `t`,
    /// solved for the coordinates [`Self::DEPENDENT`] with the others held at their values in
    /// `q`, by Newton's method starting from the dependent coordinates' values in `q` (so
    /// their sign or branch picks the root). Converged when every |fᵢ| is at most
    /// [`crate::ASSEMBLY_TOLERANCE`] times its scale Σⱼ |∂fᵢ/∂qⱼ|·max(|qⱼ|, 1), after which one
    /// more Newton step polishes the root to rounding; a `q` that satisfies them exactly comes
    /// back unchanged, and so does every `q` when K = 0.
    ///
    /// Errors: a time, parameter or coordinate that is not finite names it;
    /// [`Error::Assembly`] names the constraint, the coordinate to guess better, the time and
    /// the configuration when the derivative block is singular, a value is not finite or
    /// Newton's method does not converge (it halves steps that would not reduce the residual,
    /// so a guess on the right branch converges).
    fn assemble(&self, t: f64, q: &Self::Coordinates) -> Result<Self::Coordinates, Error> {
        if Self::K == 0 {
            return Ok(*q);
        }
        if !t.is_finite() {
            return Err(Error::InvalidSetting {
                name: "time",
                value: t,
                reason: "the time must be a finite number",
            });
        }
        self.validate()?;
        check_finite(Self::COORDINATES, q.as_ref(), "")?;
        // A body or contact that cannot be is named before Newton's method meets it as a
        // residual that does not converge (a ball larger than its bowl).
        self.check_bodies(t, q)?;
        assembly::newton(self, t, q)
    }

    /// The state of a configuration and velocities at time `t`, after checking that the
    /// parameters and values are finite, that the configuration satisfies the holonomic
    /// constraints (to [`crate::HOLONOMIC_TOLERANCE`] of their scale, see
    /// [`Self::assemble`]), that the velocities satisfy the constraints and that the reduced
    /// mass matrix is not indefinite there ([`Error::IndefiniteMassMatrix`]: parameters no
    /// physical system has). A singular one is left to the run, which names the time.
    fn state_from_velocities(
        &self,
        t: f64,
        q: &Self::Coordinates,
        qd: &Self::Coordinates,
    ) -> Result<Self::State, Error> {
        self.check_configuration(t, q)?;
        assembly::check(self, t, q)?;
        check_finite(Self::COORDINATES, qd.as_ref(), "d/dt ")?;
        let residual = self.constraint_residual(t, q, qd);
        let scale = qd.as_ref().iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let tolerance = CONSTRAINT_TOLERANCE * scale;
        for (name, r) in Self::CONSTRAINTS.iter().zip(residual.as_ref()) {
            if r.is_nan() || r.abs() > tolerance {
                return Err(Error::ConstraintViolation {
                    name: (*name).to_string(),
                    residual: *r,
                    tolerance,
                });
            }
        }
        let speeds = self.speeds(t, q, qd);
        let x = join::<Self>(q, &speeds);
        check_inertia(self, t, &x)?;
        Ok(x)
    }

    /// The state of a configuration and the free quasi-velocities at time `t` (always
    /// admissible), after checking that the parameters and values are finite, that the
    /// configuration satisfies the holonomic constraints and that the reduced mass matrix is
    /// not indefinite (see [`Self::state_from_velocities`]).
    fn state_from_speeds(
        &self,
        t: f64,
        q: &Self::Coordinates,
        speeds: &Self::Speeds,
    ) -> Result<Self::State, Error> {
        self.check_configuration(t, q)?;
        assembly::check(self, t, q)?;
        check_finite(Self::SPEEDS, speeds.as_ref(), "")?;
        let x = join::<Self>(q, speeds);
        check_inertia(self, t, &x)?;
        Ok(x)
    }

    /// A builder of a state by the names of its coordinates and speeds, which solves the
    /// dependent coordinates with [`Self::assemble`]: `system.state_builder().set("x",
    /// 1.2).set("v", 1.5).build()`.
    fn state_builder(&self) -> StateBuilder<'_, Self>
    where
        Self: Sized,
    {
        StateBuilder::new(self)
    }

    /// The coordinates part of a state.
    fn coordinates_of(x: &Self::State) -> Self::Coordinates {
        let mut q = Self::Coordinates::zeros();
        let n = Self::Coordinates::LEN;
        q.as_mut().copy_from_slice(&x.as_ref()[..n]);
        q
    }

    /// The speeds part of a state.
    fn speeds_of(x: &Self::State) -> Self::Speeds {
        let mut w = Self::Speeds::zeros();
        let n = Self::Coordinates::LEN;
        w.as_mut().copy_from_slice(&x.as_ref()[n..]);
        w
    }

    /// The error for a singularity met at time `t` in state `x`, with everything named.
    fn singular(s: Singularity, t: f64, x: &Self::State) -> Error {
        s.at(t, Self::named_state(x), Self::COORDINATES, Self::SPEEDS)
    }

    /// A state with its component names, for messages and `Debug` output.
    fn named_state(x: &Self::State) -> NamedValues {
        NamedValues::new(Self::STATE, x.as_ref())
    }
}

/// Largest entry of A·B − I accepted from a closed-form inverse: rounding, not a typo.
pub const INVERSE_TOLERANCE: f64 = 1e-9;

/// Relative tolerance on the constraint residual of initial velocities (scaled by the
/// largest velocity component, or 1): rounding, not modelling, errors pass.
pub const CONSTRAINT_TOLERANCE: f64 = 1e-10;

/// The time, state and inputs given to `function` must be finite: the first that is not is
/// named.
fn check_arguments<S: HamelSystem + ?Sized>(
    function: &'static str,
    t: f64,
    x: &S::State,
    u: &S::Inputs,
) -> Result<(), Error> {
    let named = core::iter::once(("t", t))
        .chain(S::STATE.iter().copied().zip(x.as_ref().iter().copied()))
        .chain(S::INPUTS.iter().copied().zip(u.as_ref().iter().copied()));
    for (name, value) in named {
        if !value.is_finite() {
            return Err(Error::NonFiniteArgument {
                function,
                name: name.to_string(),
                value,
            });
        }
    }
    Ok(())
}

fn check_finite(names: &[&str], values: &[f64], prefix: &str) -> Result<(), Error> {
    for (name, v) in names.iter().zip(values) {
        if !v.is_finite() {
            return Err(Error::NonFiniteInitialValue {
                name: format!("{prefix}{name}"),
                value: *v,
            });
        }
    }
    Ok(())
}

/// A state at which the reduced mass matrix is indefinite is refused when it is built, not
/// left for the first step: the kinetic energy of some admissible motion is negative there,
/// which says the parameters (or the kinetic energy) are wrong, not where a run went. The
/// right-hand side, with zero inputs (they do not enter the matrix), runs the generated
/// pivot checks; its other singularities, which a run meets and reports with the time, do not
/// stop a state being built (a singular transformation comes first and hides the matrix).
fn check_inertia<S: HamelSystem + ?Sized>(system: &S, t: f64, x: &S::State) -> Result<(), Error> {
    let mut dx = S::State::zeros();
    match system.rhs(t, x, &S::Inputs::zeros(), &mut dx) {
        Err(s @ Singularity::IndefiniteMassMatrix { .. }) => Err(S::singular(s, t, x)),
        _ => Ok(()),
    }
}

fn join<S: HamelSystem + ?Sized>(q: &S::Coordinates, w: &S::Speeds) -> S::State {
    let mut x = S::State::zeros();
    let n = S::Coordinates::LEN;
    x.as_mut()[..n].copy_from_slice(q.as_ref());
    x.as_mut()[n..].copy_from_slice(w.as_ref());
    x
}

/// The unit a parameter's doc comment ends with, in parentheses: "wheelbase (m)" gives "m",
/// "rear frame centre of mass, z (negative: above the ground) (m)" gives "m".
fn unit_in_doc(doc: &str) -> Option<&str> {
    let inner = doc.trim().strip_suffix(')')?;
    let open = inner.rfind('(')?;
    let unit = inner[open + 1..].trim();
    // A unit is short and has no spaces between words of prose ("(kg m²)" is one).
    (!unit.is_empty() && unit.len() <= 16 && !unit.contains(':')).then_some(unit)
}

#[cfg(test)]
mod unit_tests {
    use super::unit_in_doc;

    #[test]
    fn units_are_read_from_the_end_of_doc_comments() {
        assert_eq!(unit_in_doc("wheelbase (m)"), Some("m"));
        assert_eq!(
            unit_in_doc("rear wheel moment of inertia about its axle (kg m²)"),
            Some("kg m²")
        );
        assert_eq!(
            unit_in_doc("centre of mass, z (negative: above the ground) (m)"),
            Some("m")
        );
        assert_eq!(
            unit_in_doc("gravitational acceleration (m/s²) "),
            Some("m/s²")
        );
        assert_eq!(unit_in_doc("mass"), None);
        assert_eq!(unit_in_doc("the height (negative: above the ground)"), None);
        assert_eq!(unit_in_doc("()"), None);
    }
}
