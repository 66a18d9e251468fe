//! Names of the constraint rows: `#[hamel_system(constraints(..))]` names them (the rows of
//! `#[constraints]`, then the holonomic ones; indexed groups as in the other lists), each name
//! gets an index constant and labels the constraint force's column `lambda_<name>`; without
//! the key, rows are named after their function and index, `blade0`.

use hamel::models::{
    BallOnTurntable, ChaplyginSleigh, KnifeEdge, MobileRobot, MobileRobotPaper, NTrailer2,
    WhippleBicycle,
};
use hamel::prelude::*;

#[test]
fn the_catalogue_names_its_constraints() {
    assert_eq!(KnifeEdge::CONSTRAINTS, ["blade"]);
    assert_eq!(ChaplyginSleigh::CONSTRAINTS, ["blade"]);
    // The robot from its wheels: a wheel's slip along its heading, then along its axle.
    assert_eq!(MobileRobot::CONSTRAINTS, ["no_slip", "no_side_slip"]);
    assert_eq!(MobileRobotPaper::CONSTRAINTS, ["no_side_slip", "no_slip"]);
    assert_eq!(BallOnTurntable::CONSTRAINTS, ["contact_x", "contact_y"]);
    assert_eq!(NTrailer2::CONSTRAINTS, ["axle0", "axle1", "axle2"]);
    assert_eq!(
        WhippleBicycle::CONSTRAINTS,
        ["rear_x", "rear_y", "front_x", "front_y", "front_z"]
    );
    // Index constants, within the constraint rows.
    assert_eq!((KnifeEdge::BLADE, MobileRobot::NO_SIDE_SLIP), (0, 1));
    assert_eq!((NTrailer2::AXLE, NTrailer2::AXLE2), (0, 2));
    assert_eq!(WhippleBicycle::FRONT_Z, 4);
}

#[hamel_system]
pub struct Railed {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
}

/// A sleigh on a rail y = x/2: one nonholonomic row and one holonomic constraint, named as
/// a group (`skid0`) and a raw identifier.
#[hamel_system(coordinates(x, y, theta), speeds(omega), constraints(skid[1], r#rail))]
impl Railed {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[holonomic(determines(y))]
    fn rail(&self, q: &[f64; 3]) -> [f64; 1] {
        [q[1] - 0.5 * q[0]]
    }

    #[quasi_velocities]
    fn speeds(&self, _q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[2]]
    }
}

/// The same without names.
#[hamel_system]
pub struct RailedDefault {
    pub m: f64,
    pub inertia: f64,
    pub a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(omega))]
impl RailedDefault {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[holonomic(determines(y))]
    fn rail(&self, q: &[f64; 3]) -> [f64; 1] {
        [q[1] - 0.5 * q[0]]
    }

    #[quasi_velocities]
    fn speeds(&self, _q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[2]]
    }
}

#[test]
fn named_rows_label_the_constraint_forces_and_the_errors() -> Result<(), hamel::Error> {
    assert_eq!(Railed::CONSTRAINTS, ["skid0", "rail"]);
    assert_eq!((Railed::SKID, Railed::SKID0, Railed::RAIL), (0, 0, 1));
    assert_eq!(RailedDefault::CONSTRAINTS, ["blade0", "rail0"]);

    let sleigh = Railed {
        m: 2.0,
        inertia: 0.5,
        a: 0.4,
    };
    let x0 = sleigh.state_from_speeds(0.0, &[0.0, 0.0, 0.3], &[1.0])?;
    let run = Simulation::new(&sleigh, x0)
        .end_time(0.5)
        .sample_interval(0.1)
        .record_constraint_forces(true)
        .run_constant(&DormandPrince::new(1e-10, 1e-12), [])?;
    let names = run.names();
    assert_eq!(names[names.len() - 2..], ["lambda_skid0", "lambda_rail"]);
    let last = run.len() - 1;
    let x: Vec<f64> = Railed::STATE
        .iter()
        .map(|name| run.column(name).unwrap()[last])
        .collect();
    let x: [f64; 4] = x.try_into().unwrap();
    let t = run.times()[last];
    let lambda = sleigh.constraint_forces(t, &x, &[])?;
    assert_eq!(
        run.column("lambda_rail").unwrap()[last],
        lambda[Railed::RAIL]
    );

    // Off the rail: the error names the constraint.
    let e = sleigh
        .state_from_speeds(0.0, &[0.0, 1.0, 0.3], &[1.0])
        .unwrap_err();
    assert!(e.to_string().contains("constraint `rail`"), "{e}");
    Ok(())
}
