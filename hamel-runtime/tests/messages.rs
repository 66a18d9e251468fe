//! How errors and named values read: `Debug` of an [`Error`] is its message (what
//! `fn main() -> Result<(), Error>` prints), and numbers in messages have bounded digits.

use hamel_runtime::{AssemblyFailure, Error, NamedValues, Num};

/// A state as the numbers an integration produces: long decimal expansions, extremes and
/// values that are not finite.
fn awkward_state() -> NamedValues {
    NamedValues::new(
        &[
            "huge", "tiny", "nan", "inf", "neg", "sum", "t_like", "zero", "whole",
        ],
        &[
            1e300,
            1e-300,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.1 + 0.2,
            2.6692648621662616,
            0.0,
            -16.0,
        ],
    )
}

/// One error of each shape: plain values, a time and a state, strings only.
fn samples() -> Vec<Error> {
    vec![
        Error::ConstraintViolation {
            name: "no_slip[0]".into(),
            residual: 1.0,
            tolerance: 1e-10,
        },
        Error::InvalidParameter {
            name: "m".into(),
            value: f64::NAN,
        },
        Error::StepSizeUnderflow {
            t: 2.6692648621662616,
            h: 1e-300,
            state: awkward_state(),
        },
        Error::Assembly {
            constraint: "contact[0]".into(),
            coordinate: "theta".into(),
            t: 0.1 + 0.2,
            failure: AssemblyFailure::Singular { pivot: 1e-17 },
            residual: 0.5,
            configuration: awkward_state(),
        },
        Error::UnknownStateName {
            name: "z".into(),
            known: "coordinates x, y".into(),
        },
    ]
}

/// `fn main() -> Result<(), Error>` prints `Error: {e:?}`: the message, not the variant's
/// fields, as for anyhow's errors.
#[test]
fn debug_prints_the_message() {
    for e in samples() {
        let message = e.to_string();
        assert_eq!(format!("{e:?}"), message);
        assert_eq!(format!("Error: {e:?}"), format!("Error: {message}"));
        // `{:#?}` too: no multi-line struct dump.
        assert_eq!(format!("{e:#?}"), message);
    }
    let e = &samples()[0];
    assert!(format!("{e:?}").starts_with("the initial velocities violate constraint"));
    // A result unwrapped in a test shows the message as well.
    let result: Result<(), Error> = Err(e.clone());
    let shown = format!("{result:?}");
    assert!(
        shown.contains("violate constraint `no_slip[0]`") && !shown.contains("residual:"),
        "{shown}"
    );
}

#[test]
fn named_values_display_with_bounded_digits() {
    assert_eq!(
        awkward_state().to_string(),
        "huge = 1e300, tiny = 1e-300, nan = NaN, inf = inf, neg = -inf, sum = 0.3, \
         t_like = 2.669, zero = 0, whole = -16"
    );
    // Debug stays exact, for diagnostics: the value itself, as Rust writes it.
    let debug = format!("{:?}", awkward_state());
    assert!(
        debug.contains("sum: 0.30000000000000004") && debug.contains("t_like: 2.6692648621662616"),
        "{debug}"
    );
}

#[test]
fn numbers_in_messages_have_bounded_digits() {
    let [_, invalid, underflow, assembly, _] = &samples()[..] else {
        unreachable!()
    };
    assert_eq!(
        invalid.to_string(),
        "parameter `m` is NaN: parameters must be finite numbers"
    );
    let text = underflow.to_string();
    assert!(
        text.starts_with(
            "step size underflow at t = 2.669: a step of 1e-300 is below the smallest step"
        ) && text.contains("; state: huge = 1e300, tiny = 1e-300"),
        "{text}"
    );
    let text = assembly.to_string();
    assert!(text.contains("at t = 0.3:"), "{text}");
    for e in samples() {
        let text = e.to_string();
        // No number runs to more than 6 digits (`-16.67`, `1.235e-7`, `12346`).
        let longest = text
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest <= 6, "a long number in: {text}");
    }
}

#[test]
fn non_finite_values_in_messages() {
    let e = Error::NonFiniteInitialValue {
        name: "x".into(),
        value: f64::NEG_INFINITY,
    };
    assert_eq!(
        e.to_string(),
        "initial value of `x` is -inf: it must be a finite number"
    );
    let e = Error::NonFiniteDerivative {
        of: "the rate of `v`".into(),
        by: "x".into(),
        value: f64::NAN,
        at: "at the operating point".into(),
    };
    assert!(
        e.to_string().contains("derivative NaN with respect to `x`"),
        "{e}"
    );
    assert_eq!(Num(f64::NAN).to_string(), "NaN");
    assert_eq!(Num(0.1 + 0.2).to_string(), "0.3");
}

/// A failed LDLᵀ pivot check, sorted: rounding below zero is still a singular matrix, a
/// pivot negative beyond the tolerance an indefinite one, a NaN or infinite pivot or scale
/// neither.
#[test]
fn failed_mass_pivots_are_told_apart() {
    use hamel_runtime::Singularity;
    let tol = 1e-13;
    let singular = |value| Singularity::MassMatrix { speed: 2, value };
    let singular_at = |speed, value| Singularity::MassMatrix { speed, value };
    assert_eq!(Singularity::mass_pivot(2, 0.0, 0.0, tol), singular(0.0));
    assert_eq!(
        Singularity::mass_pivot(2, -1e-17, 1.0, tol),
        singular(-1e-17)
    );
    // Positive, but zero beside a huge diagonal entry (the falling bicycle's case).
    assert_eq!(
        Singularity::mass_pivot(2, 2.57, 3.5e13, tol),
        singular(2.57)
    );
    assert_eq!(
        Singularity::mass_pivot(2, -1e-12, 1.0, tol),
        Singularity::IndefiniteMassMatrix {
            speed: 2,
            value: -1e-12
        }
    );
    // A zero diagonal entry with a negative pivot: coupling to the speeds before it.
    assert_eq!(
        Singularity::mass_pivot(1, -0.5, 0.0, tol),
        Singularity::IndefiniteMassMatrix {
            speed: 1,
            value: -0.5
        }
    );
    for (pivot, diagonal) in [(2.375, f64::NAN), (f64::NAN, 1.0), (1.0, f64::INFINITY)] {
        assert_eq!(
            Singularity::mass_pivot(2, pivot, diagonal, tol),
            Singularity::NonFinite { speed: Some(2) }
        );
    }
    // From all the pivots and diagonal entries, with the scale Σ|M_kk|: the first pivot that
    // is zero beside it (not beside its own diagonal entry, which it equals here), and the
    // speed whose entries are not finite, though a NaN spoils the scale of every check.
    let pivots = Singularity::mass_pivots;
    assert_eq!(
        pivots(&[2.0, 3.7e-34], &[2.0, 3.7e-34], tol),
        singular_at(1, 3.7e-34)
    );
    assert_eq!(
        pivots(&[1e-14, 1.0], &[1e-14, 1.0], tol),
        singular_at(0, 1e-14)
    );
    assert_eq!(
        pivots(&[2.0, -0.5, 1.0], &[2.0, 0.5, 1.0], tol),
        Singularity::IndefiniteMassMatrix {
            speed: 1,
            value: -0.5
        }
    );
    assert_eq!(
        pivots(&[2.0, f64::NAN, f64::NAN], &[2.0, f64::NAN, 1.0], tol),
        Singularity::NonFinite { speed: Some(1) }
    );
    // Named, with the time and the state.
    let state = NamedValues::new(&["x", "v"], &[f64::NAN, 1.0]);
    let e = Singularity::NonFinite { speed: None }.at(0.25, state, &["x"], &["v"]);
    assert_eq!(
        e.to_string(),
        "the right-hand side produced a value that is not a finite number at t = 0.25 (in the \
         matrix A(q) of the constraints and quasi-velocities): the state is likely outside the \
         model's geometry (a square root of a negative number, a division by zero there), or a \
         parameter makes a division by zero; state: x = NaN, v = 1"
    );
}
