//! What a model and its simulation need: `use hamel::prelude::*;`.

pub use crate::{
    DormandPrince, Error, HamelSystem, Parameters, Rk4, Simulation, Trajectory, hamel_system,
};
// What the guides' runs use beside them: events, streaming, progress, why a run stopped,
// its summary, linearizations and their modes, the generated code's singularities, studies.
pub use crate::{
    CsvSink, Ensemble, Event, Linearization, Mode, Outputs, Progress, Singularity, Sink, Stopped,
    Summary, Table,
};
// The role attributes, so that a misplaced one says where it belongs.
pub use crate::{
    constraints, forces, holonomic, kinetic_energy, lagrangian, potential_energy, quasi_lagrangian,
    quasi_velocities, velocities,
};
