//! The catalogue's models with bodies, each in a short run written as a scene page, with the
//! body the browser test finds on the screen and where the trajectory puts it.

use std::path::{Path, PathBuf};

use hamel::Vector;
use hamel::geometry::Mechanism;
use hamel::models::{ChaplyginBall, MobileRobot, Rattleback, RollingDisk, WhippleBicycle};
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
fn run<M: HamelSystem>(model: &M, x0: M::State, seconds: f64) -> Result<Trajectory, Error> {
    Simulation::new(model, x0)
        .end_time(seconds)
        .sample_interval(1.0 / 60.0)
        .project_holonomic(true)
        .run_constant(
            &DormandPrince::new(1e-8, 1e-10),
            <M::Inputs as Vector>::zeros(),
        )
}

/// The rolling disk leaning and turning for a second, its disk looked for.
pub fn rolling_disk(dir: &Path) -> Result<Case, Error> {
    let disk = RollingDisk::default();
    let rolling = disk
        .state_builder()
        .set("phi", 0.3)
        .set("spin_rate", -6.0)
        .set("yaw_rate", 1.0)
        .build()?;
    case(
        dir,
        "rolling_disk",
        &disk,
        &run(&disk, rolling, 1.0)?,
        "disk",
        true,
        [0.1, 0.5],
    )
}

/// Every catalogue model with bodies in a short run, written into `dir`, each with the body
/// looked for and two times to look at (where it has moved but is still in the first
/// sample's view: the test opens the pages with the camera fixed there).
pub fn cases(dir: &Path) -> Result<Vec<Case>, Error> {
    let bike = WhippleBicycle::default();
    let ride = bike
        .state_builder()
        .set("rear_wheel_rate", -4.6 / bike.r_r)
        .set("roll_rate", 0.5)
        .build()?;
    let ball = ChaplyginBall::default();
    let rolled = ball
        .state_builder()
        .set("beta", 1.0)
        .set("alpha_rate", 3.0)
        .set("gamma_rate", 1.0)
        .build()?;
    let celt = Rattleback::default();
    let spun = celt
        .state_builder()
        .set("yaw_rate", 3.0)
        .set("roll_rate", 0.5)
        .build()?;
    let robot = MobileRobot::default();
    let driven = robot
        .state_builder()
        .set("w4", 0.5)
        .set("w5", 0.6)
        .build()?;
    // A disk seen edge-on shows no hub: the disk turns slowly enough to face the camera at
    // both times.
    Ok(vec![
        // The rear frame's ellipsoid hides the rear wheel's hub from the camera: the front
        // wheel is looked for.
        case(
            dir,
            "whipple_bicycle",
            &bike,
            &run(&bike, ride, 1.0)?,
            "front_wheel",
            true,
            [0.1, 0.5],
        )?,
        rolling_disk(dir)?,
        case(
            dir,
            "chaplygin_ball",
            &ball,
            &run(&ball, rolled, 1.0)?,
            "ball",
            false,
            [0.1, 0.5],
        )?,
        case(
            dir,
            "rattleback",
            &celt,
            &run(&celt, spun, 1.0)?,
            "rattleback",
            false,
            [0.1, 0.6],
        )?,
        case(
            dir,
            "mobile_robot",
            &robot,
            &run(&robot, driven, 1.5)?,
            "right_wheel",
            true,
            [0.2, 1.2],
        )?,
    ])
}

/// The bicycle example's `--animate` ride (`examples/support/capsize.rs`).
#[path = "../../../examples/support/capsize.rs"]
pub mod capsize;

/// The bicycle falling as its weave grows, as `cargo run --features png --example bicycle -- --animate`
/// writes it, to `dir/bicycle_capsize.html`.
pub fn bicycle_capsize_page(dir: &Path) -> Result<PathBuf, Error> {
    let bike = WhippleBicycle::default();
    let path = dir.join("bicycle_capsize.html");
    Scene::new(&bike, &capsize::ride(&bike)?)?
        .show(capsize::SHOWN)
        .unit("speed", "m/s")
        .write_html(&path)?;
    Ok(path)
}

/// The bicycle riding straight at 5 m/s, in its self-stable speed range, for `seconds`
/// (about 100 m in 20 s), at 30 samples a second, written to `dir/long_ride.html`; and the
/// run.
pub fn long_ride(dir: &Path, seconds: f64) -> Result<(PathBuf, Trajectory), Error> {
    let bike = WhippleBicycle::default();
    let x0 = bike
        .state_builder()
        .set("rear_wheel_rate", -5.0 / bike.r_r)
        .set("roll_rate", 0.2)
        .build()?;
    let run = Simulation::new(&bike, x0)
        .end_time(seconds)
        .sample_interval(1.0 / 30.0)
        .project_holonomic(true)
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [0.0; 2])?;
    let html = dir.join("long_ride.html");
    Scene::new(&bike, &run)?.write_html(&html)?;
    Ok((html, run))
}
