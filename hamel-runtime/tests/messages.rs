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
        text.starts_with("step size underflow at t = 2.669: the step shrank to 1e-300; state: huge = 1e300, tiny = 1e-300"),
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
