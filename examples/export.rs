//! A catalogue model as a C library and header, for CasADi (and any C program).
//!
//! ```text
//! cargo run --release --example export -- casadi mobile_robot OUTDIR
//! cargo run --release --example export -- casadi whipple_bicycle OUTDIR
//! cargo run --release --example export -- fmu mobile_robot OUTDIR
//! cargo run --release --example export -- --list
//! ```
//!
//! writes `OUTDIR/libmobile_robot.so` (CasADi's external functions `mobile_robot_f`,
//! `jac_mobile_robot_f`, …, and the plain C functions `mobile_robot_rhs`, …) and
//! `OUTDIR/mobile_robot.h`, which documents them with the model's names and units; `fmu`
//! writes `OUTDIR/MobileRobot.fmu`, an FMI 2.0 FMU (Model Exchange and Co-Simulation) of the
//! model for Simulink, Dymola, OpenModelica, FMPy and the other FMI tools.
//!
//! How: this program is a thin driver. It writes a small crate of type `cdylib` into
//! `target/hamel-export/<model>/` that exports the model with `hamel-export`'s macros
//! (`model!`, `c_api!`, `casadi!`, with `hamel-export`'s feature `compiled`: derivatives as
//! straight-line code), builds it with `cargo build --release` in this build's target
//! directory (the catalogue is built again there, with the derivative code), runs the
//! crate's small binary that writes the header, and copies the library and the header. A
//! model of your own is exported the same way from your own crate: `hamel::docs::export`.
//! The first export compiles the catalogue in release (a minute or two on two cores); each
//! further model takes seconds to a minute (the bicycle's second derivatives are the most).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// The catalogue: each model's snake-case name and its type in `hamel_models`.
const CATALOGUE: &[(&str, &str)] = &[
    ("ball_on_turntable", "BallOnTurntable"),
    ("chaplygin_ball", "ChaplyginBall"),
    ("chaplygin_sleigh", "ChaplyginSleigh"),
    ("contact_oscillator", "ContactOscillator"),
    ("knife_edge", "KnifeEdge"),
    ("mobile_robot", "MobileRobot"),
    ("mobile_robot_paper", "MobileRobotPaper"),
    ("n_trailer1", "NTrailer1"),
    ("n_trailer2", "NTrailer2"),
    ("n_trailer8", "NTrailer8"),
    ("n_trailer24", "NTrailer24"),
    ("rattleback", "Rattleback"),
    ("rolling_disk", "RollingDisk"),
    ("vertical_disk", "VerticalDisk"),
    ("whipple_bicycle", "WhippleBicycle"),
];

const USAGE: &str = "usage: cargo run --release --example export -- casadi MODEL OUTDIR
       cargo run --release --example export -- fmu MODEL OUTDIR
       cargo run --release --example export -- --list

casadi writes OUTDIR/libMODEL.so and OUTDIR/MODEL.h: the catalogue model MODEL (its
snake-case name, e.g. mobile_robot) as CasADi external functions with exact derivatives and
plain C functions. fmu writes OUTDIR/Model.fmu (e.g. MobileRobot.fmu): the model as an FMI
2.0 FMU, Model Exchange and Co-Simulation. --list prints the catalogue's names.";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &[String]) -> Result<(), String> {
    match args {
        [flag] if flag == "--list" => {
            for (name, _) in CATALOGUE {
                println!("{name}");
            }
            Ok(())
        }
        [flag] if flag == "--help" || flag == "-h" => {
            println!("{USAGE}");
            Ok(())
        }
        [format, model, outdir] if format == "casadi" => {
            let ty = model_type(model)?;
            export(model, ty, Path::new(outdir))
        }
        [format, model, outdir] if format == "fmu" => {
            let ty = model_type(model)?;
            fmu::export(model, ty, Path::new(outdir))
        }
        [format, ..] if format != "casadi" && format != "fmu" => Err(format!(
            "unknown export format `{format}` (known: casadi, fmu)\n\n{USAGE}"
        )),
        _ => Err(format!("expected three arguments\n\n{USAGE}")),
    }
}

fn model_type(model: &str) -> Result<&'static str, String> {
    CATALOGUE
        .iter()
        .find(|(name, _)| *name == model)
        .map(|(_, ty)| *ty)
        .ok_or_else(|| {
            let known: Vec<&str> = CATALOGUE.iter().map(|(n, _)| *n).collect();
            format!("no catalogue model `{model}`; known: {}", known.join(", "))
        })
}

/// The repository, where `hamel-export` and `hamel-models` are.
fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// This build's target directory: `target/release/examples/export` is three levels below
/// it. The exported crates build there too, so that they reuse what this program's build
/// made with the same features and profile (the runtime, the macro's dependencies; the
/// C library's catalogue is built with the derivative code, once for every model).
fn target_dir() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this program: {e}"))?;
    exe.ancestors()
        .nth(3)
        .map(Path::to_path_buf)
        .ok_or_else(|| "cannot locate the target directory".to_string())
}

fn export(model: &str, ty: &str, outdir: &Path) -> Result<(), String> {
    let target = target_dir()?;
    let dir = target.join("hamel-export").join(model);
    write_crate(&dir, model, ty)?;
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    eprintln!("building {model} in {}", dir.display());
    let status = Command::new(&cargo)
        .args(["build", "--release", "--manifest-path"])
        .arg(dir.join("Cargo.toml"))
        .env("CARGO_TARGET_DIR", &target)
        .status()
        .map_err(|e| format!("cannot run {cargo}: {e}"))?;
    if !status.success() {
        return Err(format!("building the library of {model} failed ({status})"));
    }
    std::fs::create_dir_all(outdir)
        .map_err(|e| format!("cannot create {}: {e}", outdir.display()))?;
    let library = format!("lib{model}.so");
    let built = target.join("release").join(&library);
    std::fs::copy(&built, outdir.join(&library))
        .map_err(|e| format!("cannot copy {}: {e}", built.display()))?;
    let header = outdir.join(format!("{model}.h"));
    let tool = target.join("release").join(format!("{model}-export"));
    let status = Command::new(&tool)
        .arg("header")
        .arg(&header)
        .status()
        .map_err(|e| format!("cannot run {}: {e}", tool.display()))?;
    if !status.success() {
        return Err(format!("writing {} failed ({status})", header.display()));
    }
    println!("{}", outdir.join(&library).display());
    println!("{}", header.display());
    Ok(())
}

/// The crate that exports `ty` as `model`: written only where it differs, so that a second
/// export of the same model rebuilds nothing.
fn write_crate(dir: &Path, model: &str, ty: &str) -> Result<(), String> {
    let repo = repository();
    let path = |p: &str| repo.join(p).display().to_string().replace('\\', "/");
    let manifest = format!(
        r#"# Written by hamel's `export` example: the catalogue model {ty} as a C library.
[package]
name = "hamel-export-{model}"
version = "0.1.0"
edition = "2024"
publish = false

[lib]
name = "{model}"
path = "lib.rs"
crate-type = ["cdylib", "rlib"]

[[bin]]
name = "{model}-export"
path = "main.rs"

# `compiled`: the derivatives as straight-line code that `#[hamel_system]` emits (every
# catalogue model gets it in this build, which is why only the export turns it on).
[dependencies]
hamel-export = {{ path = "{export}", features = ["compiled"] }}
hamel-models = {{ path = "{models}" }}

# Not a member of hamel's workspace, though inside its directory.
[workspace]
"#,
        export = path("hamel-export"),
        models = path("hamel-models"),
    );
    let lib = format!(
        "//! The catalogue model {ty} exported as `{model}` (written by hamel's `export` example).\n\
         hamel_export::model!(Exported => hamel_models::{ty});\n\
         hamel_export::c_api!(Exported, \"{model}\");\n\
         hamel_export::casadi!(Exported, \"{model}\");\n"
    );
    let main = format!(
        "//! Writes the header of `{model}`: `{model}-export header PATH`.\n\
         fn main() -> std::process::ExitCode {{\n\
         \x20   let args: Vec<String> = std::env::args().skip(1).collect();\n\
         \x20   let [what, path] = args.as_slice() else {{\n\
         \x20       eprintln!(\"usage: {model}-export header PATH\");\n\
         \x20       return std::process::ExitCode::FAILURE;\n\
         \x20   }};\n\
         \x20   let text = match what.as_str() {{\n\
         \x20       \"header\" => hamel_export::header::header::<{model}::Exported>(\"{model}\"),\n\
         \x20       other => {{\n\
         \x20           eprintln!(\"unknown output `{{other}}` (known: header)\");\n\
         \x20           return std::process::ExitCode::FAILURE;\n\
         \x20       }}\n\
         \x20   }};\n\
         \x20   if let Err(e) = std::fs::write(path, text) {{\n\
         \x20       eprintln!(\"cannot write {{path}}: {{e}}\");\n\
         \x20       return std::process::ExitCode::FAILURE;\n\
         \x20   }}\n\
         \x20   std::process::ExitCode::SUCCESS\n\
         }}\n"
    );
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    write_if_changed(&dir.join("Cargo.toml"), &manifest)?;
    write_if_changed(&dir.join("lib.rs"), &lib)?;
    write_if_changed(&dir.join("main.rs"), &main)?;
    // The workspace's lock file: the same versions of every dependency as hamel's own build,
    // and no registry look-up when they are in cargo's cache already.
    let lock = dir.join("Cargo.lock");
    if !lock.exists() {
        std::fs::copy(repo.join("Cargo.lock"), &lock)
            .map_err(|e| format!("cannot copy Cargo.lock: {e}"))?;
    }
    Ok(())
}

fn write_if_changed(path: &Path, text: &str) -> Result<(), String> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == text) {
        return Ok(());
    }
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The `fmu` export: a crate of its own, `target/hamel-export/<model>-fmu/`, that exports
/// the model's FMI functions (`hamel_export::fmi2!`) and nothing else, so that the FMU holds
/// no CasADi functions and builds in 15-30 s of CPU once hamel's crates are built for it; its
/// binary writes the FMU (`hamel_export::fmi2::tool`).
mod fmu {
    use super::{repository, target_dir, write_if_changed};
    use std::path::Path;
    use std::process::Command;

    pub fn export(model: &str, ty: &str, outdir: &Path) -> Result<(), String> {
        let target = target_dir()?;
        let dir = target.join("hamel-export").join(format!("{model}-fmu"));
        write_crate(&dir, model, ty)?;
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        eprintln!("building the FMU of {model} in {}", dir.display());
        let status = Command::new(&cargo)
            .args(["build", "--release", "--manifest-path"])
            .arg(dir.join("Cargo.toml"))
            .env("CARGO_TARGET_DIR", &target)
            .status()
            .map_err(|e| format!("cannot run {cargo}: {e}"))?;
        if !status.success() {
            return Err(format!("building the FMU of {model} failed ({status})"));
        }
        std::fs::create_dir_all(outdir)
            .map_err(|e| format!("cannot create {}: {e}", outdir.display()))?;
        let release = target.join("release");
        let library = release.join(format!(
            "{}{model}_fmu{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        ));
        let fmu = outdir.join(format!("{ty}.fmu"));
        let tool = release.join(format!("{model}-fmu"));
        let status = Command::new(&tool)
            .arg("fmu")
            .arg(&fmu)
            .arg(&library)
            .status()
            .map_err(|e| format!("cannot run {}: {e}", tool.display()))?;
        if !status.success() {
            return Err(format!("writing {} failed ({status})", fmu.display()));
        }
        println!("{}", fmu.display());
        Ok(())
    }

    /// The FMU's crate: written only where it differs, so that a second export rebuilds
    /// nothing.
    fn write_crate(dir: &Path, model: &str, ty: &str) -> Result<(), String> {
        let repo = repository();
        let path = |p: &str| repo.join(p).display().to_string().replace('\\', "/");
        let manifest = format!(
            r#"# Written by hamel's `export` example: the catalogue model {ty} as an FMU.
[package]
name = "hamel-fmu-{model}"
version = "0.1.0"
edition = "2024"
publish = false

[lib]
name = "{model}_fmu"
path = "lib.rs"
crate-type = ["cdylib", "rlib"]

[[bin]]
name = "{model}-fmu"
path = "main.rs"

[dependencies]
hamel-export = {{ path = "{export}", features = ["fmu"] }}
hamel-models = {{ path = "{models}" }}

# Not a member of hamel's workspace, though inside its directory.
[workspace]
"#,
            export = path("hamel-export"),
            models = path("hamel-models"),
        );
        let lib = format!(
            "//! The catalogue model {ty} as the FMU `{ty}` (written by hamel's `export` example).\n\
             hamel_export::model!(Exported => hamel_models::{ty});\n\
             hamel_export::fmi2!(Exported, \"{ty}\");\n"
        );
        let main = format!(
            "//! Writes the FMU of {ty} (`{model}-fmu fmu OUT.fmu LIBRARY`), its description, or\n\
             //! hamel's own run of the model (`hamel_export::fmi2::tool`).\n\
             fn main() -> std::process::ExitCode {{\n\
             \x20   hamel_export::fmi2::tool::main::<{model}_fmu::Exported>(\"{ty}\")\n\
             }}\n"
        );
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        write_if_changed(&dir.join("Cargo.toml"), &manifest)?;
        write_if_changed(&dir.join("lib.rs"), &lib)?;
        write_if_changed(&dir.join("main.rs"), &main)?;
        let lock = dir.join("Cargo.lock");
        if !lock.exists() {
            std::fs::copy(repo.join("Cargo.lock"), &lock)
                .map_err(|e| format!("cannot copy Cargo.lock: {e}"))?;
        }
        Ok(())
    }
}
