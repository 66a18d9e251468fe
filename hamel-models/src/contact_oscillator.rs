//! The nonholonomic contact oscillator of McLachlan and Perlmutter (*Integrators for
//! nonholonomic mechanical systems*, J. Nonlinear Sci. 16 (2006), 283–328, §5), their test
//! problem for long-time energy behaviour: q = (x, y, z) with
//! L = ½|q̇|² − U, U = ½(x² + y² + z²) + ½ε x² z², under the constraint ẋ + y ż = 0.
//!
//! The constraint's row (1, 0, y) has no ẏ, so y is a free harmonic oscillator, ÿ = −y, and
//! besides the energy H two more quantities are invariant: H_y = ½(y² + ẏ²)
//! ([`ContactOscillator::y_energy`]) and H − H_y. The model is reversible
//! ([`hamel::HamelSystem::REVERSIBLE`]), so a symmetric integrator keeps all three bounded.

use crate::hamel_system;

/// Parameters of the contact oscillator: the coupling ε of U (default 0.3, McLachlan and
/// Perlmutter's).
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct ContactOscillator {
    /// coupling of x and z in the potential, ½ε x² z²
    pub epsilon: f64,
}

impl Default for ContactOscillator {
    fn default() -> Self {
        ContactOscillator { epsilon: 0.3 }
    }
}

#[hamel_system(coordinates(x, y, z), speeds(vy, vz), constraints(contact))]
impl ContactOscillator {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2])
    }

    #[potential_energy]
    pub fn potential_energy(&self, q: &[f64; 3]) -> f64 {
        let [x, y, z] = *q;
        0.5 * (x * x + y * y + z * z) + 0.5 * self.epsilon * x * x * z * z
    }

    /// ẋ + y ż = 0.
    #[constraints]
    pub fn contact(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] + q[1] * qd[2]]
    }

    /// ẏ and ż.
    #[quasi_velocities]
    pub fn speeds(&self, _q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[1], qd[2]]
    }
}

impl ContactOscillator {
    /// The invariant H_y = ½(y² + ẏ²) of a state (x, y, z, ẏ, ż).
    pub fn y_energy(state: &[f64; 5]) -> f64 {
        0.5 * (state[1] * state[1] + state[3] * state[3])
    }

    /// The start of the test suite's and the benchmarks' runs, with McLachlan and
    /// Perlmutter's energies H₀ = 1.5 and H_y = 0.5: y = 0, ẏ = 1, x = z = 0.5 with ẋ = −y ż
    /// = 0, and ż > 0 taking the rest of the energy.
    pub fn start(&self) -> Result<[f64; 5], hamel::Error> {
        use hamel::HamelSystem;
        let (x, z) = (0.5, 0.5);
        let potential = 0.5 * (x * x + z * z) + 0.5 * self.epsilon * x * x * z * z;
        let vz = (2.0 * (1.0 - potential)).sqrt();
        self.state_from_speeds(0.0, &[x, 0.0, z], &[1.0, vz])
    }
}
