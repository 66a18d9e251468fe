//! The Whipple bicycle benchmark (Meijaard, Papadopoulos, Ruina & Schwab, Proc. R. Soc. A
//! 463, 1955–1982, 2007) from the nonlinear model `hamel::models::WhippleBicycle`:
//!
//! 1. linearized about upright, straight running for v = 0 … 10 m/s: the eigenvalues of the
//!    lateral motion (roll φ, steer δ and their rates), printed for whole speeds (the
//!    paper's Table 2), written to `bicycle_eigenvalues.csv` and plotted against speed in
//!    the manner of the paper's Figure 3 (`bicycle_eigenvalues.svg` and `.png`): each mode
//!    followed along the speed by the continuity of its eigenvector (`hamel::track_modes`)
//!    and named by its behaviour — the weave (a complex pair, two real modes below 0.68
//!    m/s), the capsize (the real mode that crosses zero at the capsize speed) and the
//!    castor (the large negative one);
//! 2. the weave and capsize speeds, the ends of the self-stable range, located on the modes
//!    that cross zero there (`hamel::ModeSweep::stable_ranges`);
//! 3. two nonlinear simulations: at 4.6 m/s, inside the self-stable range, a push in roll
//!    rate dies out; at 2 m/s, below the weave speed, a small lean grows into the weave (a
//!    simulation that takes more than a second shows a progress bar on a terminal).
//!
//! With `--animate bicycle.html` it does none of that, but rides from upright at 3 m/s,
//! below the weave speed, until the growing weave makes the bicycle fall (the run ends where
//! the front wheel turns square across the frame, just before the model stops determining
//! the motion: `support/capsize.rs`), and writes the ride as a 3D scene to open in a
//! browser (`hamel::scene`).
//!
//! ```text
//! cargo run --release --features png --example bicycle
//! cargo run --release --features png --example bicycle -- --animate bicycle.html
//! ```

use hamel::models::WhippleBicycle;
use hamel::plot::{Figure, PALETTE, Panel, Rgb, Series};
use hamel::prelude::*;
use hamel::{Linearization, Mode, ModeBranch, ModeSweep, track_modes};
use std::fmt::Write as _;
use std::process::ExitCode;

#[path = "support/animate.rs"]
mod animate;
#[path = "support/bicycle_units.rs"]
mod bicycle_units;
#[path = "support/capsize.rs"]
mod capsize;
#[path = "support/progress.rs"]
mod progress;

/// The lateral states of the benchmark's linear equations.
const LATERAL: [&str; 4] = ["phi", "delta", "roll_rate", "steer_rate"];

/// The lateral linearization at speed v.
fn lateral(bike: &WhippleBicycle, v: f64) -> Result<Linearization, Error> {
    let x = bike
        .state_builder()
        .set("rear_wheel_rate", -v / bike.r_r)
        .build()?;
    bike.linearize(0.0, &x, &[0.0, 0.0])?.reduce(&LATERAL)
}

/// The modes at speed v, least stable first.
fn modes(bike: &WhippleBicycle, v: f64) -> Result<Vec<Mode>, Error> {
    lateral(bike, v)?.modes()
}

/// The weave and capsize speeds: the ends of the self-stable range of the sweep's tracked
/// modes, each located on the mode that crosses there (`hamel::ModeSweep`).
fn critical_speeds(bike: &WhippleBicycle, all: &Sweep) -> Result<(f64, f64), Error> {
    let sweep = ModeSweep::from_branches("v", track_modes(all.iter().cloned())?);
    let linearize = |v| lateral(bike, v);
    match sweep.stable_ranges(&linearize)?.first() {
        Some(r) if r.opens.is_some() && r.closes.is_some() => Ok((r.start, r.end)),
        _ => Err(unnamed(
            "weave and capsize (no self-stable range inside 0 … 10 m/s)",
        )),
    }
}

/// The modes at each speed of a sweep.
type Sweep = Vec<(f64, Vec<Mode>)>;

/// The eigenvalues at v = 0, 0.01, …, 10, as CSV rows `v,re1,im1,…,re4,im4`, the modes in the
/// order `modes` gives (least stable first).
fn sweep(bike: &WhippleBicycle) -> Result<(String, Sweep), Error> {
    let mut csv = String::from("v,re1,im1,re2,im2,re3,im3,re4,im4\n");
    let mut all = Vec::new();
    for i in 0..=1000 {
        let v = i as f64 / 100.0;
        let m = modes(bike, v)?;
        let _ = write!(csv, "{v}");
        for mode in &m {
            let _ = write!(csv, ",{:?},{:?}", mode.value.re, mode.value.im);
        }
        csv.push('\n');
        all.push((v, m));
    }
    Ok((csv, all))
}

/// Table 2's layout: whole speeds, the four eigenvalues in columns wide enough for
/// imaginary parts of two digits (10.90681 at v = 10).
fn table(all: &[(f64, Vec<Mode>)]) -> String {
    let mut text = String::from("   v     eigenvalues (1/s), least stable first\n");
    for (v, m) in all.iter().filter(|(v, _)| v.fract() == 0.0) {
        let mut line = format!("{v:>4}  ");
        for mode in m {
            let l = mode.value;
            if l.im == 0.0 {
                let _ = write!(line, "  {:>+9.5}{:11}", l.re, "");
            } else {
                let _ = write!(line, "  {:>+9.5} {:>+9.5}i", l.re, l.im);
            }
        }
        text.push_str(line.trim_end());
        text.push('\n');
    }
    text
}

/// The bicycle's lateral modes along the sweep, each followed by the continuity of its
/// eigenvector (`hamel::track_modes`) and named by its behaviour.
struct NamedModes {
    /// The two branches of the weave: a complex pair above `split`, two real modes below.
    weave: [ModeBranch; 2],
    /// The real mode whose eigenvalue crosses zero at the capsize speed.
    capsize: ModeBranch,
    /// The large negative real mode.
    castor: ModeBranch,
    /// The highest speed of the sweep at which the weave is two real modes.
    split: f64,
}

/// Follows the four lateral modes along the sweep and names them: the weave is the pair of
/// branches that are complex at 5 m/s; of the two real ones, the castor is the more
/// negative at the highest speed and the capsize the other. The names are checked against
/// what they claim: the weave's real part changes sign at the weave speed, the capsize's
/// eigenvalue at the capsize speed.
fn named_modes(all: &Sweep, weave_speed: f64, capsize_speed: f64) -> Result<NamedModes, Error> {
    let branches = track_modes(all.iter().cloned())?;
    let value_at = |b: &ModeBranch, v: f64| b.nearest(v).map_or(f64::NAN.into(), |(_, m)| m.value);
    let (complex, real): (Vec<ModeBranch>, Vec<ModeBranch>) = branches
        .into_iter()
        .partition(|b| value_at(b, 5.0).im != 0.0);
    let [first, second] = <[ModeBranch; 2]>::try_from(complex).map_err(|_| unnamed("weave"))?;
    let [a, b] = <[ModeBranch; 2]>::try_from(real).map_err(|_| unnamed("capsize and castor"))?;
    let last = |b: &ModeBranch| b.modes().last().map_or(f64::NAN, |m| m.value.re);
    let (castor, capsize) = if last(&a) < last(&b) { (a, b) } else { (b, a) };
    // Each name must hold: a sign change of the named branch's real part around its speed.
    let crosses = |b: &ModeBranch, v: f64| {
        value_at(b, v - 0.05).re.signum() != value_at(b, v + 0.05).re.signum()
    };
    if !crosses(&first, weave_speed) || !crosses(&capsize, capsize_speed) {
        return Err(unnamed(
            "weave and capsize (their eigenvalues do not cross zero at their speeds)",
        ));
    }
    let split = first
        .parameters()
        .iter()
        .zip(first.modes())
        .filter(|&(&v, m)| v < 5.0 && m.value.im == 0.0)
        .map(|(&v, _)| v)
        .fold(f64::NAN, f64::max);
    Ok(NamedModes {
        weave: [first, second],
        capsize,
        castor,
        split,
    })
}

/// The error for modes that do not behave as their names say.
fn unnamed(which: &str) -> Error {
    Error::Io {
        path: "bicycle_eigenvalues.svg".into(),
        message: format!("the tracked modes could not be named {which}"),
    }
}

/// The colours of the modes: blue for the weave, orange for the capsize — the pair of the
/// Tableau palette colour-blind readers tell apart best, for the two modes that bound the
/// self-stable range — and grey for the castor, which is stable at every speed.
const WEAVE: Rgb = PALETTE[0];
const CAPSIZE: Rgb = PALETTE[1];
const CASTOR: Rgb = PALETTE[7];

/// The paper's Figure 3: the eigenvalues of the lateral motion against speed, each mode
/// named and in its own colour, real parts solid and the weave's imaginary part dashed, the
/// weave and capsize speeds marked where the real parts cross zero.
fn figure(modes: &NamedModes, weave: f64, capsize: f64) -> Figure {
    // The weave's two branches in one series, broken between them (NaN): below the split
    // they are two real eigenvalues, above it one real part.
    let (mut v, mut re) = (Vec::new(), Vec::new());
    for branch in &modes.weave {
        v.extend_from_slice(branch.parameters());
        re.extend(branch.eigenvalues().map(|l| l.re));
        v.push(f64::NAN);
        re.push(f64::NAN);
    }
    // |Im λ| where the weave oscillates, nothing where it is real.
    let upper = &modes.weave[0];
    let im: Vec<f64> = upper
        .eigenvalues()
        .map(|l| if l.im == 0.0 { f64::NAN } else { l.im.abs() })
        .collect();
    let real = |b: &ModeBranch| b.eigenvalues().map(|l| l.re).collect::<Vec<f64>>();
    let units = bicycle_units::units();
    let speed = |v: f64| match units.unit("v") {
        Some(unit) => format!("{v:.2} {unit}"),
        None => format!("{v:.2}"),
    };
    let panel = Panel::new("Whipple bicycle: eigenvalues of the lateral motion")
        .x_label(units.label("forward speed v", "v"))
        .y_label(units.label("eigenvalue λ", "λ"))
        .y_range(-10.0, 10.0)
        .series(
            Series::line(
                format!("weave, Re λ (two real λ below {})", speed(modes.split)),
                &v,
                &re,
            )
            .color(WEAVE),
        )
        .series(Series::dashed("weave, |Im λ|", upper.parameters(), &im).color(WEAVE))
        .series(
            Series::line("capsize", modes.capsize.parameters(), &real(&modes.capsize))
                .color(CAPSIZE),
        )
        .series(
            Series::line("castor", modes.castor.parameters(), &real(&modes.castor)).color(CASTOR),
        )
        .series(
            Series::points(
                format!("self-stable from {} to {}", speed(weave), speed(capsize)),
                &[weave, capsize],
                &[0.0, 0.0],
            )
            .color(Rgb(0, 0, 0)),
        );
    Figure::from(panel).size(1100, 600)
}

/// A nonlinear run from upright at speed v with an initial lean and roll rate, sampled
/// every `every` seconds; the holonomic front contact is kept by projection.
fn ride(
    bike: &WhippleBicycle,
    v: f64,
    (lean, roll_rate): (f64, f64),
    seconds: f64,
    every: f64,
) -> Result<Trajectory, Error> {
    let x = bike
        .state_builder()
        .set("phi", lean)
        .set("roll_rate", roll_rate)
        .set("rear_wheel_rate", -v / bike.r_r)
        .build()?;
    let bar = progress::Bar::default();
    Simulation::new(bike, x)
        .end_time(seconds)
        .sample_interval(every)
        .project_holonomic(true)
        .on_progress(|p| bar.update(p))
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [0.0, 0.0])
}

/// The roll and steer angles of a run, one line per sample.
fn angles(run: &Trajectory) -> String {
    let (t, phi, delta) = (
        run.times(),
        run.column("phi").unwrap_or(&[]),
        run.column("delta").unwrap_or(&[]),
    );
    let mut text = String::from("     t      roll φ     steer δ  (rad)\n");
    for i in 0..t.len() {
        let _ = writeln!(
            text,
            "  {:>4.2}  {:>+9.5}  {:>+9.5}",
            t[i], phi[i], delta[i]
        );
    }
    text
}

fn run() -> Result<(), Error> {
    let bike = WhippleBicycle::default();
    println!("Whipple bicycle benchmark (Meijaard, Papadopoulos, Ruina & Schwab 2007)");
    println!("n = 8 coordinates, p = 5 constraints (1 holonomic), 11 states; Table 1 parameters\n");

    let (csv, all) = sweep(&bike)?;
    println!("{}", table(&all));
    let (weave, capsize) = critical_speeds(&bike, &all)?;
    println!("weave speed   {weave:.14} m/s   (paper: 4.29238253634111)");
    println!("capsize speed {capsize:.14} m/s   (paper: 6.02426201538837)");
    println!("self-stable between them\n");

    std::fs::write("bicycle_eigenvalues.csv", csv).map_err(|e| Error::Io {
        path: "bicycle_eigenvalues.csv".into(),
        message: e.to_string(),
    })?;
    println!("wrote {} rows to bicycle_eigenvalues.csv", all.len());
    let named = named_modes(&all, weave, capsize)?;
    let plot = figure(&named, weave, capsize);
    plot.save("bicycle_eigenvalues.svg")?;
    plot.save("bicycle_eigenvalues.png")?;
    println!(
        "wrote bicycle_eigenvalues.svg and bicycle_eigenvalues.png (the paper's Figure 3: \
         the modes followed along the speed and named, the weave two real eigenvalues up to \
         {:.2} m/s and a complex pair above, the capsize and the castor)",
        named.split
    );

    let stable = ride(&bike, 4.6, (0.0, 0.5), 5.0, 0.5)?;
    println!("\nv = 4.6 m/s (self-stable), from upright with a roll rate of 0.5 rad/s: the");
    println!("oscillation dies out\n{}", angles(&stable));
    println!("{}\n", stable.summary());
    let weaving = ride(&bike, 2.0, (0.01, 0.0), 1.5, 0.25)?;
    let weave = modes(&bike, 2.0)?[0].value;
    println!("v = 2 m/s (below the weave speed), from a lean of 0.01 rad: the weave grows, ");
    println!(
        "e-fold every {:.2} s (its eigenvalue {:.4} ± {:.4}i)\n{}",
        1.0 / weave.re,
        weave.re,
        weave.im.abs(),
        angles(&weaving)
    );
    Ok(())
}

/// The bicycle falling over as its weave grows, as a scene at `path`.
fn animate(path: &std::path::Path) -> Result<(), Error> {
    let bike = WhippleBicycle::default();
    let ride = capsize::ride(&bike)?;
    let (fallen, across) = (ride.event_times("fallen"), ride.event_times("across"));
    let end = match (fallen.first(), across.first()) {
        (Some(t), _) => format!("the roll angle reaches 60° at t = {t:.3} s"),
        (None, Some(t)) => format!(
            "the weave grows until it falls: the front wheel turns square across the frame \
             at t = {t:.3} s (roll {:.2} rad, steer {:.2} rad), just before the model's \
             constraints stop determining the motion",
            last(&ride, "phi"),
            last(&ride, "delta")
        ),
        (None, None) => format!("still up at t = {} s", ride.times()[ride.len() - 1]),
    };
    println!(
        "from upright at {} m/s with a lean of {} rad: {end}",
        capsize::SPEED,
        capsize::LEAN
    );
    animate::write(&bike, &ride, &capsize::SHOWN, &[("speed", "m/s")], path)
}

/// The last value of a column of the run.
fn last(run: &Trajectory, column: &str) -> f64 {
    run.column(column)
        .and_then(|c| c.last().copied())
        .unwrap_or(f64::NAN)
}

fn main() -> ExitCode {
    animate::main(|path| match path {
        Some(path) => animate(&path),
        None => run(),
    })
}
