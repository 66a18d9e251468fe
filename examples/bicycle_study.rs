//! A parameter study of the Whipple bicycle (`hamel::models::WhippleBicycle`) on
//! `hamel::study`: its weave and capsize speeds — the ends of the self-stable speed range —
//! over trail × rider mass, drawn with the benchmark of Meijaard et al. (2007) marked.
//!
//! ```text
//! cargo run --release --features png,study --example bicycle_study   # the grid, on this machine
//! cargo run --release --features png,study --example bicycle_study -- --write-grid grid.csv
//! cargo run --release --features png,study --example bicycle_study -- --table grid.csv --shard 3/8 --out results
//! cargo run --release --features png,study --example bicycle_study -- --help
//! ```
//!
//! Each case tracks the lateral modes over 0 … 10 m/s in steps of 0.5 (`hamel::ModeSweep`)
//! and locates the ends of the self-stable range on the modes that cross there (Brent's
//! method, to 10⁻¹³ m/s). A rider of mass m scales the benchmark's rear body (frame and rider,
//! 85 kg) — its mass and moments of inertia by m/85, its centre of mass where it is; the trail
//! is the benchmark's `c`. Run on the grid, the study writes `bicycle_study.csv` (`.parquet`
//! with `--format parquet`), checks the benchmark point against Table 2 and draws
//! `bicycle_study.svg`/`.png` and the stability maps `bicycle_stability.svg`/`.png`
//! (`support/bicycle_study_figures.rs`).

use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};

use hamel::models::WhippleBicycle;
use hamel::prelude::*;
use hamel::study::{Finished, Study, steps};
use hamel::{Linearization, ModeSweep};

#[path = "support/bicycle_units.rs"]
mod bicycle_units;
#[path = "support/bicycle_study_figures.rs"]
mod figures;

use figures::BENCHMARK_RIDER;

/// The lateral states of the benchmark's linear equations.
const LATERAL: [&str; 4] = ["phi", "delta", "roll_rate", "steer_rate"];

/// Linearizations made so far, for the report.
static LINEARIZATIONS: AtomicUsize = AtomicUsize::new(0);

/// The benchmark bicycle with this trail and rider mass.
fn bicycle(trail: f64, rider_mass: f64) -> WhippleBicycle {
    let (k, b) = (rider_mass / BENCHMARK_RIDER, WhippleBicycle::default());
    let (m_b, i_bxx, i_byy) = (b.m_b * k, b.i_bxx * k, b.i_byy * k);
    let (i_bzz, i_bxz) = (b.i_bzz * k, b.i_bxz * k);
    WhippleBicycle {
        c: trail,
        m_b,
        i_bxx,
        i_byy,
        i_bzz,
        i_bxz,
        ..b
    }
}

/// The lateral linearization at speed v, upright and straight.
fn lateral(bike: &WhippleBicycle, v: f64) -> Result<Linearization, Error> {
    LINEARIZATIONS.fetch_add(1, Ordering::Relaxed);
    let x = bike
        .state_builder()
        .set("rear_wheel_rate", -v / bike.r_r)
        .build()?;
    bike.linearize(0.0, &x, &[0.0, 0.0])?.reduce(&LATERAL)
}

/// The weave and capsize speeds: the first self-stable range of 0 … 10 m/s.
fn critical_speeds(bike: &WhippleBicycle) -> Result<Vec<f64>, Error> {
    let linearize = |v| lateral(bike, v);
    let sweep = ModeSweep::track("v", steps(0.0, 0.5, 21), &linearize)?;
    match sweep.stable_ranges(&linearize)?.first() {
        Some(r) if r.opens.is_some() && r.closes.is_some() => Ok(vec![r.start, r.end]),
        Some(r) => Err(no_range(&format!(
            "it is self-stable from {} to {} m/s, an end of the scan",
            r.start, r.end
        ))),
        None => Err(no_range("it is unstable at every speed of the scan")),
    }
}

fn no_range(why: &str) -> Error {
    let message = format!("no self-stable speed range inside 0 … 10 m/s: {why}");
    Error::CaseFailed {
        kind: "no_self_stable_range".into(),
        message,
    }
}

/// The benchmark point's check, the figures and the stability maps.
fn report(run: &Finished) -> Result<(), Error> {
    let abscissa = |trail, mass, v| -> Result<f64, Error> {
        let values = lateral(&bicycle(trail, mass), v)?.eigenvalues()?;
        Ok(values
            .iter()
            .map(|l| l.re)
            .fold(f64::NEG_INFINITY, f64::max))
    };
    figures::report(run, &|| LINEARIZATIONS.load(Ordering::Relaxed), &abscissa)
}

fn main() -> ExitCode {
    Study::new("bicycle_study", "A parameter study of the Whipple bicycle: weave and capsize speeds over trail and rider mass.")
        .parameter("trail", "m", "the trail c", steps(0.04, 0.005, 17))
        .parameter("rider_mass", "kg", "the rear body's mass m_b (frame and rider)", steps(60.0, 2.5, 21))
        .output("weave_speed", "m/s", "where the self-stable range begins (the weave decays above)")
        .output("capsize_speed", "m/s", "where it ends (the capsize grows above)")
        .case(|row| critical_speeds(&bicycle(row.get("trail")?, row.get("rider_mass")?)))
        .report(report)
        .main()
}
