use super::*;
use crate::track_modes;
use nalgebra::DMatrix;

/// Two uncoupled real modes, λx = p − 1 and λz = 0.5 − p, and an oscillator
/// ẍ − (p − 1.5) ẋ + 4 x = 0 whose pair crosses at p = 1.5.
fn three(p: f64) -> Result<Linearization, Error> {
    #[rustfmt::skip]
    let a = DMatrix::from_row_slice(4, 4, &[
        p - 1.0, 0.0, 0.0, 0.0,
        0.0, 0.5 - p, 0.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        0.0, 0.0, -4.0, p - 1.5,
    ]);
    Linearization::new(&["x", "z", "u", "w"], &[], a, DMatrix::zeros(4, 0))
}

fn steps(n: i32, step: f64) -> impl Iterator<Item = f64> {
    (0..=n).map(move |i| step * f64::from(i))
}

#[test]
fn crossings_are_located_on_each_mode_to_the_tolerance() {
    let sweep = ModeSweep::track("p", steps(30, 0.1), &three).unwrap();
    let crossings = sweep.crossings(&three).unwrap();
    let found: Vec<(f64, bool)> = crossings
        .iter()
        .map(|c| (c.parameter, c.destabilizing))
        .collect();
    // z decays from p = 0.5, x grows from p = 1, the pair grows from 1.5 (both branches).
    let expected = [(0.5, false), (1.0, true), (1.5, true), (1.5, true)];
    assert_eq!(found.len(), expected.len(), "{found:?}");
    for ((p, up), (q, want)) in found.iter().zip(expected) {
        assert!((p - q).abs() < 1e-12, "{p} against {q}");
        assert_eq!(*up, want);
    }
    // The pair crosses with its frequency √(4 − 0): |Im λ| = 2 − (p−1.5)²/16 … at p = 1.5, 2.
    let pair = &crossings[2];
    assert!((pair.frequency - 2.0).abs() < 1e-12, "{}", pair.frequency);
    assert_eq!(crossings[0].frequency, 0.0);
    // Each crossing belongs to the branch whose vector is that state's.
    let z = &sweep.branches()[crossings[0].branch];
    assert_eq!(z.modes()[0].component("z").unwrap().re, 1.0);
    // Stable between z's crossing and x's.
    let ranges = sweep.stable_ranges(&three).unwrap();
    assert_eq!(ranges.len(), 1);
    assert!((ranges[0].start - 0.5).abs() < 1e-12 && (ranges[0].end - 1.0).abs() < 1e-12);
}

#[test]
fn stable_ranges_end_where_the_largest_real_part_crosses() {
    // λx = p − 1 and λz = 0.5 − p: stable on [0.5, 1] only.
    let two = |p: f64| {
        let a = DMatrix::from_row_slice(2, 2, &[p - 1.0, 0.0, 0.0, 0.5 - p]);
        Linearization::new(&["x", "z"], &[], a, DMatrix::zeros(2, 0))
    };
    let sweep = ModeSweep::track("p", steps(20, 0.1), &two).unwrap();
    let ranges = sweep.stable_ranges(&two).unwrap();
    assert_eq!(ranges.len(), 1);
    let r = &ranges[0];
    assert!(
        (r.start - 0.5).abs() < 1e-12 && (r.end - 1.0).abs() < 1e-12,
        "{r:?}"
    );
    assert!(!r.opens.as_ref().unwrap().destabilizing);
    assert!(r.closes.as_ref().unwrap().destabilizing);
    // A sweep that starts and ends stable has open ends.
    let ranges = ModeSweep::track("p", [0.6, 0.7, 0.8], &two)
        .unwrap()
        .stable_ranges(&two)
        .unwrap();
    assert_eq!((ranges[0].start, ranges[0].end), (0.6, 0.8));
    assert!(ranges[0].opens.is_none() && ranges[0].closes.is_none());
}

/// Branches that jump from one mode to another between two steps (a sweep too coarse for
/// the tracker) give an error, not a crossing at the jump.
#[test]
fn a_branch_that_jumps_is_an_error() {
    let two = |p: f64| {
        let a = DMatrix::from_row_slice(2, 2, &[p - 1.0, 0.0, 0.0, -0.5]);
        Linearization::new(&["x", "z"], &[], a, DMatrix::zeros(2, 0))
    };
    let steps: Vec<(f64, Vec<Mode>)> = [0.0, 1.6, 2.0]
        .iter()
        .map(|&p| (p, two(p).unwrap().modes().unwrap()))
        .collect();
    let branches = track_modes(steps).unwrap();
    // A sweep whose branch 0 is z's mode at p = 0 and x's afterwards.
    let mixed = mix(&branches[0], &branches[1]);
    let sweep = ModeSweep::from_branches("p", vec![mixed.0, mixed.1]);
    let e = sweep.crossings(&two).unwrap_err();
    assert!(matches!(e, Error::RootNotFound { .. }), "{e}");
    assert!(e.to_string().contains("may jump"), "{e}");
}

/// Two branches whose modes are exchanged after their first step.
fn mix(a: &ModeBranch, b: &ModeBranch) -> (ModeBranch, ModeBranch) {
    let steps = |first: &ModeBranch, rest: &ModeBranch| -> Vec<(f64, Vec<Mode>)> {
        (0..first.len())
            .map(|i| {
                let m = if i == 0 {
                    &first.modes()[0]
                } else {
                    &rest.modes()[i]
                };
                (first.parameters()[i], vec![m.clone()])
            })
            .collect()
    };
    let one = |s: Vec<(f64, Vec<Mode>)>| track_modes(s).unwrap().remove(0);
    (one(steps(a, b)), one(steps(b, a)))
}

#[cfg(feature = "ensemble")]
#[test]
fn the_table_has_the_parameter_and_each_named_mode() {
    let sweep = ModeSweep::track("p", steps(4, 0.5), &three)
        .unwrap()
        .name(0, "pair")
        .unwrap()
        .name(1, "pair")
        .unwrap();
    let table = sweep.table().unwrap();
    assert_eq!(table.names()[0], "p");
    assert_eq!(
        &table.names()[1..5],
        ["pair_1_re", "pair_1_im", "pair_2_re", "pair_2_im"]
    );
    assert_eq!(table.names().len(), 9);
    assert_eq!(table.len(), 5);
    assert_eq!(table.column("p").unwrap(), [0.0, 0.5, 1.0, 1.5, 2.0]);
    assert!(sweep.clone().name(4, "none").is_err());
    assert_eq!(sweep.branch("pair").unwrap(), &sweep.branches()[0]);
}
