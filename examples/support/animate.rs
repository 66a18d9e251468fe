//! The examples' `--animate PATH`: a run written as a 3D scene page (`hamel::scene`), to open
//! in a browser.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use hamel::Trajectory;
use hamel::geometry::Mechanism;
use hamel::scene::Scene;

/// What the command line asks for.
#[derive(Debug, PartialEq)]
pub enum Request {
    /// The example, writing its run as a scene to the path given after `--animate`, if any.
    Run(Option<PathBuf>),
    /// `--help` (or `-h`): the usage.
    Help,
}

/// Reads the command line: nothing, `--animate PATH` (or `--animate=PATH`), or `--help`;
/// anything else is an error naming the argument at fault.
pub fn request(args: &[String]) -> Result<Request, String> {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let unexpected = |other: &str| {
        format!(
            "unexpected argument `{other}`: the options are `--animate scene.html` and `--help`"
        )
    };
    let needs_name = || "option `--animate` needs a file name: `--animate scene.html`".to_string();
    let (path, rest) = match args.as_slice() {
        [] => return Ok(Request::Run(None)),
        ["--help" | "-h"] => return Ok(Request::Help),
        ["--animate", path, rest @ ..] if !path.starts_with('-') => (*path, rest),
        ["--animate", ..] => return Err(needs_name()),
        [flag, rest @ ..] if flag.starts_with("--animate=") => (&flag["--animate=".len()..], rest),
        [other, ..] => return Err(unexpected(other)),
    };
    match rest {
        _ if path.is_empty() => Err(needs_name()),
        [] => Ok(Request::Run(Some(PathBuf::from(path)))),
        [other, ..] => Err(unexpected(other)),
    }
}

/// The usage of an example that takes `--animate`: what it does (`about`), then the options.
pub fn usage(about: &str) -> String {
    let program = std::env::args()
        .next()
        .and_then(|p| {
            Path::new(&p)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| "example".into());
    format!(
        "{about}\n\nUsage: {program} [--animate FILE]\n  (no options)      the example: what \
         it prints, and the files it writes\n  --animate FILE    write the run as a 3D scene page \
         (HTML, opens from disk in a browser) to FILE\n  --help            this text\n"
    )
}

/// The examples' `main`: reads `--animate PATH`, `--help` or nothing from the command line
/// and runs `example` with the path; a wrong command line exits with 2, a failure with 1.
pub fn main(example: impl FnOnce(Option<PathBuf>) -> Result<(), hamel::Error>) -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match request(&args) {
        Ok(Request::Run(path)) => example(path),
        Ok(Request::Help) => {
            print!(
                "{}",
                usage("Runs the example, or writes its run as a 3D scene.")
            );
            return ExitCode::SUCCESS;
        }
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
/// units, the model's or those in `units`), and says so, with the scene's warnings (shown on
/// the page too).
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
    for warning in scene.warnings()? {
        eprintln!("warning: {warning}");
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
