//! The linearization δẋ = A δx + B δu of a system's reduced ODE ẋ = F(t, x, u) about an
//! operating point (t, x₀, u₀), with the state and input names attached: A = ∂F/∂x and
//! B = ∂F/∂u, named as in python-control's `StateSpace` and SymPy's `Linearizer`.
//!
//! A linearization is off the hot path, so it lives on the heap (`DMatrix`), and its size is
//! whatever [`Linearization::reduce`] leaves of the state. Its modes are in
//! [`crate::modes`].

use core::fmt;

use nalgebra::DMatrix;

use crate::assembly;
use crate::error::{Error, Num};
use crate::named::NamedValues;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// A kept state "does not depend" on a dropped one when the derivative is at most
/// `CYCLIC_TOLERANCE` times the largest |Aᵢⱼ|: a structural zero computed through
/// cancelling terms leaves rounding of that order, a real dependence does not.
pub const CYCLIC_TOLERANCE: f64 = 1e-12;

/// An LU pivot of the row-scaled constraint block below this is rounding of the row's largest
/// entry (which is 1): the constraints do not determine the coordinate.
const SINGULAR_PIVOT: f64 = 16.0 * f64::EPSILON;

/// Where a linearization was taken: the time, the state and the inputs, with their names.
#[derive(Clone, Debug, PartialEq)]
pub struct OperatingPoint {
    /// The time t.
    pub t: f64,
    /// The state x₀ (after [`Linearization::reduce`], its kept components).
    pub state: NamedValues,
    /// The inputs u₀.
    pub inputs: NamedValues,
}

impl fmt::Display for OperatingPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "t = {}; state: ", Num(self.t))?;
        write_values(f, &self.state)?;
        f.write_str("; inputs: ")?;
        write_values(f, &self.inputs)
    }
}

fn write_values(f: &mut fmt::Formatter<'_>, values: &NamedValues) -> fmt::Result {
    if values.0.is_empty() {
        return f.write_str("none");
    }
    for (i, (name, value)) in values.0.iter().enumerate() {
        let separator = if i > 0 { ", " } else { "" };
        write!(f, "{separator}{name} = {}", Num(*value))?;
    }
    Ok(())
}

/// The holonomic constraints linearized at the operating point, ∂f/∂x δx = 0 (zero in the
/// speeds' columns): what [`Linearization::reduce`] eliminates dependent coordinates with.
#[derive(Clone, PartialEq)]
struct Constraints {
    names: Vec<String>,
    /// The state each constraint determines (index into the states).
    dependent: Vec<usize>,
    /// k × S, over the linearization's states.
    jacobian: DMatrix<f64>,
}

/// The linearization δẋ = A δx + B δu of ẋ = F(t, x, u) at an operating point, from
/// [`HamelSystem::linearize`] (or [`Linearization::new`] for given matrices): A = ∂F/∂x with
/// the state names on its rows (the rates of the states) and columns, B = ∂F/∂u with the
/// input names on its columns.
///
/// `Display` prints both as aligned tables with four significant digits; `Debug` is a
/// summary.
#[derive(Clone, PartialEq)]
pub struct Linearization {
    states: Vec<String>,
    inputs: Vec<String>,
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    point: Option<OperatingPoint>,
    constraints: Constraints,
}

/// [`HamelSystem::linearize`]: checks the sizes the implementation declares, the operating
/// point, the parameters and the holonomic constraints, then takes the system's Jacobian and,
/// for [`Linearization::reduce`], the holonomic constraints' at the operating point.
pub(crate) fn linearize<S: HamelSystem + ?Sized>(
    system: &S,
    t: f64,
    x: &S::State,
    u: &S::Inputs,
) -> Result<Linearization, Error> {
    check_sizes::<S>()?;
    let point = OperatingPoint {
        t,
        state: S::named_state(x),
        inputs: NamedValues::new(S::INPUTS, u.as_ref()),
    };
    let time = ("t".to_string(), t);
    for (name, value) in core::iter::once(&time)
        .chain(&point.state.0)
        .chain(&point.inputs.0)
    {
        if !value.is_finite() {
            return Err(Error::NonFiniteOperatingPoint {
                name: name.clone(),
                value: *value,
            });
        }
    }
    // The parameters, and the bodies and contacts they make, as a run's start checks them:
    // a linearization of a body no matter makes is as meaningless as its run.
    system.check_configuration(t, &S::coordinates_of(x))?;
    // Eliminating a dependent coordinate through the constraints' linearization assumes
    // f = 0 at the operating point, as every state a simulation starts from satisfies.
    assembly::check(system, t, &S::coordinates_of(x))?;
    let (a, b) = system.jacobian(t, x, u).map_err(|s| S::singular(s, t, x))?;
    let (s, m) = (S::State::LEN, S::Inputs::LEN);
    let a = DMatrix::from_row_slice(s, s, a.as_ref());
    let b = DMatrix::from_row_slice(s, m, b.as_ref());
    let constraints = holonomic::<S>(system, t, x);
    let at = format!("at the operating point {point}");
    let linearization = Linearization {
        states: owned(S::STATE),
        inputs: owned(S::INPUTS),
        a,
        b,
        point: Some(point),
        constraints,
    };
    linearization.check_finite(&at)?;
    Ok(linearization)
}

/// The sizes a hand-written implementation could get wrong, so that they are an error rather
/// than an index out of bounds or a silently truncated name list.
fn check_sizes<S: HamelSystem + ?Sized>() -> Result<(), Error> {
    let (s, m) = (S::State::LEN, S::Inputs::LEN);
    let fits = S::StateJacobian::LEN == s * s
        && S::InputJacobian::LEN == s * m
        && S::STATE.len() == s
        && S::INPUTS.len() == m
        && S::COORDINATES.len() == S::Coordinates::LEN
        && S::Coordinates::LEN <= s;
    if !fits {
        return Err(Error::InconsistentModel {
            what: format!(
                "the state has {s} components and names {}, the inputs {m} and names {}, the \
                 coordinates {} and names {}, but `StateJacobian` has {} components (should be \
                 {}) and `InputJacobian` {} (should be {})",
                S::STATE.len(),
                S::INPUTS.len(),
                S::Coordinates::LEN,
                S::COORDINATES.len(),
                S::StateJacobian::LEN,
                s * s,
                S::InputJacobian::LEN,
                s * m
            ),
        });
    }
    assembly::check_shape::<S>()
}

/// ∂f/∂q of the holonomic constraints at the operating point, over the state (the
/// coordinates come first in it; the speeds' columns are zero).
fn holonomic<S: HamelSystem + ?Sized>(system: &S, t: f64, x: &S::State) -> Constraints {
    let (n, s, k) = (S::Coordinates::LEN, S::State::LEN, S::K);
    let q = S::coordinates_of(x);
    let derivative = system.holonomic_jacobian(t, &q);
    let mut jacobian = DMatrix::zeros(k, s);
    for row in 0..k {
        for column in 0..n {
            jacobian[(row, column)] = derivative.as_ref()[row * n + column];
        }
    }
    Constraints {
        names: (0..k).map(assembly::constraint_name::<S>).collect(),
        dependent: S::DEPENDENT.to_vec(),
        jacobian,
    }
}

fn owned(names: &[&str]) -> Vec<String> {
    names.iter().map(|n| (*n).to_string()).collect()
}

impl Linearization {
    /// The linearization with state matrix `a` (S × S) and input matrix `b` (S × M) of a
    /// system with these state and input names, without an operating point or holonomic
    /// constraints: for matrices from elsewhere.
    ///
    /// Errors: [`Error::DimensionMismatch`] when the sizes do not fit the names,
    /// [`Error::DuplicateName`] for a name given twice, [`Error::NonFiniteDerivative`]
    /// naming an entry that is not a finite number.
    pub fn new(
        states: &[&str],
        inputs: &[&str],
        a: DMatrix<f64>,
        b: DMatrix<f64>,
    ) -> Result<Self, Error> {
        let (s, m) = (states.len(), inputs.len());
        if a.shape() != (s, s) || b.shape() != (s, m) {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "{s} states and {m} inputs need A of {s} × {s} and B of {s} × {m}, not \
                     {} × {} and {} × {}",
                    a.nrows(),
                    a.ncols(),
                    b.nrows(),
                    b.ncols()
                ),
            });
        }
        for (kind, names) in [("state", states), ("input", inputs)] {
            let duplicate = (0..names.len()).find(|&i| names[..i].contains(&names[i]));
            if let Some(i) = duplicate {
                return Err(Error::DuplicateName {
                    kind,
                    name: names[i].to_string(),
                    context: "each state and input needs a name of its own",
                });
            }
        }
        let linearization = Linearization {
            states: owned(states),
            inputs: owned(inputs),
            a,
            b,
            point: None,
            constraints: Constraints {
                names: Vec::new(),
                dependent: Vec::new(),
                jacobian: DMatrix::zeros(0, s),
            },
        };
        linearization.check_finite("in the matrices given to `Linearization::new`")?;
        Ok(linearization)
    }

    /// The first entry of A, B or the constraints' Jacobian that is not a finite number.
    fn check_finite(&self, at: &str) -> Result<(), Error> {
        let c = &self.constraints;
        let rates: Vec<String> = self
            .states
            .iter()
            .map(|name| format!("the rate of `{name}`"))
            .collect();
        let constraints: Vec<String> = c
            .names
            .iter()
            .map(|name| format!("the holonomic constraint `{name}`"))
            .collect();
        let matrices = [
            (&self.a, &rates, &self.states),
            (&self.b, &rates, &self.inputs),
            (&c.jacobian, &constraints, &self.states),
        ];
        for (matrix, rows, columns) in matrices {
            for (row, of) in rows.iter().enumerate() {
                for (column, by) in columns.iter().enumerate() {
                    let value = matrix[(row, column)];
                    if !value.is_finite() {
                        return Err(Error::NonFiniteDerivative {
                            of: of.clone(),
                            by: by.clone(),
                            value,
                            at: at.to_string(),
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// The state names: A's rows (the rates of the states) and columns, B's rows.
    pub fn states(&self) -> &[String] {
        &self.states
    }

    /// The input names: B's columns.
    pub fn inputs(&self) -> &[String] {
        &self.inputs
    }

    /// A = ∂F/∂x, S × S, in the order of [`Self::states`].
    pub fn a_matrix(&self) -> &DMatrix<f64> {
        &self.a
    }

    /// B = ∂F/∂u, S × M: rows in the order of [`Self::states`], columns of [`Self::inputs`].
    pub fn b_matrix(&self) -> &DMatrix<f64> {
        &self.b
    }

    /// Where the linearization was taken (`None` for one from [`Self::new`]).
    pub fn operating_point(&self) -> Option<&OperatingPoint> {
        self.point.as_ref()
    }

    /// The holonomic constraints recorded at the operating point, each with the state it
    /// determines: the coordinates [`Self::reduce`] can eliminate.
    pub fn holonomic(&self) -> Vec<(&str, &str)> {
        let c = &self.constraints;
        c.names
            .iter()
            .zip(&c.dependent)
            .map(|(name, &d)| (name.as_str(), self.states[d].as_str()))
            .collect()
    }

    /// Aᵢⱼ = ∂(rate of `row`)/∂`column`, e.g. `a("phi_rate", "delta")`; an unknown name is
    /// [`Error::UnknownName`], listing the states.
    pub fn a(&self, row: &str, column: &str) -> Result<f64, Error> {
        Ok(self.a[(self.state_index(row)?, self.state_index(column)?)])
    }

    /// Bᵢⱼ = ∂(rate of `row`)/∂`input`; an unknown name is [`Error::UnknownName`], listing
    /// the states or the inputs.
    pub fn b(&self, row: &str, input: &str) -> Result<f64, Error> {
        let column = index_of(&self.inputs, "input", input)?;
        Ok(self.b[(self.state_index(row)?, column)])
    }

    fn state_index(&self, name: &str) -> Result<usize, Error> {
        index_of(&self.states, "state", name)
    }
}

/// The index of `name` in `names`, or the error that lists them.
fn index_of(names: &[String], kind: &'static str, name: &str) -> Result<usize, Error> {
    names
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| Error::UnknownName {
            kind,
            name: name.to_string(),
            known: if names.is_empty() {
                "(none)".to_string()
            } else {
                names.join(", ")
            },
        })
}

impl Linearization {
    /// The linearization of the states `keep` alone (in that order), the others dropped.
    ///
    /// A dropped state must be either
    /// * a coordinate a recorded holonomic constraint determines ([`Self::holonomic`]): it is
    ///   eliminated through the constraints' linearization,
    ///   δq_dep = −(∂f/∂q_dep)⁻¹ ∂f/∂q_rest δq_rest, with the constraints that determine the
    ///   dropped dependent coordinates (nalgebra's LU), which substitutes into A's columns;
    /// * or cyclic: after that substitution, no kept state's rate depends on it (its column is
    ///   zero in the kept rows, to [`CYCLIC_TOLERANCE`] times the largest |Aᵢⱼ|).
    ///
    /// The constraints that remain keep what they say about the kept states; one that also
    /// involves a dropped cyclic coordinate says nothing about the kept ones alone and is
    /// left out.
    ///
    /// Errors: [`Error::UnknownName`] listing the states, [`Error::DuplicateName`],
    /// [`Error::NotCyclic`] naming the dropped state and a kept state that depends on it,
    /// [`Error::SingularElimination`] when the constraints do not determine a dropped
    /// dependent coordinate at the operating point.
    pub fn reduce(&self, keep: &[&str]) -> Result<Linearization, Error> {
        let mut kept = Vec::with_capacity(keep.len());
        for name in keep {
            let i = self.state_index(name)?;
            if kept.contains(&i) {
                return Err(Error::DuplicateName {
                    kind: "state",
                    name: (*name).to_string(),
                    context: "list each state to keep once",
                });
            }
            kept.push(i);
        }
        let c = &self.constraints;
        let eliminated: Vec<usize> = (0..c.names.len())
            .filter(|&r| !kept.contains(&c.dependent[r]))
            .collect();
        let substitution = self.substitution(&eliminated)?;
        let columns: Vec<usize> = eliminated.iter().map(|&r| c.dependent[r]).collect();
        let a = substitute(&self.a, &columns, &substitution);
        let cyclic: Vec<usize> = (0..self.states.len())
            .filter(|i| !kept.contains(i) && !columns.contains(i))
            .collect();
        let tolerance = CYCLIC_TOLERANCE * self.a.amax();
        for &dropped in &cyclic {
            for &row in &kept {
                let derivative = a[(row, dropped)];
                if derivative.abs() > tolerance {
                    return Err(Error::NotCyclic {
                        name: self.states[dropped].clone(),
                        kept: self.states[row].clone(),
                        derivative,
                        tolerance,
                    });
                }
            }
        }
        let constraints = self.remaining(&eliminated, &columns, &substitution, &cyclic, &kept);
        Ok(Linearization {
            states: kept.iter().map(|&i| self.states[i].clone()).collect(),
            inputs: self.inputs.clone(),
            a: a.select_rows(&kept).select_columns(&kept),
            b: self.b.select_rows(&kept),
            point: self.point.as_ref().map(|p| OperatingPoint {
                state: NamedValues(kept.iter().map(|&i| p.state.0[i].clone()).collect()),
                ..p.clone()
            }),
            constraints,
        })
    }

    /// The linearization with the inputs `keep` alone (in that order), the others held at
    /// their operating values: B's columns for them. A controller that uses some of a
    /// model's inputs is designed on this (the bicycle's steer torque without its roll
    /// torque).
    ///
    /// Errors: [`Error::UnknownName`] listing the inputs, [`Error::DuplicateName`].
    pub fn with_inputs(&self, keep: &[&str]) -> Result<Linearization, Error> {
        let mut kept = Vec::with_capacity(keep.len());
        for name in keep {
            let j = index_of(&self.inputs, "input", name)?;
            if kept.contains(&j) {
                return Err(Error::DuplicateName {
                    kind: "input",
                    name: (*name).to_string(),
                    context: "list each input to keep once",
                });
            }
            kept.push(j);
        }
        Ok(Linearization {
            inputs: kept.iter().map(|&j| self.inputs[j].clone()).collect(),
            b: self.b.select_columns(&kept),
            point: self.point.as_ref().map(|p| OperatingPoint {
                inputs: NamedValues(kept.iter().map(|&j| p.inputs.0[j].clone()).collect()),
                ..p.clone()
            }),
            ..self.clone()
        })
    }

    /// D with δx_E = D δx for the dependent states E of the constraint rows `rows`, from
    /// (∂f/∂x_E) δx_E + (∂f/∂x_rest) δx_rest = 0 (D's columns for E are zero). Each row is
    /// scaled by its largest derivative so that the LU's pivots compare with 1.
    fn substitution(&self, rows: &[usize]) -> Result<DMatrix<f64>, Error> {
        let c = &self.constraints;
        let (k, s) = (rows.len(), self.states.len());
        if k == 0 {
            return Ok(DMatrix::zeros(0, s));
        }
        let columns: Vec<usize> = rows.iter().map(|&r| c.dependent[r]).collect();
        let mut block = DMatrix::zeros(k, k);
        let mut rest = DMatrix::zeros(k, s);
        for (i, &r) in rows.iter().enumerate() {
            let largest = c.jacobian.row(r).amax();
            // A row without derivatives leaves its block row zero: the pivot test catches it.
            let scale = if largest > 0.0 { 1.0 / largest } else { 0.0 };
            for column in 0..s {
                let d = c.jacobian[(r, column)] * scale;
                match columns.iter().position(|&e| e == column) {
                    Some(j) => block[(i, j)] = d,
                    None => rest[(i, column)] = -d,
                }
            }
        }
        let lu = block.lu();
        let u = lu.u();
        let singular = |j: usize, pivot: f64| Error::SingularElimination {
            coordinate: self.states[columns[j]].clone(),
            constraint: c.names[rows[j]].clone(),
            pivot,
        };
        if let Some(j) = (0..k).find(|&j| u[(j, j)].abs() <= SINGULAR_PIVOT) {
            return Err(singular(j, u[(j, j)]));
        }
        // Every pivot is above the threshold, so the solve succeeds; one that overflows
        // comes from a block too close to singular all the same.
        let d = lu
            .solve(&rest)
            .unwrap_or_else(|| DMatrix::from_element(k, s, f64::NAN));
        match (0..k).find(|&j| d.row(j).iter().any(|v| !v.is_finite())) {
            Some(j) => Err(singular(j, u[(j, j)])),
            None => Ok(d),
        }
    }

    /// The constraints that are not used up by eliminated coordinates and involve no dropped
    /// cyclic state, with the substitution applied and restricted to the kept states.
    fn remaining(
        &self,
        eliminated: &[usize],
        columns: &[usize],
        substitution: &DMatrix<f64>,
        cyclic: &[usize],
        kept: &[usize],
    ) -> Constraints {
        let c = &self.constraints;
        let jacobian = substitute(&c.jacobian, columns, substitution);
        // Each remaining constraint with the position of its dependent state among the kept
        // ones (it is kept: the constraints of dropped dependent states were eliminated).
        let rows: Vec<(usize, usize)> = (0..c.names.len())
            .filter(|r| !eliminated.contains(r))
            .filter(|&r| {
                let tolerance = CYCLIC_TOLERANCE * c.jacobian.row(r).amax();
                cyclic.iter().all(|&d| jacobian[(r, d)].abs() <= tolerance)
            })
            .filter_map(|r| Some((r, kept.iter().position(|&i| i == c.dependent[r])?)))
            .collect();
        let indices: Vec<usize> = rows.iter().map(|&(r, _)| r).collect();
        Constraints {
            names: rows.iter().map(|&(r, _)| c.names[r].clone()).collect(),
            dependent: rows.iter().map(|&(_, position)| position).collect(),
            jacobian: jacobian.select_rows(&indices).select_columns(kept),
        }
    }
}

/// M + M[:, E]·D: the columns of `matrix` after δx_E = D δx is substituted (the columns E
/// themselves are zeroed, as nothing depends on the eliminated states any more).
fn substitute(
    matrix: &DMatrix<f64>,
    columns: &[usize],
    substitution: &DMatrix<f64>,
) -> DMatrix<f64> {
    let mut result = matrix.clone();
    for &e in columns {
        result.column_mut(e).fill(0.0);
    }
    for (j, &e) in columns.iter().enumerate() {
        result += matrix.column(e) * substitution.row(j);
    }
    result
}

impl fmt::Display for Linearization {
    /// The operating point, then A, B and the holonomic constraints' ∂f/∂x as tables with the
    /// names on their rows and columns.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.point {
            Some(point) => writeln!(f, "linearized at {point}")?,
            None => writeln!(f, "linearization given as matrices")?,
        }
        writeln!(f, "A = ∂F/∂x (rows: the rates of the states)")?;
        write_table(f, &self.states, &self.states, &self.a)?;
        if self.inputs.is_empty() {
            writeln!(f, "B = ∂F/∂u: no inputs")?;
        } else {
            writeln!(f, "B = ∂F/∂u")?;
            write_table(f, &self.states, &self.inputs, &self.b)?;
        }
        let c = &self.constraints;
        if !c.names.is_empty() {
            writeln!(f, "holonomic constraints ∂f/∂x (each determines a state)")?;
            let rows: Vec<String> = self
                .holonomic()
                .iter()
                .map(|(name, state)| format!("{name} → {state}"))
                .collect();
            write_table(f, &rows, &self.states, &c.jacobian)?;
        }
        Ok(())
    }
}

/// `matrix` with the row names on the left and the column names above, every column as wide
/// as its widest entry, numbers right-aligned with four significant digits.
fn write_table(
    f: &mut fmt::Formatter<'_>,
    rows: &[String],
    columns: &[String],
    matrix: &DMatrix<f64>,
) -> fmt::Result {
    let width = |s: &str| s.chars().count();
    // + 0.0 prints a negative zero as 0.
    let cells: Vec<Vec<String>> = (0..rows.len())
        .map(|i| {
            (0..columns.len())
                .map(|j| Num(matrix[(i, j)] + 0.0).to_string())
                .collect()
        })
        .collect();
    let label = rows.iter().map(|r| width(r)).max().unwrap_or(0);
    let widths: Vec<usize> = columns
        .iter()
        .enumerate()
        .map(|(j, name)| {
            cells
                .iter()
                .map(|row| width(&row[j]))
                .fold(width(name), usize::max)
        })
        .collect();
    write!(f, "{:label$}", "")?;
    for (name, w) in columns.iter().zip(&widths) {
        write!(f, "  {name:>w$}")?;
    }
    writeln!(f)?;
    for (name, row) in rows.iter().zip(&cells) {
        write!(f, "{name:label$}")?;
        for (cell, w) in row.iter().zip(&widths) {
            write!(f, "  {cell:>w$}")?;
        }
        writeln!(f)?;
    }
    Ok(())
}

impl fmt::Debug for Linearization {
    /// A summary: the names, where it was taken and the size of the entries.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Linearization")
            .field("states", &self.states)
            .field("inputs", &self.inputs)
            .field("t", &self.point.as_ref().map(|p| p.t))
            .field("max_abs_a", &format_args!("{}", Num(self.a.amax())))
            .field("max_abs_b", &format_args!("{}", Num(self.b.amax())))
            .field("holonomic", &self.holonomic())
            .finish()
    }
}
