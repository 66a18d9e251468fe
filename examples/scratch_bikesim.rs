use hamel::models::WhippleBicycle;
use hamel::prelude::*;
fn main() -> Result<(), hamel::Error> {
    let bike = WhippleBicycle::default();
    for (v, phi, phid) in [(4.6, 0.0, 0.5), (2.0, 0.01, 0.0)] {
        let x0 = bike
            .state_builder()
            .set("phi", phi)
            .set("roll_rate", phid)
            .set("rear_wheel_rate", -v / bike.r_r)
            .build()?;
        let t0 = std::time::Instant::now();
        let run = Simulation::new(&bike, x0)
            .end_time(5.0)
            .sample_interval(0.5)
            .run_constant(&DormandPrince::new(1e-10, 1e-10), [0.0, 0.0])?;
        println!("v = {v}: {:?}", t0.elapsed());
        let phis = run.column("phi").unwrap();
        let deltas = run.column("delta").unwrap();
        for (i, t) in run.times().iter().enumerate() {
            println!("  t={t:.1} phi={:+.5} delta={:+.5}", phis[i], deltas[i]);
        }
        println!("{}", run.summary());
    }
    Ok(())
}
