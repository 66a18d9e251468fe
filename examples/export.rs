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

# This crate's own code (where the model's derivative code is optimized: its functions are
# generic and instantiated here) at opt-level 2, which leaves out LLVM's SLP vectorizer
# (rustc runs it at opt-level 3 only): on straight-line code of this size it took 272 of the
# 330 s of CPU of the bicycle's build (199 s on its second derivatives alone; rustc's
# `-Z llvm-time-trace`), for a few per cent of instructions per call of the robot's functions
# (`hamel-export/bench/instructions.sh`). Its dependencies keep the release profile.
[profile.release.package.hamel-export-{model}]
opt-level = 2
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

/// The `fmu` export, in three steps, each built in this build's target directory:
/// - the model's library (`fmi2!`) and command line (`hamel_export::fmi2::tool`): the
///   examples `fmu_library` and `fmu_tool` of `hamel-export`, which include the source this
///   program writes into `target/hamel-export/<model>-fmu/`, built in hamel's own workspace
///   with its release profile and the same features, so that they link the runtime, the
///   macro and the catalogue this program's build made (a crate of its own would build them
///   again: cargo tells a path dependency's builds apart by its path from the workspace
///   root); the command line is copied to `target/release/<model>-fmu`;
/// - its `modelDescription.xml`, written by that command line;
/// - the archive, by a small program of its own, `target/hamel-export/fmu-archive/`: zip and
///   `hamel-export/src/fmi2/archive.rs` alone (the zip crate turns on memchr's `std`, which
///   would give the first build other features than the robot example's). It is built once
///   for every model.
///
/// The two examples' outputs are the same files for every model: export one model at a time
/// into a target directory (a second export started meanwhile could replace the library
/// between its build and its archive).
mod fmu {
    use super::{repository, target_dir, write_if_changed};
    use std::path::{Path, PathBuf};
    use std::process::Command;

    pub fn export(model: &str, ty: &str, outdir: &Path) -> Result<(), String> {
        let target = target_dir()?;
        let release = target.join("release");
        let dir = target.join("hamel-export").join(format!("{model}-fmu"));
        write_sources(&dir, ty)?;
        eprintln!("building the FMU of {model} ({})", dir.display());
        let manifest = repository().join("Cargo.toml");
        cargo(
            Command::new(cargo_program())
                .args(["build", "--release", "--manifest-path"])
                .arg(&manifest)
                .args(["-p", "hamel-export", "--features", "catalogue-fmu"])
                .args(["--example", "fmu_library", "--example", "fmu_tool"])
                .env("HAMEL_FMU_SOURCE", &dir)
                .env("CARGO_TARGET_DIR", &target),
            &format!("the FMU library of {model}"),
        )?;
        let examples = release.join("examples");
        let library = examples.join(format!(
            "{}fmu_library{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        ));
        let exe = std::env::consts::EXE_SUFFIX;
        let tool = release.join(format!("{model}-fmu{exe}"));
        let built = examples.join(format!("fmu_tool{exe}"));
        std::fs::copy(&built, &tool)
            .map_err(|e| format!("cannot copy {} to {}: {e}", built.display(), tool.display()))?;
        let description = dir.join("modelDescription.xml");
        run(Command::new(&tool).arg("description").arg(&description))?;

        let archiver = build_archiver(&target)?;
        std::fs::create_dir_all(outdir)
            .map_err(|e| format!("cannot create {}: {e}", outdir.display()))?;
        let fmu = outdir.join(format!("{ty}.fmu"));
        run(Command::new(&archiver)
            .arg(&fmu)
            .arg(ty)
            .arg(&description)
            .arg(&library))?;
        println!("{}", fmu.display());
        Ok(())
    }

    fn cargo_program() -> String {
        std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
    }

    /// Runs a cargo build, `what` naming it if it fails.
    fn cargo(command: &mut Command, what: &str) -> Result<(), String> {
        let status = command
            .status()
            .map_err(|e| format!("cannot run {}: {e}", cargo_program()))?;
        if status.success() {
            Ok(())
        } else {
            Err(format!("building {what} failed ({status})"))
        }
    }

    fn run(command: &mut Command) -> Result<(), String> {
        let program = command.get_program().to_string_lossy().into_owned();
        let status = command
            .status()
            .map_err(|e| format!("cannot run {program}: {e}"))?;
        if status.success() {
            Ok(())
        } else {
            Err(format!("{program} failed ({status})"))
        }
    }

    /// The sources the examples `fmu_library` and `fmu_tool` include: written only where
    /// they differ, so that a second export of the same model rebuilds nothing.
    fn write_sources(dir: &Path, ty: &str) -> Result<(), String> {
        let library = format!(
            "// The catalogue model {ty} as the FMU `{ty}` (written by hamel's `export` example).\n\
             hamel_export::model!(Exported => hamel_models::{ty});\n\
             hamel_export::fmi2!(Exported, \"{ty}\");\n"
        );
        let tool = format!(
            "// The command line of the FMU `{ty}` (written by hamel's `export` example).\n\
             hamel_export::model!(Exported => hamel_models::{ty});\n\
             fn main() -> std::process::ExitCode {{\n\
             \x20   hamel_export::fmi2::tool::main::<Exported>(\"{ty}\")\n\
             }}\n"
        );
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        write_if_changed(&dir.join("library.rs"), &library)?;
        write_if_changed(&dir.join("tool.rs"), &tool)
    }

    /// The program that writes an FMU's archive (`fmu-archive OUT.fmu IDENTIFIER
    /// DESCRIPTION LIBRARY`), built once: a crate of its own with zip alone.
    fn build_archiver(target: &Path) -> Result<PathBuf, String> {
        let repo = repository();
        let dir = target.join("hamel-export").join("fmu-archive");
        let archive = repo.join("hamel-export/src/fmi2/archive.rs");
        let manifest = r#"# Written by hamel's `export` example: the program that writes an FMU's archive.
[package]
name = "hamel-fmu-archive"
version = "0.1.0"
edition = "2024"
publish = false

[[bin]]
name = "fmu-archive"
path = "main.rs"

# The versions and features of hamel-export's feature `fmu`.
[dependencies]
zip = { version = "7", default-features = false, features = ["deflate-flate2"] }
flate2 = "1.1"

# Not a member of hamel's workspace, though inside its directory.
[workspace]

# Unoptimized: it compresses one library, in a quarter of a second for the robot's 1 MB,
# and builds in about half the time (5 s against 9 s of wall time at opt-level 3).
[profile.release]
opt-level = 0
"#;
        let main = format!(
            "//! Writes an FMU's archive: `fmu-archive OUT.fmu IDENTIFIER DESCRIPTION LIBRARY`\n\
             //! (written by hamel's `export` example).\n\
             #[path = {archive:?}]\n\
             mod archive;\n\
             \n\
             fn main() -> std::process::ExitCode {{\n\
             \x20   let args: Vec<String> = std::env::args().skip(1).collect();\n\
             \x20   let [out, identifier, description, library] = args.as_slice() else {{\n\
             \x20       eprintln!(\"usage: fmu-archive OUT.fmu IDENTIFIER DESCRIPTION LIBRARY\");\n\
             \x20       return std::process::ExitCode::FAILURE;\n\
             \x20   }};\n\
             \x20   let written = std::fs::read_to_string(description)\n\
             \x20       .map_err(|e| format!(\"cannot read {{description}}: {{e}}\"))\n\
             \x20       .and_then(|text| {{\n\
             \x20           let (library, out) = (library.as_ref(), out.as_ref());\n\
             \x20           archive::write_archive(identifier, &text, library, &[], out)\n\
             \x20       }});\n\
             \x20   match written {{\n\
             \x20       Ok(()) => std::process::ExitCode::SUCCESS,\n\
             \x20       Err(message) => {{\n\
             \x20           eprintln!(\"error: {{message}}\");\n\
             \x20           std::process::ExitCode::FAILURE\n\
             \x20       }}\n\
             \x20   }}\n\
             }}\n",
            archive = archive.display().to_string().replace('\\', "/"),
        );
        std::fs::create_dir_all(&dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        write_if_changed(&dir.join("Cargo.toml"), manifest)?;
        write_if_changed(&dir.join("main.rs"), &main)?;
        // The workspace's lock file: the same versions as hamel's own build, and no registry
        // look-up when they are in cargo's cache already.
        let lock = dir.join("Cargo.lock");
        if !lock.exists() {
            std::fs::copy(repo.join("Cargo.lock"), &lock)
                .map_err(|e| format!("cannot copy Cargo.lock: {e}"))?;
        }
        cargo(
            Command::new(cargo_program())
                .args(["build", "--release", "--manifest-path"])
                .arg(dir.join("Cargo.toml"))
                .env("CARGO_TARGET_DIR", target),
            "the FMU archiver",
        )?;
        let exe = std::env::consts::EXE_SUFFIX;
        Ok(target.join("release").join(format!("fmu-archive{exe}")))
    }
}
