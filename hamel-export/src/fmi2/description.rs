//! `modelDescription.xml`, written from what the model's traits and the macro's tables know:
//! the variables of [`Table`] with their names, units, start values and doc comments, the
//! units, and `ModelStructure` with the dependencies of the generated code's graph.
//!
//! The GUID is a hash of the rest of the description: the library computes the same text
//! and refuses an instance whose GUID differs, so a library and a description of different
//! models (or of different versions of one) never meet; a rebuild of the same model on
//! another platform gives the same GUID.

use super::units;
use super::variables::{self, DEFAULT_STEP, INTEGRATORS, Role, Table};
use crate::model::Model;
use hamel_runtime::{HamelSystem, Parameters};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;

/// The stop time, communication step and tolerance an importer uses by default.
pub const DEFAULT_STOP_TIME: f64 = 10.0;
pub const DEFAULT_STEP_SIZE: f64 = 0.01;
/// The relative tolerance of Co-Simulation when the importer gives none; the absolute one is
/// a thousandth of the relative one ([`absolute_tolerance`]).
pub const DEFAULT_TOLERANCE: f64 = 1e-9;

/// The absolute tolerance that goes with a relative one: 1e-12 with the default 1e-9, as the
/// robot example's run.
pub fn absolute_tolerance(relative: f64) -> f64 {
    relative * 1e-3
}

/// The log categories: the name and what it holds. Warnings, discards and errors are
/// always reported; `logEvents` (initialization, steps refused, termination) only with
/// logging on.
pub const LOG_CATEGORIES: &[(&str, &str)] = &[
    (
        "logEvents",
        "initialization, the constraints solved, termination",
    ),
    ("logStatusWarning", "warnings"),
    (
        "logStatusDiscard",
        "steps and evaluations the model could not complete",
    ),
    ("logStatusError", "errors: calls refused and their reasons"),
];

/// The model description of `M` as the FMU `identifier` (its file and model name).
pub fn model_description<M: Model>(identifier: &str) -> String {
    let unsigned = document::<M>(identifier, "");
    document::<M>(identifier, &guid_of(&unsigned))
}

/// The GUID of `M` exported as `identifier`.
pub fn guid<M: Model>(identifier: &str) -> String {
    guid_of(&document::<M>(identifier, ""))
}

/// A GUID from a text: FNV-1a (128 bits) of its bytes, in the form
/// `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
fn guid_of(text: &str) -> String {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013b;
    let hash = text
        .bytes()
        .fold(OFFSET, |h, b| (h ^ u128::from(b)).wrapping_mul(PRIME));
    let hex = format!("{hash:032x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..]
    )
}

/// Text for an XML attribute value.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' | '\r' | '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A number as `xs:double` (shortest round trip).
fn number(value: f64) -> String {
    format!("{value:?}")
}

/// The text of the description with this GUID.
fn document<M: Model>(identifier: &str, guid: &str) -> String {
    let table = Table::of::<M>();
    let mut x = String::new();
    let w = &mut x;
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{id}" guid="{guid}" description="{description}" generationTool="hamel-export {version}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
        id = escape(identifier),
        description = escape(&format!(
            "{identifier}: a nonholonomic mechanical model by hamel (Hamel's equations, reduced \
             ODE of {nx} states)",
            nx = table.sizes.nx
        )),
        version = env!("CARGO_PKG_VERSION"),
    );
    let capabilities =
        r#"canNotUseMemoryManagementFunctions="true" providesDirectionalDerivative="true""#;
    let _ = writeln!(
        w,
        r#"  <ModelExchange modelIdentifier="{id}" completedIntegratorStepNotNeeded="true" {capabilities}/>"#,
        id = escape(identifier)
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{id}" canHandleVariableCommunicationStepSize="true" {capabilities}/>"#,
        id = escape(identifier)
    );
    unit_definitions::<M>(w, &table);
    let _ = writeln!(w, "  <TypeDefinitions>");
    let _ = writeln!(w, r#"    <SimpleType name="hamel.Integrator">"#);
    let _ = writeln!(w, "      <Enumeration>");
    for (value, (name, _, what)) in INTEGRATORS.iter().enumerate() {
        let _ = writeln!(
            w,
            r#"        <Item name="{name}" value="{}" description="{}"/>"#,
            value + 1,
            escape(what)
        );
    }
    let _ = writeln!(w, "      </Enumeration>");
    let _ = writeln!(w, "    </SimpleType>");
    let _ = writeln!(w, "  </TypeDefinitions>");
    let _ = writeln!(w, "  <LogCategories>");
    for (name, what) in LOG_CATEGORIES {
        let _ = writeln!(
            w,
            r#"    <Category name="{name}" description="{}"/>"#,
            escape(what)
        );
    }
    let _ = writeln!(w, "  </LogCategories>");
    let _ = writeln!(
        w,
        r#"  <DefaultExperiment startTime="0.0" stopTime="{}" tolerance="{}" stepSize="{}"/>"#,
        number(DEFAULT_STOP_TIME),
        number(DEFAULT_TOLERANCE),
        number(DEFAULT_STEP_SIZE)
    );
    let _ = writeln!(w, "  <ModelVariables>");
    for (vr, role) in table.roles.iter().enumerate() {
        variable::<M>(w, &table, vr, *role);
    }
    let _ = writeln!(w, "  </ModelVariables>");
    model_structure::<M>(w, &table);
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

/// The unit of a variable, as the model states it.
pub fn unit<M: Model>(role: Role) -> Option<String> {
    let unit = <M::System as HamelSystem>::unit;
    let state = <M::System as HamelSystem>::STATE;
    match role {
        Role::Time | Role::Step => unit("t").map(str::to_string),
        Role::State(i) => unit(state.get(i)?).map(str::to_string),
        Role::Derivative(i) => units::per_time(unit(state.get(i)?), unit("t")),
        Role::Input(i) => unit(<M::System as HamelSystem>::INPUTS.get(i)?).map(str::to_string),
        Role::Parameter(i) => {
            let name = <M::System as Parameters>::NAMES.get(i)?;
            <M::System as Parameters>::parameter_unit(name).map(str::to_string)
        }
        Role::Output(i) => unit(M::OUTPUTS.get(i)?).map(str::to_string),
        Role::Energy => unit("energy").map(str::to_string),
        Role::Constraint(_) | Role::Holonomic(_) | Role::Integrator => None,
    }
}

fn unit_definitions<M: Model>(w: &mut String, table: &Table) {
    let used: BTreeSet<String> = table.roles.iter().filter_map(|r| unit::<M>(*r)).collect();
    if used.is_empty() {
        return;
    }
    let _ = writeln!(w, "  <UnitDefinitions>");
    for name in used {
        match units::exponents(&name) {
            Some(exponents) => {
                let base: String = units::BASE
                    .iter()
                    .zip(exponents)
                    .filter(|(_, e)| *e != 0)
                    .map(|(b, e)| format!(r#" {b}="{e}""#))
                    .collect();
                let _ = writeln!(w, r#"    <Unit name="{}">"#, escape(&name));
                let _ = writeln!(w, "      <BaseUnit{base}/>");
                let _ = writeln!(w, "    </Unit>");
            }
            None => {
                let _ = writeln!(w, r#"    <Unit name="{}"/>"#, escape(&name));
            }
        }
    }
    let _ = writeln!(w, "  </UnitDefinitions>");
}

/// What a variable is, for its `description`.
fn description<M: Model>(role: Role) -> String {
    let n = <M::System as HamelSystem>::COORDINATES.len();
    let k = <M::System as HamelSystem>::K;
    match role {
        Role::Time => "the time".into(),
        Role::State(i) if variables::is_dependent::<M>(i) => {
            "generalized coordinate determined by the holonomic constraints: its start value \
             is a guess (it picks the branch), solved for at initialization"
                .into()
        }
        Role::State(i) if i < n => "generalized coordinate".into(),
        Role::State(_) => "free quasi-velocity (a speed of the reduced state)".into(),
        Role::Derivative(_) => "its time derivative: the generated right-hand side".into(),
        Role::Input(_) => "input (held constant over a communication step)".into(),
        Role::Parameter(i) => <M::System as Parameters>::DOCS
            .get(i)
            .map(|d| d.trim().to_string())
            .unwrap_or_default(),
        Role::Output(_) => "output of the model (`#[outputs]`)".into(),
        Role::Energy => "the energy E = q̇·∂L/∂q̇ − L".into(),
        Role::Constraint(i) => {
            let p = <M::System as HamelSystem>::CONSTRAINTS.len();
            if i + k >= p && k > 0 {
                "residual of the time derivative of a holonomic constraint (velocity level)".into()
            } else {
                "residual of the constraint row A_c(q) q̇ + a_c (zero along every admissible \
                 motion)"
                    .into()
            }
        }
        Role::Holonomic(_) => {
            "residual of the holonomic constraint f(t, q) (position level)".into()
        }
        Role::Step => "the step of the fixed-step integrators of Co-Simulation".into(),
        Role::Integrator => "the integrator of Co-Simulation".into(),
    }
}

fn variable<M: Model>(w: &mut String, table: &Table, vr: usize, role: Role) {
    let name = escape(&variables::name::<M>(role));
    let description = escape(&description::<M>(role));
    let unit = unit::<M>(role)
        .map(|u| format!(r#" unit="{}""#, escape(&u)))
        .unwrap_or_default();
    let defaults = M::System::default();
    let (attributes, element) = match role {
        Role::Time => (
            r#"causality="independent" variability="continuous""#.to_string(),
            format!("<Real{unit}/>"),
        ),
        Role::State(i) => {
            let initial = if variables::is_dependent::<M>(i) {
                "approx"
            } else {
                "exact"
            };
            (
                format!(r#"causality="local" variability="continuous" initial="{initial}""#),
                format!(r#"<Real start="0.0"{unit}/>"#),
            )
        }
        Role::Derivative(i) => (
            r#"causality="local" variability="continuous" initial="calculated""#.to_string(),
            format!(
                r#"<Real derivative="{}"{unit}/>"#,
                table.index(Role::State(i))
            ),
        ),
        Role::Input(_) => (
            r#"causality="input" variability="continuous""#.to_string(),
            format!(r#"<Real start="0.0"{unit}/>"#),
        ),
        Role::Parameter(i) => {
            let value = <M::System as Parameters>::NAMES
                .get(i)
                .and_then(|n| defaults.get(n))
                .unwrap_or(f64::NAN);
            (
                r#"causality="parameter" variability="tunable" initial="exact""#.to_string(),
                format!(r#"<Real start="{}"{unit}/>"#, number(value)),
            )
        }
        Role::Output(_) | Role::Energy | Role::Constraint(_) | Role::Holonomic(_) => (
            r#"causality="output" variability="continuous" initial="calculated""#.to_string(),
            format!("<Real{unit}/>"),
        ),
        Role::Step => (
            r#"causality="parameter" variability="fixed" initial="exact""#.to_string(),
            format!(r#"<Real start="{}"{unit}/>"#, number(DEFAULT_STEP)),
        ),
        Role::Integrator => (
            r#"causality="parameter" variability="fixed" initial="exact""#.to_string(),
            r#"<Enumeration declaredType="hamel.Integrator" start="1"/>"#.to_string(),
        ),
    };
    let _ = writeln!(
        w,
        r#"    <ScalarVariable name="{name}" valueReference="{vr}" description="{description}" {attributes}>"#
    );
    let _ = writeln!(w, "      {element}");
    let _ = writeln!(w, "    </ScalarVariable>");
}

/// What each unknown depends on, as variable indices: `continuous` for the Outputs and
/// Derivatives (the knowns are the states, the inputs and the time), `initial` for the
/// InitialUnknowns (the knowns are the start values, the inputs, the parameters and the
/// time).
pub struct Dependencies {
    pub continuous: BTreeMap<usize, BTreeSet<usize>>,
    pub initial: BTreeMap<usize, BTreeSet<usize>>,
}

/// The dependencies the generated code's graph gives: each component of ẋ and y on the
/// components of x, u and p it reads; the energy on the whole state; the constraint rows on
/// nothing (the reduced state satisfies them identically); the holonomic constraints on the
/// coordinates. A time-dependent model's unknowns depend on the time as well.
pub fn dependencies<M: Model>(table: &Table) -> Dependencies {
    let s = table.sizes;
    let n = <M::System as HamelSystem>::COORDINATES.len();
    let params = <M::System as Parameters>::NAMES;
    let time = M::TIME_DEPENDENT.then(|| table.index(Role::Time));
    let state = |i: usize| table.index(Role::State(i));
    let parameter_indices = |names: &[&str]| -> BTreeSet<usize> {
        names
            .iter()
            .filter_map(|name| params.iter().position(|p| p == name))
            .map(|i| table.index(Role::Parameter(i)))
            .collect()
    };
    let all_parameters: BTreeSet<usize> =
        (0..s.np).map(|i| table.index(Role::Parameter(i))).collect();
    // Per unknown: the knowns of continuous time, and the parameters it reads.
    let mut direct: Vec<(usize, BTreeSet<usize>, BTreeSet<usize>)> = Vec::new();
    for i in 0..s.nx {
        let columns = M::RHS_COLUMNS.get(i).copied().unwrap_or(&[]);
        let knowns = columns
            .iter()
            .map(|&c| {
                if c < s.nx {
                    state(c)
                } else {
                    table.index(Role::Input(c - s.nx))
                }
            })
            .chain(time)
            .collect();
        let read = parameter_indices(M::RHS_PARAMETERS.get(i).copied().unwrap_or(&[]));
        direct.push((table.index(Role::Derivative(i)), knowns, read));
    }
    for i in 0..s.ny {
        let columns = M::OUTPUT_COLUMNS.get(i).copied().unwrap_or(&[]);
        let knowns = columns.iter().map(|&c| state(c)).chain(time).collect();
        let read = parameter_indices(M::OUTPUT_PARAMETERS.get(i).copied().unwrap_or(&[]));
        direct.push((table.index(Role::Output(i)), knowns, read));
    }
    let whole_state: BTreeSet<usize> = (0..s.nx).map(state).chain(time).collect();
    direct.push((
        table.index(Role::Energy),
        whole_state,
        all_parameters.clone(),
    ));
    for i in 0..table.p {
        direct.push((
            table.index(Role::Constraint(i)),
            BTreeSet::new(),
            BTreeSet::new(),
        ));
    }
    let coordinates: BTreeSet<usize> = (0..n).map(state).chain(time).collect();
    for i in 0..table.k {
        direct.push((
            table.index(Role::Holonomic(i)),
            coordinates.clone(),
            all_parameters.clone(),
        ));
    }
    // At initialization the dependent coordinates are unknowns, solved from the others, the
    // parameters and the time; what reads one reads those instead.
    let dependent: BTreeSet<usize> = <M::System as HamelSystem>::DEPENDENT
        .iter()
        .map(|&i| state(i))
        .collect();
    let solved_from: BTreeSet<usize> = (0..n)
        .map(state)
        .filter(|i| !dependent.contains(i))
        .chain(all_parameters.iter().copied())
        .chain(time)
        .collect();
    let substitute = |knowns: &BTreeSet<usize>| -> BTreeSet<usize> {
        let mut out = BTreeSet::new();
        for k in knowns {
            if dependent.contains(k) {
                out.extend(solved_from.iter().copied());
            } else {
                out.insert(*k);
            }
        }
        out
    };
    let mut continuous = BTreeMap::new();
    let mut initial = BTreeMap::new();
    for (unknown, knowns, read) in direct {
        let mut at_start = substitute(&knowns);
        at_start.extend(read);
        initial.insert(unknown, at_start);
        continuous.insert(unknown, knowns);
    }
    for d in &dependent {
        initial.insert(*d, solved_from.clone());
    }
    Dependencies {
        continuous,
        initial,
    }
}

fn unknown(w: &mut String, index: usize, dependencies: &BTreeSet<usize>) {
    let list: Vec<String> = dependencies.iter().map(|d| d.to_string()).collect();
    let _ = writeln!(
        w,
        r#"      <Unknown index="{index}" dependencies="{}"/>"#,
        list.join(" ")
    );
}

fn model_structure<M: Model>(w: &mut String, table: &Table) {
    let deps = dependencies::<M>(table);
    let _ = writeln!(w, "  <ModelStructure>");
    let _ = writeln!(w, "    <Outputs>");
    for role in &table.roles {
        if matches!(
            role,
            Role::Output(_) | Role::Energy | Role::Constraint(_) | Role::Holonomic(_)
        ) {
            let index = table.index(*role);
            unknown(w, index, &deps.continuous[&index]);
        }
    }
    let _ = writeln!(w, "    </Outputs>");
    let _ = writeln!(w, "    <Derivatives>");
    for i in 0..table.sizes.nx {
        let index = table.index(Role::Derivative(i));
        unknown(w, index, &deps.continuous[&index]);
    }
    let _ = writeln!(w, "    </Derivatives>");
    let _ = writeln!(w, "    <InitialUnknowns>");
    for (index, knowns) in &deps.initial {
        unknown(w, *index, knowns);
    }
    let _ = writeln!(w, "    </InitialUnknowns>");
    let _ = writeln!(w, "  </ModelStructure>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guids_are_stable_and_differ_with_the_text() {
        let a = guid_of("model a");
        assert_eq!(a, guid_of("model a"));
        assert_ne!(a, guid_of("model b"));
        assert_eq!(a.len(), 38);
        assert!(a.starts_with('{') && a.ends_with('}'));
    }

    #[test]
    fn attribute_text_is_escaped() {
        assert_eq!(escape(r#"a < b & "c""#), "a &lt; b &amp; &quot;c&quot;");
    }
}
