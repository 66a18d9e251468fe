//! The right-hand side with its parameter-only values prepared once (`prepare`,
//! `rhs_prepared`, what a simulation calls) against `rhs`, which computes them at every call:
//! the same bits for every catalogue model at seeded random states, the plain `rhs` for a
//! slice of the wrong length, and values prepared for other parameters are really read. The
//! right-hand side fused with the power (`rhs_power_prepared`, what a simulation of a forced
//! model calls) gives the bits of `rhs_prepared`, and `power` to rounding.

use crate::common::xorshift::XorShift;
use hamel::models::{
    BallOnTurntable, ChaplyginSleigh, KnifeEdge, MobileRobot, MobileRobotPaper, NTrailer1,
    NTrailer2, NTrailer8, NTrailer24, WhippleBicycle,
};
use hamel::{HamelSystem, Vector};

/// Random states per model.
const SAMPLES: usize = 50;

/// A state with every component in [−1, 1) and inputs in [−1, 1).
fn sample<S: HamelSystem>(rng: &mut XorShift) -> (S::State, S::Inputs) {
    let mut x = S::State::zeros();
    for v in x.as_mut() {
        *v = rng.uniform(-1.0, 1.0);
    }
    let mut u = S::Inputs::zeros();
    for v in u.as_mut() {
        *v = rng.uniform(-1.0, 1.0);
    }
    (x, u)
}

/// The values `system` prepares.
fn prepared<S: HamelSystem>(system: &S) -> Vec<f64> {
    let mut values = vec![0.0; S::PREPARED_LEN];
    system.prepare(&mut values);
    values
}

/// `rhs` and `rhs_prepared` (with `values`) at one state, as `Debug` text of the results
/// and the written derivatives: equal text is equal bits, errors included.
fn both<S: HamelSystem>(system: &S, values: &[f64], x: &S::State, u: &S::Inputs) -> [String; 2] {
    let (mut plain, mut fast) = (S::State::zeros(), S::State::zeros());
    let a = system.rhs(0.0, x, u, &mut plain);
    let b = system.rhs_prepared(values, 0.0, x, u, &mut fast);
    let bits = |d: &S::State| d.as_ref().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    [
        format!("{a:?} {:?}", bits(&plain)),
        format!("{b:?} {:?}", bits(&fast)),
    ]
}

/// Every sample gives the same bits through both paths; returns how many were regular.
fn same_bits<S: HamelSystem>(name: &str, system: &S, seed: u64) -> usize {
    let mut rng = XorShift::new(seed);
    let values = prepared(system);
    assert_eq!(values.len(), S::PREPARED_LEN, "{name}");
    let mut regular = 0;
    for _ in 0..SAMPLES {
        let (x, u) = sample::<S>(&mut rng);
        let [plain, fast] = both(system, &values, &x, &u);
        assert_eq!(plain, fast, "{name} at x = {x:?}, u = {u:?}");
        // The right-hand side and the power in one pass: the bits of each alone.
        let mut dx = S::State::zeros();
        let fused = system.rhs_power_prepared(&values, 0.0, &x, &u, &mut dx);
        let power = system.power(0.0, &x, &u);
        let bits = |d: &S::State| d.as_ref().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        match (fused, power) {
            (Ok(p), Ok(alone)) => {
                // Computed from shared values, the power may round differently.
                let scale = alone.abs().max(1.0);
                assert!((p - alone).abs() <= 1e-13 * scale, "{name}: {p} vs {alone}");
                assert_eq!(
                    format!("Ok(()) {:?}", bits(&dx)),
                    fast,
                    "{name} at x = {x:?}"
                );
            }
            (fused, _) => assert!(
                fast.starts_with("Err") && fused.is_err(),
                "{name}: {fused:?}"
            ),
        }
        let mut dx = S::State::zeros();
        regular += usize::from(system.rhs(0.0, &x, &u, &mut dx).is_ok());
    }
    println!(
        "{name}: {} prepared values, {regular} of {SAMPLES} states regular, equal bits",
        S::PREPARED_LEN
    );
    regular
}

#[test]
fn prepared_right_hand_sides_equal_rhs_bit_for_bit() {
    let regular = [
        same_bits("MobileRobot", &MobileRobot::default(), 1),
        same_bits("MobileRobotPaper", &MobileRobotPaper::default(), 2),
        same_bits("KnifeEdge", &KnifeEdge::default(), 3),
        same_bits("ChaplyginSleigh", &ChaplyginSleigh::default(), 4),
        same_bits("BallOnTurntable", &BallOnTurntable::default(), 5),
        same_bits("NTrailer1", &NTrailer1::default(), 6),
        same_bits("NTrailer2", &NTrailer2::default(), 7),
        same_bits("NTrailer8", &NTrailer8::default(), 8),
        same_bits("NTrailer24", &NTrailer24::default(), 9),
        same_bits("WhippleBicycle", &WhippleBicycle::default(), 10),
    ];
    // The comparison is of motions, not of errors alone.
    assert!(regular.iter().all(|&r| r > SAMPLES / 2), "{regular:?}");
}

/// A slice of another length is not read: `rhs_prepared` is then `rhs`, and `prepare`
/// leaves the slice as it was.
#[test]
fn a_slice_of_the_wrong_length_is_not_read() {
    let robot = MobileRobot::default();
    const { assert!(MobileRobot::PREPARED_LEN > 0) };
    let mut short = vec![7.0; MobileRobot::PREPARED_LEN - 1];
    robot.prepare(&mut short);
    assert!(short.iter().all(|&v| v == 7.0));
    let mut rng = XorShift::new(11);
    for _ in 0..SAMPLES {
        let (x, u) = sample::<MobileRobot>(&mut rng);
        let [plain, fast] = both(&robot, &short, &x, &u);
        assert_eq!(plain, fast);
        let [plain, fast] = both(&robot, &[], &x, &u);
        assert_eq!(plain, fast);
    }
}

/// Values prepared for other parameters change the result: `rhs_prepared` reads them
/// rather than computing them again (and a simulation must prepare for its own model).
#[test]
fn values_prepared_for_other_parameters_are_read() {
    let robot = MobileRobot::default();
    let heavier = MobileRobot {
        m0: 2.0 * robot.m0,
        ..robot.clone()
    };
    let stale = prepared(&robot);
    let mut rng = XorShift::new(12);
    let mut differing = 0;
    for _ in 0..SAMPLES {
        let (x, u) = sample::<MobileRobot>(&mut rng);
        let [plain, fast] = both(&heavier, &stale, &x, &u);
        differing += usize::from(plain != fast);
    }
    assert_eq!(differing, SAMPLES);
}
