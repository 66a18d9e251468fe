//! Programs that must compile, link and run: each case file is a `main` that asserts, compiled
//! by rustc with the given code-generation flags against the hamel cargo built for this test
//! (the same rustc, rlibs and working directory as the compile-fail cases), then run.
//!
//! For emitted code that once crashed rustc in one configuration only (full debuginfo):
//! cargo's dev profile may not be that configuration, so the flags are the check's own.

use super::{Outcome, Setup, report};
use std::path::Path;
use std::process::{Command, Output};

/// Compiles every `*.rs` in `cases_dir` (relative to the package) with `codegen_flags` into an
/// executable, runs it, and panics with every case whose rustc or program failed (a crash
/// included), with what it printed.
pub fn check_run_pass(cases_dir: &str, codegen_flags: &[&str]) {
    let setup = Setup::find(cases_dir);
    let outcomes = setup.each_case(|case| compile_and_run(&setup, case, codegen_flags));
    report(
        &outcomes,
        "programs did not compile, link and run",
        &format!(
            "Each was compiled with `rustc {}` against the hamel cargo built for this test.",
            codegen_flags.join(" ")
        ),
    );
}

fn compile_and_run(setup: &Setup, case: &str, codegen_flags: &[&str]) -> Outcome {
    let name = Path::new(case)
        .file_stem()
        .and_then(|stem| stem.to_str())
        .unwrap_or_default();
    let exe = setup.out_dir.join(name);
    // The crate is named after its file, so that cases compiled side by side in one directory
    // do not share the names of their object files. rustc's stack is its default one: a
    // RUST_MIN_STACK in the environment would hide the overflows these cases guard against.
    let compiled = setup
        .rustc(case, name)
        .arg("--color=never")
        .args(codegen_flags)
        .arg("-o")
        .arg(&exe)
        .env_remove("RUST_MIN_STACK")
        .output();
    let compiled = match compiled {
        Ok(output) => output,
        Err(e) => return Outcome::Failed(format!("cannot run {}: {e}", setup.rustc.display())),
    };
    let stderr = String::from_utf8_lossy(&compiled.stderr);
    if let Err(why) = setup.check_toolchain(&stderr) {
        return Outcome::Failed(why);
    }
    if !compiled.status.success() {
        return Outcome::Failed(failure("rustc", &compiled, &stderr));
    }
    match Command::new(&exe).output() {
        Ok(ran) if ran.status.success() => Outcome::Passed,
        Ok(ran) => Outcome::Failed(failure(
            "the program",
            &ran,
            &String::from_utf8_lossy(&ran.stderr),
        )),
        Err(e) => Outcome::Failed(format!("cannot run {}: {e}", exe.display())),
    }
}

/// What failed, how (exit code or signal: a crash of rustc shows as `signal: 11 (SIGSEGV)`),
/// and what it printed.
fn failure(what: &str, output: &Output, stderr: &str) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout);
    let mut text = format!("{what} failed ({}).\nstderr:\n{stderr}", output.status);
    if !stdout.trim().is_empty() {
        text += &format!("stdout:\n{stdout}");
    }
    text
}
