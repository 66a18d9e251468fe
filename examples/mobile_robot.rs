//! The paper's mobile robot (Franke, Zaiczek, Röbenack, section 4), simulated end to end.
//!
//! ```text
//! cargo run --release --example mobile_robot                       # defaults
//! cargo run --release --example mobile_robot -- --alpha 1.0 --tau1 0.2 --t-end 5 --out run.csv
//! cargo run --release --example mobile_robot -- --integrator gauss2 --step 0.01 --t-end 1000
//! cargo run --release --example mobile_robot -- --animate robot.html
//! cargo run --release --example mobile_robot -- --help
//! ```
//!
//! The model is `hamel::models::MobileRobot` (hamel-models/src/mobile_robot.rs): kinetic and
//! potential energy of the body and the wheels, two rolling constraints, three
//! quasi-velocities, the motor torques. It prints a summary and writes one CSV row per
//! sample, `t,x,y,alpha,phi1,phi2,w3,w4,w5,tau1,tau2,energy,energy_balance`, and (feature
//! `plot`, on by default) a figure beside it with the same stem, `mobile_robot.svg`: the path
//! y against x, the pitch α against time and the energy drift against time. A run that takes
//! more than a second shows a progress bar on a terminal. `--integrator` picks the method:
//! Dormand–Prince (the default), RK4, the implicit midpoint rule, Gauss–Legendre with 2 or 3
//! stages (bounded energy error over long runs) or Radau5 (stiff), see
//! `hamel::docs::running`. `--animate robot.html` writes the run as a 3D scene of the
//! body and its two wheels, to open in a browser (`hamel::scene`).

use hamel::models::MobileRobot;
use hamel::{
    DormandPrince, GaussLegendre, HamelSystem, ImplicitMidpoint, Integrator, Parameters, Radau5,
    Rk4, Simulation, Trajectory,
};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

// The command line below reads `--animate` itself: `animate::request` goes unused here.
#[allow(dead_code)]
#[path = "support/animate.rs"]
mod animate;
#[path = "support/progress.rs"]
mod progress;

/// Everything the command line can set, with the defaults documented in `--help`.
struct Settings {
    robot: MobileRobot,
    state: [f64; 8],
    torques: [f64; 2],
    t_end: f64,
    dt_out: f64,
    rtol: f64,
    atol: f64,
    method: Method,
    /// The step of the fixed-step methods.
    step: f64,
    out: String,
    /// The 3D scene's file, if one is asked for.
    animate: Option<String>,
}

/// The integrators `--integrator` offers.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    DormandPrince,
    Rk4,
    Midpoint,
    Gauss2,
    Gauss3,
    Radau5,
}

impl Method {
    const ALL: [(&'static str, Method); 6] = [
        ("dopri5", Method::DormandPrince),
        ("rk4", Method::Rk4),
        ("midpoint", Method::Midpoint),
        ("gauss2", Method::Gauss2),
        ("gauss3", Method::Gauss3),
        ("radau5", Method::Radau5),
    ];

    fn parse(name: &str) -> Result<Method, String> {
        Method::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, m)| *m)
            .ok_or_else(|| {
                let names: Vec<&str> = Method::ALL.iter().map(|(n, _)| *n).collect();
                format!(
                    "option `--integrator`: unknown integrator `{name}`; the integrators are {}",
                    names.join(", ")
                )
            })
    }

    /// The method and its settings, as the run's header prints them.
    fn describe(self, s: &Settings) -> String {
        let tolerances = format!("rtol = {:e}, atol = {:e}", s.rtol, s.atol);
        match self {
            Method::DormandPrince => format!("Dormand–Prince 5(4), {tolerances}"),
            Method::Radau5 => format!("Radau IIA 5 (Radau5), {tolerances}"),
            Method::Rk4 => format!("RK4, step {}", s.step),
            Method::Midpoint => format!("implicit midpoint, step {}", s.step),
            Method::Gauss2 => format!("Gauss–Legendre, 2 stages (order 4), step {}", s.step),
            Method::Gauss3 => format!("Gauss–Legendre, 3 stages (order 6), step {}", s.step),
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            robot: MobileRobot::default(),
            // Tilted forward by 0.3 rad, rolling at 0.5 m/s and turning at 0.4 rad/s.
            state: [0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 0.5, 0.4],
            torques: [0.0, 0.0],
            t_end: 10.0,
            dt_out: 0.01,
            rtol: 1e-9,
            atol: 1e-12,
            method: Method::DormandPrince,
            step: 0.01,
            out: "mobile_robot.csv".into(),
            animate: None,
        }
    }
}

fn help() -> String {
    let d = Settings::default();
    let mut text = String::from(
        "Simulate the paper's mobile robot and write its trajectory as CSV.\n\n\
         Usage: mobile_robot [--option value]...\n\nParameters (default in brackets):\n",
    );
    for (name, doc) in MobileRobot::NAMES.iter().zip(MobileRobot::DOCS) {
        let value = d.robot.get(name).unwrap_or(f64::NAN);
        text += &format!("  --{name:<8} {doc} [{value}]\n");
    }
    text += "\nInitial state (coordinates, then quasi-velocities ω³ = α̇, ω⁴ = path speed, ω⁵ = yaw rate):\n";
    for (name, value) in MobileRobot::STATE.iter().zip(d.state) {
        text += &format!("  --{name:<8} [{value}]\n");
    }
    let names: Vec<&str> = Method::ALL.iter().map(|(n, _)| *n).collect();
    text += &format!(
        "\nInputs (constant motor torques, N m):\n  --tau1     [{}]\n  --tau2     [{}]\n\n\
         Integration:\n  --integrator  {} [dopri5]\n  \
         --t-end    end time, s [{}]\n  \
         --dt-out   sample interval, s [{}]\n  --rtol     relative tolerance (dopri5, radau5) [{}]\n  \
         --atol     absolute tolerance (dopri5, radau5) [{}]\n  \
         --step     step, s (rk4, midpoint, gauss2, gauss3) [{}]\n  \
         --out      CSV file, the figure beside it as .svg [{}]\n  \
         --animate  also write the run as a 3D scene, an HTML file to open in a browser\n  \
         --help     this text\n",
        d.torques[0],
        d.torques[1],
        names.join(" | "),
        d.t_end,
        d.dt_out,
        d.rtol,
        d.atol,
        d.step,
        d.out
    );
    text
}

/// Parse `--name value` pairs; every mistake is an error message, never a panic.
fn parse(args: &[String]) -> Result<Option<Settings>, String> {
    let mut s = Settings::default();
    let mut i = 0;
    while i < args.len() {
        let arg = &args[i];
        if arg == "--help" || arg == "-h" {
            return Ok(None);
        }
        let Some(name) = arg.strip_prefix("--") else {
            return Err(format!(
                "unexpected argument `{arg}`: options look like `--alpha 0.3` (see --help)"
            ));
        };
        let Some(raw) = args.get(i + 1) else {
            return Err(format!("option `--{name}` needs a value (see --help)"));
        };
        i += 2;
        if name == "out" {
            if figure_path(raw) == Path::new(raw) {
                return Err(format!(
                    "option `--out`: `{raw}` is the name of the figure written beside the CSV \
                     (the CSV's name with the extension svg); give the CSV another extension"
                ));
            }
            s.out = raw.clone();
            continue;
        }
        if name == "animate" {
            s.animate = Some(raw.clone());
            continue;
        }
        if name == "integrator" {
            s.method = Method::parse(raw)?;
            continue;
        }
        let value: f64 = raw
            .parse()
            .map_err(|_| format!("option `--{name}`: `{raw}` is not a number"))?;
        if !value.is_finite() {
            return Err(format!(
                "option `--{name}`: the value must be a finite number, not `{raw}`"
            ));
        }
        if let Some(k) = MobileRobot::STATE.iter().position(|n| *n == name) {
            s.state[k] = value;
        } else if let Some(k) = MobileRobot::INPUTS.iter().position(|n| *n == name) {
            s.torques[k] = value;
        } else if MobileRobot::NAMES.contains(&name) {
            s.robot.set(name, value).map_err(|e| e.to_string())?;
        } else {
            match name {
                "t-end" => s.t_end = value,
                "dt-out" => s.dt_out = value,
                "rtol" => s.rtol = value,
                "atol" => s.atol = value,
                "step" => s.step = value,
                _ => return Err(format!("unknown option `--{name}` (see --help)")),
            }
        }
    }
    Ok(Some(s))
}

fn run(s: &Settings) -> Result<(), hamel::Error> {
    // The output file is created before the run, so that a directory that does not exist
    // (or cannot be written) is an error at once, not after the whole run.
    let csv = std::fs::File::create(&s.out).map_err(|e| io_error(&s.out, &e))?;
    let robot = &s.robot;
    let q = MobileRobot::coordinates_of(&s.state);
    let speeds = MobileRobot::speeds_of(&s.state);
    let x0 = robot.state_from_speeds(0.0, &q, &speeds)?;
    println!(
        "Mobile robot (Franke, Zaiczek, Röbenack): n = 5 coordinates, p = 2 constraints, 8 states"
    );
    println!("parameters: {}", robot.parameter_values());
    println!("initial state: {}", MobileRobot::named_state(&x0));
    println!("torques: tau1 = {}, tau2 = {}", s.torques[0], s.torques[1]);
    println!(
        "integrator: {}; t = 0 … {} s, samples every {} s\n",
        s.method.describe(s),
        s.t_end,
        s.dt_out
    );
    let trajectory = match s.method {
        Method::DormandPrince => simulate(s, x0, &DormandPrince::new(s.rtol, s.atol))?,
        Method::Radau5 => simulate(s, x0, &Radau5::new(s.rtol, s.atol))?,
        Method::Rk4 => simulate(s, x0, &Rk4::new(s.step))?,
        Method::Midpoint => simulate(s, x0, &ImplicitMidpoint::new(s.step))?,
        Method::Gauss2 => simulate(s, x0, &GaussLegendre::new(2, s.step))?,
        Method::Gauss3 => simulate(s, x0, &GaussLegendre::new(3, s.step))?,
    };
    println!("{}", trajectory.summary());
    if let Some(last) = trajectory.row(trajectory.len() - 1) {
        let state = &last[1..=MobileRobot::STATE.len()];
        println!(
            "\nfinal state at t = {}: {}",
            last[0],
            hamel::NamedValues::new(MobileRobot::STATE, state)
        );
    }
    let mut writer = std::io::BufWriter::new(csv);
    trajectory
        .write_csv(&mut writer)
        .and_then(|()| writer.flush())
        .map_err(|e| io_error(&s.out, &e))?;
    println!(
        "wrote {} rows to {} ({})",
        trajectory.len(),
        s.out,
        trajectory.names().join(",")
    );
    #[cfg(feature = "plot")]
    {
        use hamel::plot::{Figure, Panel, Units};
        let path = figure_path(&s.out);
        // The axes carry the units the model states: y (m), alpha (rad), t (s), energy (J).
        let units = Units::of::<MobileRobot>();
        Figure::new()
            .columns(3)
            .panel(Panel::xy(&trajectory, "x", "y")?.units(&units))
            .panel(Panel::time_series(&trajectory, &["alpha"])?.units(&units))
            .panel(Panel::energy_drift(&trajectory)?.units(&units))
            .save(&path)?;
        println!(
            "wrote {} (the path, the pitch alpha and the energy drift)",
            path.display()
        );
    }
    if let Some(path) = &s.animate {
        let shown = ["x", "y", "alpha", "w4", "w5", "energy"];
        animate::write(robot, &trajectory, &shown, &[], Path::new(path))?;
    }
    Ok(())
}

/// The run with `integrator`, behind a progress bar.
fn simulate<I: Integrator>(
    s: &Settings,
    x0: [f64; 8],
    integrator: &I,
) -> Result<Trajectory, hamel::Error> {
    let bar = progress::Bar::default();
    let trajectory = Simulation::new(&s.robot, x0)
        .end_time(s.t_end)
        .sample_interval(s.dt_out)
        .on_progress(|p| bar.update(p))
        .run_constant(integrator, s.torques);
    bar.clear();
    trajectory
}

fn io_error(path: &str, e: &std::io::Error) -> hamel::Error {
    hamel::Error::Io {
        path: path.to_string(),
        message: e.to_string(),
    }
}

/// The figure's file: the CSV's path with the extension `svg`.
fn figure_path(csv: &str) -> PathBuf {
    Path::new(csv).with_extension("svg")
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match parse(&args) {
        Ok(None) => {
            print!("{}", help());
            ExitCode::SUCCESS
        }
        Ok(Some(settings)) => match run(&settings) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}
