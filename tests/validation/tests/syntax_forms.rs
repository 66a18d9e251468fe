//! Every syntax form of the engine's subset (`hamel::docs::subset`), each in a small
//! `#[hamel_system]` model that builds and runs.
//!
//! Each model below describes the same mechanical system as a catalogue model — almost always
//! the knife edge on an inclined plane, `hamel::models::KnifeEdge`:
//!
//!   L = ½ m (ẋ² + ẏ²) + ½ J φ̇² + m g sin(incline) x,   ẋ sin φ − ẏ cos φ = 0,
//!   speeds v = ẋ cos φ + ẏ sin φ, ω = φ̇
//!
//! (`ChaplyginSleigh` where a form fits it better) — but its role functions are written with
//! the form under test: exact rewrites of the same energy, constraint and speeds. That it
//! compiles is the first proof; `common/same_system.rs` then compares the generated right-hand
//! side, energy, velocities and mass matrix with the reference's at seeded random states
//! (1e-12 norm-wise relative) and a 2 s simulation sample by sample (1e-9).
//!
//! Run with `--nocapture` to see the measured discrepancies of every model.

use crate::common::same_system::{ThreeByOne, check_same_system, random_state, relative};
use crate::common::xorshift::XorShift;
use hamel::models::{ChaplyginSleigh, KnifeEdge};
use hamel::{HamelSystem, hamel_system};
use std::f64::consts;

// ---------------------------------------------------------------------------------------------
// The references
// ---------------------------------------------------------------------------------------------

/// The knife edge's parameters (not the catalogue's defaults, so that no factor is 1).
const MASS: f64 = 1.7;
const INERTIA: f64 = 0.23;
const GRAVITY: f64 = 9.81;
const INCLINE: f64 = 0.3;

fn knife_edge() -> KnifeEdge {
    KnifeEdge {
        m: MASS,
        j: INERTIA,
        g: GRAVITY,
        incline: INCLINE,
    }
}

/// Start of the compared knife-edge runs: φ̇ = 3 and v ≥ 1.2 throughout (v oscillates by
/// g sin(incline)/φ̇ ≈ 0.97 about its mean).
const KNIFE_Q0: [f64; 3] = [0.1, -0.2, 0.3];
const KNIFE_SPEEDS0: [f64; 2] = [2.5, 3.0];

/// A knife-edge variant without inputs against `KnifeEdge`.
fn check_knife<S: ThreeByOne<Inputs = [f64; 0]>>(name: &str, model: &S) {
    check_same_system(name, model, [], &knife_edge(), KNIFE_Q0, KNIFE_SPEEDS0);
}

/// The parameters of most variants: the reference's, under the same names.
macro_rules! knife_parameters {
    ($name:ident) => {
        #[hamel_system]
        struct $name {
            m: f64,
            j: f64,
            g: f64,
            incline: f64,
        }

        impl $name {
            fn new() -> Self {
                $name {
                    m: MASS,
                    j: INERTIA,
                    g: GRAVITY,
                    incline: INCLINE,
                }
            }
        }
    };
}

// ---------------------------------------------------------------------------------------------
// f64 literals (decimal, exponent, suffixed, a method called on a literal)
// ---------------------------------------------------------------------------------------------

/// No parameters at all: m = 1.7, J = 0.23, g = 9.81 and the incline 0.3 are literals.
#[hamel_system]
struct KnifeLiterals;

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeLiterals {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * 1.7 * (qd[0] * qd[0] + qd[1] * qd[1])
            + 23e-2 * qd[2] * qd[2] / 2f64
            + 1.7_f64 * 9.81 * 0.3f64.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - 1.0 * qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), 1e0 * qd[2]]
    }
}

#[test]
fn f64_literals() {
    check_knife("f64 literals", &KnifeLiterals);
}

// ---------------------------------------------------------------------------------------------
// `const` items in a body (one defined through another)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeBodyConsts);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeBodyConsts {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        const HALF: f64 = 0.5;
        const TWICE_HALF: f64 = 2.0 * HALF;
        HALF * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + HALF * self.j * qd[2] * qd[2]
            + TWICE_HALF * self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        const SIGN: f64 = -1.0;
        [qd[0] * q[2].sin() + SIGN * qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn const_items_in_a_body() {
    check_knife("const in body", &KnifeBodyConsts::new());
}

// ---------------------------------------------------------------------------------------------
// Associated consts `Self::NAME` (one defined through another)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeAssociatedConsts);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeAssociatedConsts {
    const HALF: f64 = 0.5;
    const ONE: f64 = 2.0 * Self::HALF;

    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        Self::HALF * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + Self::HALF * self.j * qd[2] * qd[2]
            + Self::ONE * self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - Self::ONE * qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), Self::ONE * qd[2]]
    }
}

#[test]
fn associated_consts() {
    check_knife("associated consts", &KnifeAssociatedConsts::new());
}

// ---------------------------------------------------------------------------------------------
// A module-level constant read by its bare name (`GRAVITY`, defined at the top of this file)
// ---------------------------------------------------------------------------------------------

#[hamel_system]
struct KnifeModuleConst {
    m: f64,
    j: f64,
    incline: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeModuleConst {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * GRAVITY * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn module_level_constant() {
    let model = KnifeModuleConst {
        m: MASS,
        j: INERTIA,
        incline: INCLINE,
    };
    check_knife("module-level const", &model);
}

// ---------------------------------------------------------------------------------------------
// `std::f64::consts::*` (full path, through `core`, through an imported `consts`)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeStdConsts);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeStdConsts {
    /// ½ = ln √e; sin(incline) = sin(incline + 2π).
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let half = std::f64::consts::E.sqrt().ln();
        half * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + half * self.j * qd[2] * qd[2]
            + self.m * self.g * (self.incline + consts::TAU).sin() * q[0]
    }

    /// sin φ = −sin(φ + π), cos φ = sin(φ + π/2).
    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [
            -qd[0] * (q[2] + core::f64::consts::PI).sin()
                - qd[1] * (q[2] + consts::FRAC_PI_2).sin(),
        ]
    }

    /// ω = φ̇ · √2 · (1/√2).
    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [
            qd[0] * q[2].cos() + qd[1] * q[2].sin(),
            qd[2] * consts::SQRT_2 * consts::FRAC_1_SQRT_2,
        ]
    }
}

#[test]
fn std_f64_consts() {
    check_knife("std::f64::consts", &KnifeStdConsts::new());
}

// ---------------------------------------------------------------------------------------------
// Parameters `self.field` (other names, another order, a derived local)
// ---------------------------------------------------------------------------------------------

#[hamel_system]
struct KnifeParameterFields {
    incline: f64,
    gravity: f64,
    inertia: f64,
    mass: f64,
}

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeParameterFields {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let weight = self.mass * self.gravity;
        0.5 * self.mass * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.inertia * qd[2] * qd[2]
            + weight * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn parameter_fields() {
    let model = KnifeParameterFields {
        incline: INCLINE,
        gravity: GRAVITY,
        inertia: INERTIA,
        mass: MASS,
    };
    check_knife("self.field", &model);
}

// ---------------------------------------------------------------------------------------------
// Arguments by value, `[f64; N]`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeByValue);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeByValue {
    #[lagrangian]
    fn lagrangian(&self, q: [f64; 3], qd: [f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: [f64; 3], qd: [f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: [f64; 3], qd: [f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn arguments_by_value() {
    check_knife("args by value", &KnifeByValue::new());
}

// ---------------------------------------------------------------------------------------------
// Arguments named as the user likes (only a role's own names, `q`, `qd`, are held to their
// places)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeOwnNames);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeOwnNames {
    #[lagrangian]
    fn lagrangian(&self, config: &[f64; 3], vel: &[f64; 3]) -> f64 {
        0.5 * self.m * (vel[0] * vel[0] + vel[1] * vel[1])
            + 0.5 * self.j * vel[2] * vel[2]
            + self.m * self.g * self.incline.sin() * config[0]
    }

    #[constraints]
    fn blade(&self, __q: &[f64; 3], rate: &[f64; 3]) -> [f64; 1] {
        [rate[0] * __q[2].sin() - rate[1] * __q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, pose: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * pose[2].cos() + qd[1] * pose[2].sin(), qd[2]]
    }
}

#[test]
fn arguments_with_names_of_ones_own() {
    check_knife("own argument names", &KnifeOwnNames::new());
}

// ---------------------------------------------------------------------------------------------
// Role attributes by the path of their macros in `hamel`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeRolePaths);

#[hamel::hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeRolePaths {
    #[hamel::lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[::hamel::constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn role_attributes_by_path() {
    check_knife("role attributes by path", &KnifeRolePaths::new());
}

// ---------------------------------------------------------------------------------------------
// Arguments by reference, `&[f64; N]`, destructured: `let [x, y, phi] = *q;`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeArrayPattern);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeArrayPattern {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let [x, _, _] = *q;
        let [xd, yd, phid] = *qd;
        0.5 * self.m * (xd * xd + yd * yd)
            + 0.5 * self.j * phid * phid
            + self.m * self.g * self.incline.sin() * x
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let [_x, _y, phi] = *q;
        let [xd, yd, _] = *qd;
        [xd * phi.sin() - yd * phi.cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let [_, _, phi] = *q;
        let [xd, yd, phid] = *qd;
        [xd * phi.cos() + yd * phi.sin(), phid]
    }
}

#[test]
fn arguments_by_reference_with_array_pattern() {
    check_knife("&[f64; N] + array pattern", &KnifeArrayPattern::new());
}

// ---------------------------------------------------------------------------------------------
// `+ - * /`, unary `-`, parentheses
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeOperators);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeOperators {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        (self.m / 2.0) * (qd[0] * qd[0] + qd[1] * qd[1])
            - -(self.j * (qd[2] * qd[2]) / 2.0)
            - (-self.m) * (self.g * self.incline.sin()) * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-(qd[1] * q[2].cos() - qd[0] * q[2].sin())]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [
            qd[0] * q[2].cos() - -(qd[1] * q[2].sin()),
            -(-qd[2] / 2.0) * 2.0,
        ]
    }
}

#[test]
fn arithmetic_operators() {
    check_knife("operators", &KnifeOperators::new());
}

// ---------------------------------------------------------------------------------------------
// `let` and `let mut` (also typed) with `=`, `+=`, `-=`, `*=`, `/=`, on scalars and on array
// elements
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeAssignments);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeAssignments {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        // Twice the kinetic energy, term by term in an array.
        let mut twice = [0.0; 3];
        twice[0] = self.m * qd[0];
        twice[0] *= qd[0];
        twice[1] += self.m * qd[1] * qd[1];
        twice[2] -= self.j * qd[2] * qd[2];
        twice[2] /= -1.0;
        // The Lagrangian, on a scalar.
        let mut l: f64 = twice[0] + twice[1];
        l += twice[2];
        l /= 2.0;
        let height = self.incline.sin() * q[0];
        let mut weight = self.m;
        weight *= self.g;
        l -= -weight * height;
        l
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let mut across = qd[0] * q[2].sin();
        across -= qd[1] * q[2].cos();
        [across]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let mut w = [qd[0] * q[2].cos(), qd[2]];
        w[0] += qd[1] * q[2].sin();
        w
    }
}

#[test]
fn let_and_compound_assignments() {
    check_knife("let mut, op-assign", &KnifeAssignments::new());
}

// ---------------------------------------------------------------------------------------------
// `[0.0; N]` filled element by element as results (array literals are results everywhere)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeZeroArrayResults);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeZeroArrayResults {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let mut rows = [0.0; 1];
        rows[0] = qd[0] * q[2].sin() - qd[1] * q[2].cos();
        rows
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let mut w = [0.0; 2];
        w[1] = qd[2];
        w[0] = qd[0] * q[2].cos() + qd[1] * q[2].sin();
        w
    }
}

#[test]
fn zero_array_results() {
    check_knife("[0.0; N] results", &KnifeZeroArrayResults::new());
}

// ---------------------------------------------------------------------------------------------
// Tuple patterns, tuple fields and `sin_cos()`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeTuples);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeTuples {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let (xd, yd, phid) = (qd[0], qd[1], qd[2]);
        let (slope, _) = self.incline.sin_cos();
        0.5 * self.m * (xd * xd + yd * yd)
            + 0.5 * self.j * phid * phid
            + self.m * self.g * slope * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let (s, c) = q[2].sin_cos();
        [qd[0] * s - qd[1] * c]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let along = (qd[0] * q[2].sin_cos().1, qd[1] * q[2].sin_cos().0);
        [along.0 + along.1, qd[2]]
    }
}

#[test]
fn tuples_and_sin_cos() {
    check_knife("tuples, sin_cos", &KnifeTuples::new());
}

// ---------------------------------------------------------------------------------------------
// Block expressions (nested, with shadowing inside)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeBlocks);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeBlocks {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let kinetic = {
            let v2 = qd[0] * qd[0] + qd[1] * qd[1];
            let spin = {
                let v2 = qd[2] * qd[2]; // shadows the outer v2 in this block only
                self.j * v2
            };
            0.5 * (self.m * v2 + spin)
        };
        let potential = {
            let slope = self.g * self.incline.sin();
            -self.m * slope * q[0]
        };
        kinetic - potential
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [{
            let (s, c) = q[2].sin_cos();
            qd[0] * s - qd[1] * c
        }]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let v = { qd[0] * q[2].cos() + qd[1] * q[2].sin() };
        [v, { qd[2] }]
    }
}

#[test]
fn block_expressions() {
    check_knife("blocks", &KnifeBlocks::new());
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: sin cos tan asin acos atan atan2
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeTrigonometry);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeTrigonometry {
    /// sin(incline) = tan(incline) · cos(incline).
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let slope = self.incline.tan() * self.incline.cos();
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * slope * q[0]
    }

    /// z = 2 sin(asin(z/2)) = 2 cos(acos(z/2)) for |z| ≤ 1 (well away from asin's and acos's
    /// branch points).
    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let s = 2.0 * (0.5 * q[2].sin()).asin().sin();
        let c = 2.0 * (0.5 * q[2].cos()).acos().cos();
        [qd[0] * s - qd[1] * c]
    }

    /// φ reduced to (−π, π] by atan2 has the same sine and cosine; tan(atan(z)) = z.
    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let phi = q[2].sin().atan2(q[2].cos());
        let s = phi.sin().atan().tan();
        [qd[0] * phi.cos() + qd[1] * s, qd[2]]
    }
}

#[test]
fn trigonometric_functions() {
    check_knife(
        "sin cos tan asin acos atan atan2",
        &KnifeTrigonometry::new(),
    );
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: sinh cosh tanh
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeHyperbolic);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeHyperbolic {
    /// 1 = cosh²u − sinh u · (tanh u · cosh u) for any u; here u = sin φ, a configuration
    /// dependence that cancels exactly.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let u = q[2].sin();
        let one = u.cosh() * u.cosh() - u.sinh() * (u.tanh() * u.cosh());
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) * one
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn hyperbolic_functions() {
    check_knife("sinh cosh tanh", &KnifeHyperbolic::new());
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: exp ln log10
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeExpLog);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeExpLog {
    /// m = exp(ln m), J = exp(log10(J) · ln 10), v² = exp(ln v²) (v² > 0 off rest).
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let m = self.m.ln().exp();
        let j = (self.j.log10() * consts::LN_10).exp();
        let v2 = (qd[0] * qd[0] + qd[1] * qd[1]).ln().exp();
        0.5 * m * v2 + 0.5 * j * qd[2] * qd[2] + m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn exp_and_logarithms() {
    check_knife("exp ln log10", &KnifeExpLog::new());
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: sqrt cbrt hypot
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeRoots);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeRoots {
    /// The path speed |v| = hypot(ẋ, ẏ), the turning rate |φ̇| = √(φ̇²), J = (∛J)³.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let speed = qd[0].hypot(qd[1]);
        let turning = (qd[2] * qd[2]).sqrt();
        let root = self.j.cbrt();
        0.5 * self.m * speed * speed
            + 0.5 * (root * root * root) * turning * turning
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn roots_and_hypot() {
    check_knife("sqrt cbrt hypot", &KnifeRoots::new());
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: powi powf recip mul_add
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifePowers);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifePowers {
    /// ½ = 2⁻¹, squares as powi(2) and powf(2.0) (of negative numbers too), J = (J⁻¹)⁻¹,
    /// m v² + J φ̇² as one mul_add.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let half = (2.0f64).recip();
        let v2 = qd[0].powi(2) + qd[1].powf(2.0);
        let j = self.j.powi(-1).recip();
        half * self.m.mul_add(v2, j * qd[2].powi(2))
            + self.m * self.g * self.incline.sin() * q[0].powf(1.0)
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn powers_recip_mul_add() {
    check_knife("powi powf recip mul_add", &KnifePowers::new());
}

// ---------------------------------------------------------------------------------------------
// Elementary functions: abs signum min max
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeAbsSignMinMax);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeAbsSignMinMax {
    /// ẋ = sgn(ẋ)·|ẋ|, a + b = max(a, b) + min(a, b), φ̇² = |φ̇|², J = |J|.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let xd = qd[0].signum() * qd[0].abs();
        let (a, b) = (self.m * xd * xd, self.m * qd[1] * qd[1]);
        0.5 * (a.max(b) + a.min(b))
            + 0.5 * self.j.abs() * qd[2].abs() * qd[2].abs()
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn abs_signum_min_max() {
    check_knife("abs signum min max", &KnifeAbsSignMinMax::new());
}

// ---------------------------------------------------------------------------------------------
// Elementary functions in path form, `f64::sin(x)` (the models above use the method form)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifePathCalls);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifePathCalls {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let speed = f64::hypot(qd[0], qd[1]);
        let turning = f64::sqrt(f64::powf(f64::abs(qd[2]), 2.0));
        let m = f64::exp(f64::ln(self.m));
        let slope = f64::tan(self.incline) * f64::cos(self.incline);
        f64::recip(2.0) * f64::mul_add(m, f64::powi(speed, 2), self.j * turning * turning)
            + f64::max(m, 0.0) * f64::min(self.g, f64::INFINITY) * slope * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let (s, c) = f64::sin_cos(q[2]);
        [qd[0] * s - qd[1] * c]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let phi = f64::atan2(f64::sin(q[2]), f64::cos(q[2]));
        [qd[0] * f64::cos(phi) + qd[1] * f64::sin(phi), qd[2]]
    }
}

#[test]
fn path_form_calls() {
    check_knife("f64::f(x) path calls", &KnifePathCalls::new());
}

// ---------------------------------------------------------------------------------------------
// `for i in 0..N`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeRangeLoop);

// The subset indexes arrays by loop counters, which is what `needless_range_loop` dislikes.
#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
#[allow(clippy::needless_range_loop)]
impl KnifeRangeLoop {
    /// T = Σᵢ ½ Mᵢ q̇ᵢ² with M = diag(m, m, J).
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let inertia = [self.m, self.m, self.j];
        let mut l = self.m * self.g * self.incline.sin() * q[0];
        for i in 0..3 {
            l += 0.5 * inertia[i] * qd[i] * qd[i];
        }
        l
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let direction = [q[2].sin(), -q[2].cos()];
        let mut across = 0.0;
        for i in 0..2 {
            across += direction[i] * qd[i];
        }
        [across]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn for_range_loop() {
    check_knife("for i in 0..N", &KnifeRangeLoop::new());
}

// ---------------------------------------------------------------------------------------------
// `for i in 0..=N` (with `i as f64` and an `if` on the counter, decided at compile time)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeInclusiveLoop);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeInclusiveLoop {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let mut twice_t = 0.0;
        let mut x = 0.0;
        for i in 0..=2 {
            let inertia = if i < 2 { self.m } else { self.j };
            twice_t += inertia * qd[i] * qd[i];
            x += (1.0 - i as f64).max(0.0) * q[i]; // picks q[0]
        }
        0.5 * twice_t + self.m * self.g * self.incline.sin() * x
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let (s, c) = q[2].sin_cos();
        let direction = [c, s];
        let mut v = 0.0;
        for i in 0..=1 {
            v += direction[i] * qd[i];
        }
        [v, qd[2]]
    }
}

#[test]
fn for_inclusive_range_loop() {
    check_knife("for i in 0..=N", &KnifeInclusiveLoop::new());
}

// ---------------------------------------------------------------------------------------------
// `for i in (0..N).rev()`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeReversedLoop);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
#[allow(clippy::needless_range_loop)]
impl KnifeReversedLoop {
    /// L built from the last velocity to the first, then the potential.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let inertia = [self.m, self.m, self.j];
        let mut twice_t = 0.0;
        for i in (0..3).rev() {
            twice_t += inertia[i] * qd[i] * qd[i];
        }
        0.5 * twice_t + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    /// w[1] first, then w[0] from it: a reversed loop over the rows.
    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let mut w = [0.0; 2];
        for k in (0..2).rev() {
            w[k] = if k > 0 {
                qd[2]
            } else {
                qd[0] * q[2].cos() + qd[1] * q[2].sin()
            };
        }
        w
    }
}

#[test]
fn for_reversed_range_loop() {
    check_knife("for i in (0..N).rev()", &KnifeReversedLoop::new());
}

// ---------------------------------------------------------------------------------------------
// `for x in arr`, over the elements of an array
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeElementLoop);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeElementLoop {
    /// 2T = Σ pᵢ² with p = (√m ẋ, √m ẏ, √J φ̇).
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let scaled = [
            self.m.sqrt() * qd[0],
            self.m.sqrt() * qd[1],
            self.j.sqrt() * qd[2],
        ];
        let mut twice_t = 0.0;
        for p in scaled {
            twice_t += p * p;
        }
        0.5 * twice_t + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn for_element_loop() {
    check_knife("for x in arr", &KnifeElementLoop::new());
}

// ---------------------------------------------------------------------------------------------
// Calls `self.helper(..)` (helpers reading parameters, one calling another)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeSelfHelpers);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeSelfHelpers {
    fn kinetic(&self, qd: &[f64; 3]) -> f64 {
        0.5 * self.m * self.planar_speed_squared(qd) + 0.5 * self.j * qd[2] * qd[2]
    }

    fn planar_speed_squared(&self, qd: &[f64; 3]) -> f64 {
        qd[0] * qd[0] + qd[1] * qd[1]
    }

    fn height_drop(&self, x: f64) -> f64 {
        self.incline.sin() * x
    }

    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        self.kinetic(qd) + self.m * self.g * self.height_drop(q[0])
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [self.across(q[2], qd)]
    }

    fn across(&self, phi: f64, qd: &[f64; 3]) -> f64 {
        qd[0] * phi.sin() - qd[1] * phi.cos()
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn self_helper_calls() {
    check_knife("self.helper(..)", &KnifeSelfHelpers::new());
}

// ---------------------------------------------------------------------------------------------
// Calls `Self::helper(..)` (associated functions, one returning an array)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeAssociatedHelpers);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeAssociatedHelpers {
    fn square(z: f64) -> f64 {
        z * z
    }

    /// The planar velocity in the blade's frame: [along, across].
    fn blade_frame(phi: f64, xd: f64, yd: f64) -> [f64; 2] {
        let (s, c) = phi.sin_cos();
        [xd * c + yd * s, xd * s - yd * c]
    }

    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (Self::square(qd[0]) + Self::square(qd[1]))
            + 0.5 * self.j * Self::square(qd[2])
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        let frame = Self::blade_frame(q[2], qd[0], qd[1]);
        [frame[1]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [Self::blade_frame(q[2], qd[0], qd[1])[0], qd[2]]
    }
}

#[test]
fn associated_helper_calls() {
    check_knife("Self::helper(..)", &KnifeAssociatedHelpers::new());
}

// ---------------------------------------------------------------------------------------------
// A helper taking a `usize` (a coordinate number), called with literals and a loop counter
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeIndexHelper);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeIndexHelper {
    /// The inertia of coordinate i: m for x and y, J for φ.
    fn inertia(&self, i: usize) -> f64 {
        if i == 2 { self.j } else { self.m }
    }

    fn kinetic_term(&self, qd: &[f64; 3], i: usize) -> f64 {
        0.5 * self.inertia(i) * qd[i] * qd[i]
    }

    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let mut t = self.kinetic_term(qd, 2);
        for i in 0..2 {
            t += self.kinetic_term(qd, i);
        }
        t + self.inertia(0) * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn helper_taking_usize() {
    check_knife("helper(.., i: usize)", &KnifeIndexHelper::new());
}

// ---------------------------------------------------------------------------------------------
// `if`/`else` as a value (`else if` chains, `<`, `<=`, `>`, `>=`)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeBranchValues);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeBranchValues {
    /// |ẋ| and |ẏ| by branches on their signs (squared, so the sign does not matter), and the
    /// potential from either side of the origin (the same expression on both).
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let ax = if qd[0] < 0.0 { -qd[0] } else { qd[0] };
        let ay = if qd[1] >= 0.0 {
            qd[1]
        } else if qd[1] > -1.0 {
            -qd[1]
        } else {
            0.0 - qd[1]
        };
        let potential = if q[0] <= 0.0 {
            -self.m * self.g * self.incline.sin() * q[0]
        } else {
            -(self.m * self.g * self.incline.sin()) * q[0]
        };
        0.5 * self.m * (ax * ax + ay * ay) + 0.5 * self.j * qd[2] * qd[2] - potential
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn if_else_values() {
    check_knife("if/else values", &KnifeBranchValues::new());
}

// ---------------------------------------------------------------------------------------------
// `if`/`else` as statements updating `let mut` locals, conditions with `&&`, `||`, `!`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeBranchStatements);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeBranchStatements {
    /// |ẋ|, |ẏ| and |φ̇| built by statements (squared, so the sign does not matter); the
    /// second conditions never change which branch is taken on the motion, only the form.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let [xd, yd, phid] = *qd;
        let mut ax = 0.0;
        if xd < 0.0 && q[2] < 100.0 {
            ax -= xd;
        } else {
            ax += xd;
        }
        let mut ay = 0.0;
        if yd > 1.0 || yd > 100.0 {
            ay = yd;
        } else if yd >= 0.0 {
            ay += 2.0 * yd;
            ay /= 2.0;
        } else {
            ay -= yd;
        }
        let mut spin = phid;
        if !(phid >= 0.0 || q[0] > 1e6) {
            spin *= -1.0;
        }
        0.5 * self.m * (ax * ax + ay * ay)
            + 0.5 * self.j * spin * spin
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn if_else_statements() {
    check_knife("if/else statements, && || !", &KnifeBranchStatements::new());
}

// ---------------------------------------------------------------------------------------------
// A domain guard: `if s > 0.0 { s.sqrt() } else { 0.0 }` on a quantity positive on the motion
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeDomainGuard);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeDomainGuard {
    /// T = ½ m |v|² + ½ J φ̇² with the path speed |v| = √(ẋ² + ẏ²), guarded at rest.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let v2 = qd[0] * qd[0] + qd[1] * qd[1];
        let speed = if v2 > 0.0 { v2.sqrt() } else { 0.0 };
        0.5 * self.m * speed * speed
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn domain_guard() {
    check_knife("guarded sqrt", &KnifeDomainGuard::new());
}

// ---------------------------------------------------------------------------------------------
// The generated index constants: `q[Self::PHI]`, `w[Self::OMEGA]`
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeIndexConstants);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeIndexConstants {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[Self::X] * qd[Self::X] + qd[Self::Y] * qd[Self::Y])
            + 0.5 * self.j * qd[Self::PHI] * qd[Self::PHI]
            + self.m * self.g * self.incline.sin() * q[Self::X]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[Self::X] * q[Self::PHI].sin() - qd[Self::Y] * q[Self::PHI].cos()]
    }

    /// The speeds' index constants number the free speeds: `Self::V` is 0.
    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        let mut w = [0.0; 2];
        w[Self::V] = qd[Self::X] * q[Self::PHI].cos() + qd[Self::Y] * q[Self::PHI].sin();
        w[Self::OMEGA] = qd[Self::PHI];
        w
    }
}

#[test]
fn generated_index_constants() {
    assert_eq!(
        (KnifeIndexConstants::PHI, KnifeIndexConstants::OMEGA),
        (2, 1)
    );
    check_knife("Self::PHI index consts", &KnifeIndexConstants::new());
}

// ---------------------------------------------------------------------------------------------
// A `#[velocities]` closed-form inverse (against the sleigh of the catalogue, whose inverse
// comes from a run-time LU of A(q))
// ---------------------------------------------------------------------------------------------

#[hamel_system]
struct SleighWithInverse {
    m: f64,
    inertia: f64,
    a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl SleighWithInverse {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    /// The centre of mass moves at v along the body's axis and at (ω¹ + a ω) across it.
    #[velocities]
    fn velocities(&self, q: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
        let (s, c) = q[2].sin_cos();
        let across = w[0] + self.a * w[2];
        [c * w[1] - s * across, s * w[1] + c * across, w[2]]
    }
}

#[test]
fn closed_form_inverse() {
    let reference = ChaplyginSleigh::default();
    let model = SleighWithInverse {
        m: reference.m,
        inertia: reference.inertia,
        a: reference.a,
    };
    let q = [0.3, -0.1, 0.7];
    assert!(model.inverse_defect(0.0, &q).unwrap() < 1e-15);
    check_same_system(
        "#[velocities] (sleigh)",
        &model,
        [],
        &reference,
        [0.0; 3],
        [1.0, 2.0],
    );
}

// ---------------------------------------------------------------------------------------------
// `#[forces]` with inputs (forces along x and y and a torque about the vertical, applied at
// the contact point; index constants of the inputs)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeForced);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega), inputs(fx, fy, torque))]
impl KnifeForced {
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.j * qd[2] * qd[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    #[forces]
    fn forces(&self, _t: f64, _q: &[f64; 3], _qd: &[f64; 3], u: &[f64; 3]) -> [f64; 3] {
        [u[Self::FX], u[Self::FY], u[Self::TORQUE]]
    }
}

#[test]
fn forces_with_inputs() {
    let model = KnifeForced::new();
    // Without inputs, the same system.
    check_same_system(
        "#[forces], u = 0",
        &model,
        [0.0; 3],
        &knife_edge(),
        KNIFE_Q0,
        KNIFE_SPEEDS0,
    );
    // With inputs: the force's component along the blade accelerates the path speed, the
    // torque the turning (the component across the blade is taken by the constraint):
    // Δv̇ = (fx cos φ + fy sin φ)/m, Δω̇ = τ/J.
    let mut rng = XorShift::new(0xf0_4ce5);
    let mut worst = 0.0f64;
    for _ in 0..64 {
        let x = random_state(&mut rng);
        let u = [
            rng.uniform(-5.0, 5.0),
            rng.uniform(-5.0, 5.0),
            rng.uniform(-5.0, 5.0),
        ];
        let (mut free, mut forced) = ([0.0; 5], [0.0; 5]);
        model.rhs(0.0, &x, &[0.0; 3], &mut free).unwrap();
        model.rhs(0.0, &x, &u, &mut forced).unwrap();
        let (s, c) = x[2].sin_cos();
        let mut expected = free;
        expected[3] += (u[0] * c + u[1] * s) / MASS;
        expected[4] += u[2] / INERTIA;
        let e = relative(&forced, &expected);
        assert!(
            e <= 1e-12,
            "forced rhs {forced:?} vs {expected:?} at {x:?}, u = {u:?}"
        );
        worst = worst.max(e);
    }
    println!("#[forces], u ≠ 0 vs closed form   rhs {worst:.1e}");
}

// ---------------------------------------------------------------------------------------------
// `#[quasi_lagrangian]` L̃(q, ω) (ω¹ = ẋ sin φ − ẏ cos φ is the constrained one; B from A)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeQuasiLagrangian);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeQuasiLagrangian {
    /// The blade frame is orthonormal: ẋ² + ẏ² = (ω¹)² + (ω²)².
    #[quasi_lagrangian]
    fn lagrangian(&self, q: &[f64; 3], w: &[f64; 3]) -> f64 {
        0.5 * self.m * (w[0] * w[0] + w[1] * w[1])
            + 0.5 * self.j * w[2] * w[2]
            + self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn quasi_lagrangian() {
    check_knife("#[quasi_lagrangian]", &KnifeQuasiLagrangian::new());
}

// ---------------------------------------------------------------------------------------------
// `#[kinetic_energy]` + `#[potential_energy]` (against the knife edge's `#[lagrangian]`), and
// `#[lagrangian]` (against the sleigh's `#[kinetic_energy]` alone)
// ---------------------------------------------------------------------------------------------

knife_parameters!(KnifeSplitEnergy);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeSplitEnergy {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2]
    }

    /// x points down the slope: the height is −x sin(incline).
    #[potential_energy]
    fn potential_energy(&self, q: &[f64; 3]) -> f64 {
        -self.m * self.g * self.incline.sin() * q[0]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn kinetic_and_potential_energy() {
    check_knife("#[kinetic_energy]+#[potential]", &KnifeSplitEnergy::new());
}

#[hamel_system]
struct SleighLagrangian {
    m: f64,
    inertia: f64,
    a: f64,
}

#[hamel_system(coordinates(x, y, theta), speeds(v, omega))]
impl SleighLagrangian {
    #[lagrangian]
    fn lagrangian(&self, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.inertia * qd[2] * qd[2]
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [-qd[0] * q[2].sin() + qd[1] * q[2].cos() - self.a * qd[2]]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn lagrangian_against_kinetic_energy() {
    let reference = ChaplyginSleigh::default();
    let model = SleighLagrangian {
        m: reference.m,
        inertia: reference.inertia,
        a: reference.a,
    };
    check_same_system(
        "#[lagrangian] (sleigh)",
        &model,
        [],
        &reference,
        [0.0; 3],
        [1.0, 2.0],
    );
}

// ---------------------------------------------------------------------------------------------
// Role functions without a receiver (associated functions, no `&self`)
// ---------------------------------------------------------------------------------------------

#[hamel_system]
struct KnifeAssociatedRoles;

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeAssociatedRoles {
    #[lagrangian]
    fn lagrangian(q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        0.5 * MASS * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * INERTIA * qd[2] * qd[2]
            + MASS * GRAVITY * INCLINE.sin() * q[0]
    }

    #[constraints]
    fn blade(q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn role_functions_without_receiver() {
    check_knife("roles without &self", &KnifeAssociatedRoles);
}

// =============================================================================================
// Regression tests for an engine bug this suite found (fixed)
// =============================================================================================

// ---------------------------------------------------------------------------------------------
// An `if`/`else` *statement* whose two branches leave a `let mut` local with the same value
// (the same node of the hash-consed graph, e.g. `y += x` in both, or `l -= -v` and `l += v`
// after normalization) once dropped the update: the local kept its value from before the
// `if`, because the branches were merged only where they differed.
// ---------------------------------------------------------------------------------------------

struct EqualBranchStatements;

#[hamel::differentiate]
#[allow(clippy::if_same_then_else)]
impl EqualBranchStatements {
    fn f(&self, x: f64) -> f64 {
        let mut y = 1.0;
        if x > 0.0 {
            y += x;
        } else {
            y += x;
        }
        y
    }
}

#[test]
fn if_else_statement_with_equal_branches_updates_the_local() {
    for x in [-1.5, 0.5] {
        assert_eq!(EqualBranchStatements.f(x), 1.0 + x);
        assert_eq!(
            EqualBranchStatements.f_generic::<f64>(x),
            1.0 + x,
            "value at x = {x}"
        );
        assert_eq!(
            EqualBranchStatements.f_gradient(x),
            [1.0],
            "gradient at x = {x}"
        );
    }
}

knife_parameters!(KnifeEqualBranchStatements);

#[hamel_system(coordinates(x, y, phi), speeds(v, omega))]
impl KnifeEqualBranchStatements {
    /// The potential added on either side of the origin, written two ways that the engine's
    /// normal forms make one node: the gravity term disappears from the equations.
    #[lagrangian]
    fn lagrangian(&self, q: &[f64; 3], qd: &[f64; 3]) -> f64 {
        let mut l = 0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * self.j * qd[2] * qd[2];
        let weight = self.m * self.g * self.incline.sin();
        if q[0] > 0.0 {
            l -= -weight * q[0];
        } else {
            l += weight * q[0];
        }
        l
    }

    #[constraints]
    fn blade(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
        [qd[0] * q[2].sin() - qd[1] * q[2].cos()]
    }

    #[quasi_velocities]
    fn speeds(&self, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }
}

#[test]
fn knife_edge_keeps_gravity_from_equal_branch_statements() {
    // v̇ once came out 0 instead of g sin(incline) cos φ.
    check_knife(
        "equal-branch statements in a model",
        &KnifeEqualBranchStatements::new(),
    );
}
