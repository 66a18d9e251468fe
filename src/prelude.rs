//! What a model and its simulation need: `use hamel::prelude::*;`.

pub use crate::{
    DormandPrince, Error, GaussLegendre, HamelSystem, ImplicitMidpoint, Parameters, Radau5, Rk4,
    Simulation, Trajectory, hamel_system,
};
// The role attributes, so that a misplaced one says where it belongs.
pub use crate::{
    constraints, forces, holonomic, kinetic_energy, lagrangian, potential_energy, quasi_lagrangian,
    quasi_velocities, velocities,
};
