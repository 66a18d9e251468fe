//! What a model and its simulation need: `use hamel::prelude::*;`.

pub use crate::{
    DormandPrince, Error, GaussLegendre, HamelSystem, ImplicitMidpoint, Parameters, Radau5, Rk4,
    Rodas5P, Simulation, Trajectory, hamel_system,
};
// What the guides' runs use beside them: events, streaming, progress, why a run stopped,
// its summary, linearizations and their modes (followed along a parameter), the generated
// code's singularities, studies, control from the model.
pub use crate::{
    ControlAffine, CsvSink, Event, Linearization, Mode, ModeBranch, Progress, Singularity, Sink,
    Stopped, Summary, track_modes,
};
#[cfg(feature = "ensemble")]
pub use crate::{Ensemble, Outputs, Table};
// The role attributes, so that a misplaced one says where it belongs.
pub use crate::{
    bodies, constraints, contacts, forces, gravity, holonomic, kinetic_energy, lagrangian, outputs,
    potential_energy, quasi_lagrangian, quasi_velocities, velocities,
};
// The geometry vocabulary a model's roles are written in, and the rates along the motion.
pub use crate::geometry::{
    Body, Contact, Inertia, Rotation3, Shape, Surface, Vector3, disk_contact,
};
pub use crate::{angular_velocity, body_rates, rate};
