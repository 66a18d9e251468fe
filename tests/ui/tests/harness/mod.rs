//! Compiles each case file with rustc against the `hamel` library cargo already built for this
//! test, and compares the errors with the case's `.stderr`. (`run_pass.rs` compiles programs
//! the same way, links and runs them.)
//!
//! Why not trybuild: trybuild checks its cases in a cargo project of its own, with a target
//! directory of its own, so a fresh `cargo test --workspace` built every dependency of hamel a
//! second time (57 s of the suite's 320 s on two cores). Here rustc reads the rlibs cargo put
//! beside this test binary, and only the cases themselves are compiled (`--emit=metadata`, as
//! `cargo check` does). The output is normalized as trybuild normalized it (`normalize.rs`),
//! so the `.stderr` files keep their form.

mod normalize;
mod run_pass;

pub use run_pass::check_run_pass;

use normalize::Context;
use serde_json::Value;
use std::collections::HashSet;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The crate name each case is compiled as (shown as `$CRATE` in the `.stderr`).
const CASE_CRATE: &str = "hamel_ui_case";

/// The variable that rewrites the `.stderr` files from what rustc says now.
pub const OVERWRITE_VARIABLE: &str = "HAMEL_UI";

/// What a case gave: against what its `.stderr` says, or whether its program ran.
enum Outcome {
    Passed,
    Overwritten,
    Failed(String),
}

/// Compiles every `*.rs` in `cases_dir` (relative to the package) in parallel and checks each
/// against its `.stderr`; panics with every mismatch at once.
pub fn check_compile_fail(cases_dir: &str) {
    let setup = Setup::find(cases_dir);
    let overwrite = std::env::var(OVERWRITE_VARIABLE).is_ok_and(|v| v == "overwrite");
    let outcomes = setup.each_case(|case| setup.check(case, overwrite));
    report(
        &outcomes,
        "compile-fail cases did not give their .stderr",
        &format!(
            "If the new messages are right: {OVERWRITE_VARIABLE}=overwrite cargo test -p hamel-ui, \
             then read the diff."
        ),
    );
}

/// Prints each case's outcome; panics with every failure at once, `what` (after "N of M")
/// saying what went wrong and `advice` what to do about it.
fn report(outcomes: &[(String, Outcome)], what: &str, advice: &str) {
    let mut failures = String::new();
    let mut failed = 0;
    for (case, outcome) in outcomes {
        match outcome {
            Outcome::Passed => eprintln!("{case} ... ok"),
            Outcome::Overwritten => eprintln!("{case} ... wrote its .stderr"),
            Outcome::Failed(why) => {
                eprintln!("{case} ... FAILED");
                failed += 1;
                let _ = writeln!(failures, "\n==== {case}\n{why}");
            }
        }
    }
    let total = outcomes.len();
    assert!(
        failed == 0,
        "{failed} of {total} {what}:\n{failures}\n{advice}"
    );
}

/// Where rustc, the built libraries and the cases are.
struct Setup {
    rustc: PathBuf,
    /// `target/<profile>/deps`, where cargo put this test binary and hamel's rlibs.
    deps_dir: PathBuf,
    hamel_rlib: PathBuf,
    /// The package directory (`tests/ui/`): the `.stderr` files name the cases relative to it.
    package_dir: PathBuf,
    workspace_dir: PathBuf,
    /// The package directory relative to the workspace root, ending in `/` (`tests/ui/`).
    package_prefix: String,
    cases_dir: String,
    out_dir: PathBuf,
}

impl Setup {
    fn find(cases_dir: &str) -> Setup {
        let exe = std::env::current_exe().expect("the test binary's own path");
        let deps_dir = exe
            .parent()
            .expect("the test binary lies in target/<profile>/deps")
            .to_path_buf();
        let hamel_rlib = newest_hamel_rlib(&deps_dir);
        let package_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
        let workspace_dir = package_dir
            .join("../..")
            .canonicalize()
            .expect("the workspace root exists");
        let out_dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("hamel-ui");
        fs::create_dir_all(&out_dir).expect("a directory for the cases' metadata");
        // Cargo runs tests with the toolchain that built them; `RUSTC` names it when set, and
        // rustup's proxy otherwise resolves `rustc` to the same toolchain.
        let rustc = std::env::var_os("RUSTC").map_or_else(|| PathBuf::from("rustc"), PathBuf::from);
        let package = package_dir
            .canonicalize()
            .unwrap_or_else(|_| package_dir.clone());
        let package_prefix = directory(package.strip_prefix(&workspace_dir).unwrap_or(&package));
        Setup {
            rustc,
            deps_dir,
            hamel_rlib,
            package_dir,
            workspace_dir,
            package_prefix,
            cases_dir: cases_dir.to_owned(),
            out_dir,
        }
    }

    /// Runs `check` on every case file in parallel; the outcomes sorted by case.
    fn each_case(&self, check: impl Fn(&str) -> Outcome + Sync) -> Vec<(String, Outcome)> {
        let cases = self.cases();
        assert!(!cases.is_empty(), "no case files in {}", self.cases_dir);
        let next = AtomicUsize::new(0);
        let outcomes = Mutex::new(Vec::new());
        let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
        std::thread::scope(|scope| {
            for _ in 0..workers.min(cases.len()) {
                scope.spawn(|| {
                    while let Some(case) = cases.get(next.fetch_add(1, Ordering::Relaxed)) {
                        let outcome = check(case);
                        outcomes.lock().unwrap().push((case.clone(), outcome));
                    }
                });
            }
        });
        let mut outcomes = outcomes.into_inner().unwrap();
        outcomes.sort_by(|a, b| a.0.cmp(&b.0));
        outcomes
    }

    /// The case files, relative to the package directory, sorted.
    fn cases(&self) -> Vec<String> {
        let dir = self.package_dir.join(&self.cases_dir);
        let mut cases: Vec<String> = fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
            .filter_map(|entry| {
                let name = entry.ok()?.file_name().into_string().ok()?;
                name.ends_with(".rs")
                    .then(|| format!("{}/{name}", self.cases_dir))
            })
            .collect();
        cases.sort();
        cases
    }

    fn check(&self, case: &str, overwrite: bool) -> Outcome {
        let (failed, stderr) = match self.compile(case) {
            Ok(result) => result,
            Err(why) => return Outcome::Failed(why),
        };
        if !failed {
            return Outcome::Failed(format!(
                "expected a compile error, but it compiled.\nWarnings:\n{stderr}"
            ));
        }
        let expected_path = self.package_dir.join(case).with_extension("stderr");
        let expected = fs::read_to_string(&expected_path).ok();
        if expected.as_deref() == Some(stderr.as_str()) {
            return Outcome::Passed;
        }
        if overwrite {
            return match fs::write(&expected_path, &stderr) {
                Ok(()) => Outcome::Overwritten,
                Err(e) => Outcome::Failed(format!("cannot write {}: {e}", expected_path.display())),
            };
        }
        Outcome::Failed(match expected {
            None => format!(
                "{} is missing. rustc says:\n{stderr}",
                expected_path.display()
            ),
            Some(expected) => {
                let line = first_difference(&expected, &stderr);
                format!(
                    "first difference at line {line}\nexpected:\n{expected}\nrustc says:\n{stderr}"
                )
            }
        })
    }

    /// Checks one case as `cargo check` would; returns whether it failed to compile and its
    /// normalized diagnostics.
    fn compile(&self, case: &str) -> Result<(bool, String), String> {
        let out_file = self
            .out_dir
            .join(Path::new(case).file_stem().unwrap_or_default())
            .with_extension("rmeta");
        // The flags trybuild gave rustc, so that the messages are the ones users see under
        // cargo: dead code is not warned about, and notes are as wide as in a terminal. The
        // case's own path is remapped to the package-relative one the `.stderr` files show.
        let output = self
            .rustc(case, CASE_CRATE)
            .arg(format!("--remap-path-prefix={}=", self.package_prefix))
            .args(["--emit=metadata", "--error-format=json", "--color=never"])
            .args(["--diagnostic-width=140", "--verbose", "-A", "dead_code"])
            .arg("-o")
            .arg(&out_file)
            .output()
            .map_err(|e| format!("cannot run {}: {e}", self.rustc.display()))?;
        let raw = String::from_utf8_lossy(&output.stderr);
        self.check_toolchain(&raw)?;
        let context = Context {
            krate: CASE_CRATE,
            source_dir: &directory(&self.package_dir),
            workspace: &directory(&self.workspace_dir),
            input_file: case,
        };
        let (has_error, stderr) = diagnostics(&raw, &context)?;
        Ok((has_error || !output.status.success(), stderr))
    }

    /// rustc set to compile `case` as a binary crate named `crate_name` against hamel's rlib;
    /// the caller adds what to emit and where.
    ///
    /// rustc runs in the workspace root: cargo compiled hamel's crates from paths relative to
    /// it, and rustc finds their sources from there to quote them in notes.
    fn rustc(&self, case: &str, crate_name: &str) -> Command {
        let mut dependency_dir = std::ffi::OsString::from("dependency=");
        dependency_dir.push(&self.deps_dir);
        let mut extern_hamel = std::ffi::OsString::from("hamel=");
        extern_hamel.push(&self.hamel_rlib);
        let mut rustc = Command::new(&self.rustc);
        rustc
            .current_dir(&self.workspace_dir)
            .args([
                "--edition=2024",
                "--crate-type=bin",
                "--crate-name",
                crate_name,
            ])
            .arg("-L")
            .arg(&dependency_dir)
            .arg("--extern")
            .arg(&extern_hamel)
            .arg(format!("{}{case}", self.package_prefix));
        rustc
    }

    /// An `Err` that says what to do when rustc (by its `stderr`) could not read hamel's rlib.
    fn check_toolchain(&self, stderr: &str) -> Result<(), String> {
        if stderr.contains("compiled by an incompatible version of rustc") {
            return Err(format!(
                "{} is not the rustc that cargo built hamel with; set RUSTC to that one",
                self.rustc.display()
            ));
        }
        Ok(())
    }
}

/// rustc's JSON diagnostics, each normalized, joined by blank lines; and whether one was an
/// error. Anything else rustc printed (an internal compiler error) is an `Err`.
fn diagnostics(json_lines: &str, context: &Context) -> Result<(bool, String), String> {
    let mut seen = HashSet::new();
    let mut stderr = String::new();
    let mut has_error = false;
    for line in json_lines.lines().filter(|l| !l.trim().is_empty()) {
        let Ok(message) = serde_json::from_str::<Value>(line) else {
            return Err(format!(
                "rustc printed something that is not a diagnostic:\n{json_lines}"
            ));
        };
        let level = message["level"].as_str().unwrap_or_default();
        let rendered = message["rendered"].as_str().unwrap_or_default();
        if message["$message_type"] != "diagnostic" || level == "failure-note" || !seen.insert(line)
        {
            continue;
        }
        has_error |= level == "error";
        let normalized = normalize::diagnostic(rendered, context);
        if !stderr.is_empty() && !normalized.is_empty() {
            stderr.push('\n');
        }
        stderr += &normalized;
    }
    Ok((has_error, stderr))
}

/// The number (from 1) of the first line where two texts differ.
fn first_difference(a: &str, b: &str) -> usize {
    let (mut a, mut b) = (a.lines(), b.lines());
    let mut line = 1;
    while let (Some(x), Some(y)) = (a.next(), b.next()) {
        if x != y {
            break;
        }
        line += 1;
    }
    line
}

/// The `hamel` rlib cargo built last in `deps_dir`: the one of this build, when earlier builds
/// with other features left others beside it.
fn newest_hamel_rlib(deps_dir: &Path) -> PathBuf {
    let entries = fs::read_dir(deps_dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", deps_dir.display()));
    entries
        .filter_map(|entry| {
            let entry = entry.ok()?;
            let name = entry.file_name().into_string().ok()?;
            let hash = name.strip_prefix("libhamel-")?.strip_suffix(".rlib")?;
            let is_hamel = hash.bytes().all(|b| b.is_ascii_hexdigit());
            let modified = entry.metadata().ok()?.modified().ok()?;
            is_hamel.then(|| (modified, entry.path()))
        })
        .max()
        .map(|(_, path)| path)
        .unwrap_or_else(|| {
            panic!(
                "no libhamel-*.rlib in {}: run this suite through cargo (`cargo test -p hamel-ui`), \
                 which builds hamel first",
                deps_dir.display()
            )
        })
}

/// A directory's path with a trailing slash, as the normalization matches it.
fn directory(path: &Path) -> String {
    let mut text = path.to_string_lossy().replace('\\', "/");
    if !text.ends_with('/') {
        text.push('/');
    }
    text
}
