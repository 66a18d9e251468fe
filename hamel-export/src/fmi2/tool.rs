//! The command line of an FMU's crate (its small binary is `main` below):
//!
//! ```text
//! <model>-fmu fmu OUT.fmu LIBRARY [PLATFORM=LIBRARY]...   the FMU, with other platforms' builds
//! <model>-fmu description OUT.xml                         its modelDescription.xml alone
//! <model>-fmu simulate OUT.csv [OPTION VALUE]... [NAME=VALUE]...
//! ```
//!
//! `fmu` needs the feature `fmu` (the zip archive); without it the export example writes
//! the archive from the description (`hamel-export/src/fmi2/archive.rs`).
//!
//! `simulate` is hamel's own run of the model (`Simulation` with Dormand–Prince), what an
//! FMU's run is compared with: options `--t-end` (3), `--dt` (0.01), `--rtol` (1e-9),
//! `--atol` (1e-12); `NAME=VALUE` sets a parameter, a start value (the dependent coordinates
//! are solved from the others, as the FMU does) or a constant input by its name.

use super::description::model_description;
use crate::model::Model;
use hamel_runtime::{DormandPrince, HamelSystem, Parameters, Simulation, Vector};
use std::process::ExitCode;

const USAGE: &str = "usage: MODEL-fmu fmu OUT.fmu LIBRARY [PLATFORM=LIBRARY]...
       MODEL-fmu description OUT.xml
       MODEL-fmu simulate OUT.csv [--t-end T] [--dt DT] [--rtol R] [--atol A] [NAME=VALUE]...";

/// Runs the command line `args` (without the program's name) for `M` as `identifier`.
pub fn main<M: Model>(identifier: &str) -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run::<M>(identifier, &args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// [`main`] on given arguments.
pub fn run<M: Model>(identifier: &str, args: &[String]) -> Result<(), String> {
    match args {
        #[cfg(feature = "fmu")]
        [command, out, library, others @ ..] if command == "fmu" => {
            let others = others
                .iter()
                .map(|o| {
                    o.split_once('=')
                        .map(|(p, l)| (p.to_string(), std::path::Path::new(l)))
                        .ok_or_else(|| format!("`{o}` is not PLATFORM=LIBRARY\n{USAGE}"))
                })
                .collect::<Result<Vec<_>, _>>()?;
            let (library, out) = (std::path::Path::new(library), std::path::Path::new(out));
            super::write_fmu::<M>(identifier, library, &others, out)
        }
        #[cfg(not(feature = "fmu"))]
        [command, ..] if command == "fmu" => Err(
            "this program was built without hamel-export's feature `fmu` (the zip archive): \
             build it with that feature, or write the archive from `description`'s output"
                .to_string(),
        ),
        [command, out] if command == "description" => {
            std::fs::write(out, model_description::<M>(identifier))
                .map_err(|e| format!("cannot write {out}: {e}"))
        }
        [command, out, options @ ..] if command == "simulate" => simulate::<M>(out, options),
        _ => Err(USAGE.to_string()),
    }
}

/// The run's settings.
struct Run {
    t_end: f64,
    dt: f64,
    rtol: f64,
    atol: f64,
}

/// hamel's own run, written as CSV (`Trajectory::write_csv`).
fn simulate<M: Model>(out: &str, options: &[String]) -> Result<(), String> {
    let mut run = Run {
        t_end: 3.0,
        dt: 0.01,
        rtol: 1e-9,
        atol: 1e-12,
    };
    let mut system = M::System::default();
    let mut start: Vec<(&str, f64)> = Vec::new();
    let mut u = <M::System as HamelSystem>::Inputs::zeros();
    let mut i = 0;
    while i < options.len() {
        let option = &options[i];
        let number = |text: &str| -> Result<f64, String> {
            text.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("`{text}` is not a finite number (in `{option}`)"))
        };
        if let Some(flag) = option.strip_prefix("--") {
            let value = number(options.get(i + 1).map_or("", String::as_str))?;
            match flag {
                "t-end" => run.t_end = value,
                "dt" => run.dt = value,
                "rtol" => run.rtol = value,
                "atol" => run.atol = value,
                _ => return Err(format!("unknown option `{option}`\n{USAGE}")),
            }
            i += 2;
            continue;
        }
        let (name, value) = option
            .split_once('=')
            .ok_or_else(|| format!("`{option}` is not NAME=VALUE\n{USAGE}"))?;
        let value = number(value)?;
        let inputs = <M::System as HamelSystem>::INPUTS;
        if let Some(k) = inputs.iter().position(|n| *n == name) {
            u.as_mut()[k] = value;
        } else if <M::System as HamelSystem>::STATE.contains(&name) {
            start.push((name, value));
        } else {
            system.set(name, value).map_err(|e| e.to_string())?;
        }
        i += 1;
    }
    let builder = start
        .iter()
        .fold(system.state_builder(), |b, (n, v)| b.set(n, *v));
    let x0 = builder.build().map_err(|e| e.to_string())?;
    let trajectory = Simulation::new(&system, x0)
        .end_time(run.t_end)
        .sample_interval(run.dt)
        .run_constant(&DormandPrince::new(run.rtol, run.atol), u)
        .map_err(|e| e.to_string())?;
    let file = std::fs::File::create(out).map_err(|e| format!("cannot create {out}: {e}"))?;
    trajectory
        .write_csv(std::io::BufWriter::new(file))
        .map_err(|e| format!("cannot write {out}: {e}"))
}
