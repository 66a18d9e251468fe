//! A user's crate of models for Python: `export_models!` makes it the extension module
//! `my_models`, which `hamel.load("my_models")` turns into `hamel.Model` classes.
//!
//! * `Sleigh`: the README's Chaplygin sleigh with defaults, its doc comment the class's
//!   docstring.
//! * `TabulatedSpring`: a model written by hand (no `#[hamel_system]`), a mass on a spring
//!   whose stiffness is read from a table, with the bug such code has: the table is indexed
//!   without a bound check, so a motion that leaves it panics. The Python tests use it to
//!   show that a Rust panic raised inside a run or an ensemble's case comes back as a Python
//!   exception (`hamel.errors.Panic`, a failed case's `case_panicked`), the interpreter going
//!   on.

use hamel::prelude::*;
use hamel::{Error, Parameters, Singularity};

/// The Chaplygin sleigh: a rigid body on a plane whose blade, at distance `a` behind the
/// centre of mass, cannot slide sideways.
///
/// Its forward speed tends to √(2E/m) as it straightens out.
#[hamel_system]
pub struct Sleigh {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the centre of mass (kg m^2)
    pub inertia: f64,
    /// distance from the centre of mass to the blade (m)
    pub a: f64,
}

impl Default for Sleigh {
    fn default() -> Self {
        Sleigh {
            m: 2.0,
            inertia: 0.5,
            a: 0.4,
        }
    }
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl Sleigh {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    /// The contact point does not slide across the blade.
    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    /// Forward speed and turning rate.
    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

/// The spring's stiffness (N/m) on each 0.1 m of |x|, from 0 to 0.8 m: constant here, so the
/// motion is harmonic while it stays in the table.
const STIFFNESS: [f64; 8] = [4.0; 8];

/// A mass m on a spring whose stiffness is tabulated against the displacement: state (x, v).
pub struct TabulatedSpring {
    /// mass (kg)
    pub m: f64,
}

impl Default for TabulatedSpring {
    fn default() -> Self {
        TabulatedSpring { m: 1.0 }
    }
}

impl TabulatedSpring {
    /// The stiffness at x. The bug: no bound check, so |x| ≥ 0.8 m indexes past the table
    /// and panics.
    fn stiffness(x: f64) -> f64 {
        STIFFNESS[(x.abs() / 0.1) as usize]
    }
}

impl Parameters for TabulatedSpring {
    const NAMES: &'static [&'static str] = &["m"];
    const DOCS: &'static [&'static str] = &["mass (kg)"];
    const DOC: &'static str = "A mass on a spring whose stiffness is read from a table.";

    fn get(&self, name: &str) -> Option<f64> {
        (name == "m").then_some(self.m)
    }

    fn set(&mut self, name: &str, value: f64) -> Result<(), Error> {
        if name != "m" {
            return Err(Error::UnknownParameter {
                name: name.to_string(),
                known: "m".to_string(),
            });
        }
        if !value.is_finite() {
            return Err(Error::InvalidParameter {
                name: name.to_string(),
                value,
            });
        }
        self.m = value;
        Ok(())
    }
}

impl HamelSystem for TabulatedSpring {
    type Coordinates = [f64; 1];
    type Speeds = [f64; 1];
    type Constraints = [f64; 0];
    type State = [f64; 2];
    type Inputs = [f64; 0];
    type Holonomic = [f64; 0];
    type HolonomicJacobian = [f64; 0];
    type Extended = [f64; 3];
    type MassMatrix = [[f64; 1]; 1];
    type Gamma = [[[f64; 1]; 1]; 1];
    type StateJacobian = [f64; 4];
    type InputJacobian = [f64; 0];

    const N: usize = 1;
    const P: usize = 0;
    const M: usize = 0;
    const K: usize = 0;
    const COORDINATES: &'static [&'static str] = &["x"];
    const SPEEDS: &'static [&'static str] = &["v"];
    const CONSTRAINTS: &'static [&'static str] = &[];
    const INPUTS: &'static [&'static str] = &[];
    const STATE: &'static [&'static str] = &["x", "v"];
    const DEPENDENT: &'static [usize] = &[];
    const CONSERVATIVE: bool = true;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 2],
        _u: &[f64; 0],
        dx: &mut [f64; 2],
    ) -> Result<(), Singularity> {
        *dx = [x[1], -Self::stiffness(x[0]) * x[0] / self.m];
        Ok(())
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 2]) -> Result<[f64; 1], Singularity> {
        Ok([x[1]])
    }

    fn energy(&self, _t: f64, x: &[f64; 2]) -> Result<f64, Singularity> {
        Ok(0.5 * self.m * x[1] * x[1] + 0.5 * Self::stiffness(x[0]) * x[0] * x[0])
    }

    fn power(&self, _t: f64, _x: &[f64; 2], _u: &[f64; 0]) -> Result<f64, Singularity> {
        Ok(0.0)
    }

    fn multipliers(&self, _t: f64, _x: &[f64; 2], _u: &[f64; 0]) -> Result<[f64; 0], Singularity> {
        Ok([])
    }

    fn constraint_residual(&self, _t: f64, _q: &[f64; 1], _qd: &[f64; 1]) -> [f64; 0] {
        []
    }

    fn speeds(&self, _t: f64, _q: &[f64; 1], qd: &[f64; 1]) -> [f64; 1] {
        *qd
    }

    fn holonomic_residual(&self, _t: f64, _q: &[f64; 1]) -> [f64; 0] {
        []
    }

    fn holonomic_jacobian(&self, _t: f64, _q: &[f64; 1]) -> [f64; 0] {
        []
    }

    fn mass_matrix(&self, _t: f64, _x: &[f64; 2]) -> Result<[[f64; 1]; 1], Singularity> {
        Ok([[self.m]])
    }

    fn gamma(&self, _t: f64, _q: &[f64; 1]) -> Result<[[[f64; 1]; 1]; 1], Singularity> {
        Ok([[[0.0]]])
    }

    fn inverse_defect(&self, _t: f64, _q: &[f64; 1]) -> Result<f64, Singularity> {
        Ok(0.0)
    }

    fn jacobian(
        &self,
        _t: f64,
        x: &[f64; 2],
        _u: &[f64; 0],
    ) -> Result<([f64; 4], [f64; 0]), Singularity> {
        Ok(([0.0, 1.0, -Self::stiffness(x[0]) / self.m, 0.0], []))
    }
}

hamel_python::export_models!(my_models: Sleigh, TabulatedSpring);
