//! The catalogue's models with bodies, each in a short run written as a scene page, with the
//! body the browser test finds on the screen and where the trajectory puts it.

use std::path::{Path, PathBuf};

use hamel::Vector;
use hamel::geometry::Mechanism;
use hamel::models::MobileRobot;
use hamel::prelude::*;
use hamel::scene::Scene;

/// One model's scene and what to look for in it.
pub struct Case {
    pub name: &'static str,
    pub html: PathBuf,
    pub times: Vec<f64>,
    /// The checked body's index and, at each sample, its centre.
    pub body: usize,
    pub centres: Vec<[f64; 3]>,
    /// Whether the body is a wheel (drawn with a dark hub at its centre).
    pub wheel: bool,
    /// The two samples looked at.
    pub samples: [usize; 2],
}

/// Writes the scene of `run` to `dir/<name>.html` and records where `body` is at each
/// sample.
fn case<M: Mechanism>(
    dir: &Path,
    name: &'static str,
    model: &M,
    run: &Trajectory,
    body: &str,
    wheel: bool,
    at: [f64; 2],
) -> Result<Case, Error> {
    let html = dir.join(format!("{name}.html"));
    Scene::new(model, run)?.write_html(&html)?;
    let index = M::BODIES
        .iter()
        .position(|b| *b == body)
        .ok_or_else(|| Error::Io {
            path: name.into(),
            message: format!("no body {body}"),
        })?;
    let columns: Vec<&[f64]> = M::COORDINATES
        .iter()
        .map(|c| run.column(c).unwrap_or(&[]))
        .collect();
    let centres = (0..run.len())
        .map(|i| {
            let q = <M::Coordinates as Vector>::from_slice(
                &columns.iter().map(|c| c[i]).collect::<Vec<_>>(),
            )
            .unwrap_or_else(<M::Coordinates as Vector>::zeros);
            model.bodies_at(run.times()[i], &q)[index].centre.to_array()
        })
        .collect();
    let sample = |t: f64| run.times().iter().position(|&s| s >= t - 1e-9).unwrap_or(0);
    Ok(Case {
        name,
        html,
        times: run.times().to_vec(),
        body: index,
        centres,
        wheel,
        samples: [sample(at[0]), sample(at[1])],
    })
}

/// A run of `seconds` at 60 samples a second.
fn run<M: HamelSystem>(
    model: &M,
    x0: M::State,
    seconds: f64,
    holonomic: bool,
) -> Result<Trajectory, Error> {
    Simulation::new(model, x0)
        .end_time(seconds)
        .sample_interval(1.0 / 60.0)
        .project_holonomic(holonomic)
        .run_constant(
            &DormandPrince::new(1e-8, 1e-10),
            <M::Inputs as Vector>::zeros(),
        )
}

/// Every catalogue model with bodies, written into `dir`.
pub fn cases(dir: &Path) -> Result<Vec<Case>, Error> {
    let robot = MobileRobot::default();
    let x0 = robot
        .state_builder()
        .set("w4", 0.5)
        .set("w5", 0.6)
        .build()?;
    let robot_run = run(&robot, x0, 1.5, false)?;
    Ok(vec![case(
        dir,
        "mobile_robot",
        &robot,
        &robot_run,
        "right_wheel",
        true,
        [0.2, 1.2],
    )?])
}

/// The bicycle capsizing (the bicycle example's `--animate` run), written to
/// `dir/bicycle_capsize.html`.
pub fn bicycle_capsize_page(dir: &Path) -> Result<PathBuf, Error> {
    let robot = MobileRobot::default();
    let x0 = robot.state_builder().set("w4", 0.5).build()?;
    let path = dir.join("bicycle_capsize.html");
    Scene::new(&robot, &run(&robot, x0, 10.0, false)?)?.write_html(&path)?;
    Ok(path)
}
