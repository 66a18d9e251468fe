//! The examples' `--animate PATH`: a run written as a 3D scene page (`hamel::scene`), to open
//! in a browser.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use hamel::Trajectory;
use hamel::geometry::Mechanism;
use hamel::scene::Scene;

/// The path given after `--animate` on the command line, if the option is there; any other
/// argument is an error naming it.
pub fn requested(args: &[String]) -> Result<Option<PathBuf>, String> {
    match args {
        [] => Ok(None),
        [flag, path] if flag == "--animate" => Ok(Some(PathBuf::from(path))),
        [flag] if flag == "--animate" => Err("option `--animate` needs a file name".into()),
        [other, ..] => Err(format!(
            "unexpected argument `{other}`: the only option is `--animate scene.html`"
        )),
    }
}

/// The examples' `main`: reads `--animate PATH` (or nothing) from the command line and runs
/// `example` with it; a wrong command line exits with 2, a failure with 1.
pub fn main(example: impl FnOnce(Option<PathBuf>) -> Result<(), hamel::Error>) -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match requested(&args) {
        Ok(path) => example(path),
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Writes `run` of `model` to `path` as a scene, the columns `shown` beside it (with their
/// units, the model's or those in `units`), and says so.
pub fn write<M: Mechanism>(
    model: &M,
    run: &Trajectory,
    shown: &[&str],
    units: &[(&str, &str)],
    path: &Path,
) -> Result<(), hamel::Error> {
    let mut scene = Scene::new(model, run)?.show(shown.iter().copied());
    for (column, unit) in units {
        scene = scene.unit(column, unit);
    }
    scene.write_html(path)?;
    let times = run.times();
    println!(
        "wrote {}: {} samples, t = {} … {:.3} s, to open in a browser",
        path.display(),
        run.len(),
        times[0],
        times[times.len() - 1]
    );
    Ok(())
}
