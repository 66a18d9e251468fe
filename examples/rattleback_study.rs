// The rattleback's spin reversal time against its base's curvatures, on `hamel::study`.
use hamel::models::Rattleback;
use hamel::prelude::*;
use hamel::study::{Study, steps};

fn reversal_time(r1: f64, r2: f64) -> Result<Vec<f64>, Error> {
    let mut body = Rattleback::default();
    (body.r1, body.r2) = (r1, r2);
    let tilted = [0.0, 0.0, 0.0, 0.0, 0.005, 0.005];
    let x0 = body.state_builder().coordinates(&tilted);
    let x0 = x0.speeds(&[3.0, 0.0, 0.0]).build()?;
    let yaw_rate = |_: f64, x: &[f64; 9]| x[Rattleback::N + Rattleback::YAW_RATE];
    let run = Simulation::new(&body, x0)
        .end_time(60.0)
        .event(Event::new("reversal", yaw_rate).falling().terminal())
        .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
    let times = run.event_times("reversal");
    let none = || Error::case_failed("no_reversal", "the spin did not reverse in 60 s");
    times.first().map(|&t| vec![t]).ok_or_else(none)
}

fn main() -> std::process::ExitCode {
    Study::new("rattleback_study", "Spin reversal time against curvatures")
        .parameter("r1", "m", "long radius", [0.1, 0.15, 0.2, 0.25, 0.3])
        .parameter("r2", "m", "cross radius", steps(0.02, 0.005, 5))
        .output("reversal_time", "s", "when a 3 rad/s spin reverses")
        .case(|row| reversal_time(row.get("r1")?, row.get("r2")?))
        .main()
}
