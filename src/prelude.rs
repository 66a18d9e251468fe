//! What a model and its simulation need: `use hamel::prelude::*;`.

pub use crate::{
    DormandPrince, Error, HamelSystem, Parameters, Rk4, Simulation, Trajectory, hamel_system,
};
