//! A model as an FMU: FMI 2.0, Model Exchange and Co-Simulation in one.
//!
//! ```ignore
//! // In a crate of type cdylib:
//! hamel_export::model!(Robot => hamel_models::MobileRobot);
//! hamel_export::fmi2!(Robot, "MobileRobot");        // fmi2Instantiate, fmi2DoStep, …
//! // and, from a small binary of the same crate, the FMU:
//! hamel_export::fmi2::write_fmu::<Robot>("MobileRobot", "libmobile_robot_fmu.so".as_ref(),
//!                                        "MobileRobot.fmu".as_ref())?;
//! ```
//!
//! One module per job:
//! - [`variables`]: what each value reference is (one table for the description and the
//!   instance); [`description`]: `modelDescription.xml` from the model's traits, its units
//!   ([`units`]) and the dependencies of the generated code; `archive` (feature `fmu`): the `.fmu` file.
//! - [`types`]: the standard's C types; [`modes`]: its state machine; [`logger`]: messages
//!   through the importer's callback; [`api`]: the boundary (pointers checked, modes
//!   checked, panics caught); [`instance`]: one instance's data and variables;
//!   [`exchange`] and [`cosim`]: the functions of each interface; [`directional`]: exact
//!   directional derivatives; [`snapshot`]: the FMU state, saved, restored and serialized;
//!   [`exports`]: the macro that exports the symbols.
//!
//! `hamel::docs::export` has the guide (its FMI section), and `cargo run --release --example
//! export -- fmu mobile_robot OUTDIR` writes any catalogue model's FMU.

pub mod api;
#[cfg(feature = "fmu")]
pub mod archive;
pub mod cosim;
pub mod description;
pub mod directional;
pub mod exchange;
pub mod exports;
pub mod instance;
pub mod logger;
pub mod modes;
pub mod snapshot;
pub mod tool;
pub mod types;
pub mod units;
pub mod variables;

pub use description::{guid, model_description};

/// Writes the FMU of `M` as `identifier` to `out`: its description, and `library` (this
/// crate's `cdylib` with [`crate::fmi2!`], built for this platform) as
/// `binaries/<platform>/<identifier>.<ext>`. `others` adds libraries built for other
/// platforms (`("win64", path to the .dll)`, …). Feature `fmu`.
#[cfg(feature = "fmu")]
pub fn write_fmu<M: crate::Model>(
    identifier: &str,
    library: &std::path::Path,
    others: &[(String, &std::path::Path)],
    out: &std::path::Path,
) -> Result<(), String> {
    let description = model_description::<M>(identifier);
    archive::write_archive(identifier, &description, library, others, out)
}
