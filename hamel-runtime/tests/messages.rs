//! How errors and named values read: `Debug` of an [`Error`] is its message (what
//! `fn main() -> Result<(), Error>` prints), and numbers in messages have bounded digits.

use hamel_runtime::{AssemblyFailure, Error, NamedValues, Num};

/// A state as the numbers an integration produces: long decimal expansions, extremes and
/// values that are not finite.
fn awkward_state() -> NamedValues {
    NamedValues::new(
        &["huge", "tiny", "nan", "inf", "neg", "sum", "t_like", "zero", "whole"],
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
    assert!(e.to_string().contains("derivative NaN with respect to `x`"), "{e}");
    assert_eq!(Num(f64::NAN).to_string(), "NaN");
    assert_eq!(Num(0.1 + 0.2).to_string(), "0.3");
}
