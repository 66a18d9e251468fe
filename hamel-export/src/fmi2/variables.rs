//! The FMU's variables: what each value reference is, in one table that the model
//! description and the running instance share (the description lists the table in order,
//! so that a variable's index in `ModelVariables` is its value reference plus one).
//!
//! Reals, in this order: the time; the state x, named as in the model; the derivatives
//! `der(x)`; the inputs u; the parameters p (tunable, in the struct's order); the outputs y
//! of a model with `#[outputs]`; the `energy`; the constraint rows at the velocity level
//! (`constraint.<name>`, A_c q̇ + a_c, one per constraint); the holonomic constraints at the
//! position level (`holonomic.<name>`, f(t, q)); the fixed step of the fixed-step
//! integrators (`hamel.step`). Then one enumeration, the Co-Simulation integrator
//! (`hamel.integrator`).

use crate::model::{Model, Sizes};
use hamel_runtime::{HamelSystem, Parameters};

/// What a value reference stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Time,
    State(usize),
    Derivative(usize),
    Input(usize),
    Parameter(usize),
    Output(usize),
    Energy,
    /// A constraint row A_c q̇ + a_c (velocity level), by its index in `CONSTRAINTS`.
    Constraint(usize),
    /// A holonomic constraint f(t, q) (position level), by its index among the K.
    Holonomic(usize),
    /// The step of the fixed-step integrators (Co-Simulation).
    Step,
    /// The Co-Simulation integrator, an enumeration.
    Integrator,
}

/// The integrators Co-Simulation offers (`hamel.integrator`), in the enumeration's order
/// (its values start at 1): the name, whether it is adaptive (the tolerance applies) or takes
/// equal steps of at most `hamel.step`, and what it is.
pub const INTEGRATORS: &[(&str, bool, &str)] = &[
    (
        "dopri5",
        true,
        "Dormand-Prince 5(4), adaptive (the default)",
    ),
    (
        "radau5",
        true,
        "Radau IIA of order 5, implicit and adaptive: for stiff models",
    ),
    (
        "rk4",
        false,
        "the classical Runge-Kutta method of order 4, fixed steps",
    ),
    (
        "gauss2",
        false,
        "Gauss-Legendre with 2 stages (order 4), symmetric, fixed steps",
    ),
    (
        "gauss3",
        false,
        "Gauss-Legendre with 3 stages (order 6), symmetric, fixed steps",
    ),
    (
        "midpoint",
        false,
        "the implicit midpoint rule (order 2), symmetric, fixed steps",
    ),
];

/// The default of `hamel.step` (s): the fixed-step integrators' step.
pub const DEFAULT_STEP: f64 = 1e-3;

/// The variables of model `M`: the value reference of variable `i` is `i`.
#[derive(Clone, Debug)]
pub struct Table {
    pub roles: Vec<Role>,
    pub sizes: Sizes,
    /// K, the holonomic constraints.
    pub k: usize,
    /// P, the constraint rows (the holonomic ones' time derivatives included).
    pub p: usize,
}

impl Table {
    pub fn of<M: Model>() -> Table {
        let sizes = Sizes::of::<M>();
        let k = <M::System as HamelSystem>::K;
        let p = <M::System as HamelSystem>::CONSTRAINTS.len();
        let mut roles = vec![Role::Time];
        roles.extend((0..sizes.nx).map(Role::State));
        roles.extend((0..sizes.nx).map(Role::Derivative));
        roles.extend((0..sizes.nu).map(Role::Input));
        roles.extend((0..sizes.np).map(Role::Parameter));
        roles.extend((0..sizes.ny).map(Role::Output));
        roles.push(Role::Energy);
        roles.extend((0..p).map(Role::Constraint));
        roles.extend((0..k).map(Role::Holonomic));
        roles.push(Role::Step);
        roles.push(Role::Integrator);
        Table { roles, sizes, k, p }
    }

    /// The role of value reference `vr`, if there is such a variable.
    pub fn role(&self, vr: u32) -> Option<Role> {
        self.roles.get(vr as usize).copied()
    }

    /// The value reference of a role (its position in the table).
    pub fn reference(&self, role: Role) -> u32 {
        let s = &self.sizes;
        let at = match role {
            Role::Time => 0,
            Role::State(i) => 1 + i,
            Role::Derivative(i) => 1 + s.nx + i,
            Role::Input(i) => 1 + 2 * s.nx + i,
            Role::Parameter(i) => 1 + 2 * s.nx + s.nu + i,
            Role::Output(i) => 1 + 2 * s.nx + s.nu + s.np + i,
            Role::Energy => 1 + 2 * s.nx + s.nu + s.np + s.ny,
            Role::Constraint(i) => 2 + 2 * s.nx + s.nu + s.np + s.ny + i,
            Role::Holonomic(i) => 2 + 2 * s.nx + s.nu + s.np + s.ny + self.p + i,
            Role::Step => 2 + 2 * s.nx + s.nu + s.np + s.ny + self.p + self.k,
            Role::Integrator => 3 + 2 * s.nx + s.nu + s.np + s.ny + self.p + self.k,
        };
        at as u32
    }

    /// The variable's index in `ModelVariables` (1-based), as `ModelStructure` names it.
    pub fn index(&self, role: Role) -> usize {
        self.reference(role) as usize + 1
    }
}

/// The name of a variable in the model description, and in messages.
pub fn name<M: Model>(role: Role) -> String {
    let system_names = |names: &[&str], i: usize| names.get(i).map_or("?", |n| n).to_string();
    match role {
        Role::Time => "time".to_string(),
        Role::State(i) => system_names(<M::System as HamelSystem>::STATE, i),
        Role::Derivative(i) => format!(
            "der({})",
            system_names(<M::System as HamelSystem>::STATE, i)
        ),
        Role::Input(i) => system_names(<M::System as HamelSystem>::INPUTS, i),
        Role::Parameter(i) => system_names(<M::System as Parameters>::NAMES, i),
        Role::Output(i) => system_names(M::OUTPUTS, i),
        Role::Energy => "energy".to_string(),
        Role::Constraint(i) => format!(
            "constraint.{}",
            system_names(<M::System as HamelSystem>::CONSTRAINTS, i)
        ),
        Role::Holonomic(i) => {
            let names = <M::System as HamelSystem>::CONSTRAINTS;
            let k = <M::System as HamelSystem>::K;
            let first = names.len().saturating_sub(k);
            format!("holonomic.{}", system_names(names, first + i))
        }
        Role::Step => "hamel.step".to_string(),
        Role::Integrator => "hamel.integrator".to_string(),
    }
}

/// Whether state `i` is a coordinate the holonomic constraints determine: its start value
/// is a guess (`initial="approx"`), solved for at `fmi2ExitInitializationMode`.
pub fn is_dependent<M: Model>(i: usize) -> bool {
    <M::System as HamelSystem>::DEPENDENT.contains(&i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_are_positions() {
        // A table of the sizes of the robot: 8 states, 2 inputs, 9 parameters, 2 outputs,
        // 2 constraints, none holonomic.
        let sizes = Sizes {
            nx: 8,
            nu: 2,
            np: 9,
            ny: 2,
        };
        let mut roles = vec![Role::Time];
        roles.extend((0..8).map(Role::State));
        roles.extend((0..8).map(Role::Derivative));
        roles.extend((0..2).map(Role::Input));
        roles.extend((0..9).map(Role::Parameter));
        roles.extend((0..2).map(Role::Output));
        roles.push(Role::Energy);
        roles.extend((0..2).map(Role::Constraint));
        roles.push(Role::Step);
        roles.push(Role::Integrator);
        let table = Table {
            roles,
            sizes,
            k: 0,
            p: 2,
        };
        for (vr, role) in table.roles.iter().enumerate() {
            assert_eq!(table.reference(*role), vr as u32, "{role:?}");
            assert_eq!(table.role(vr as u32), Some(*role));
        }
        assert_eq!(table.role(table.roles.len() as u32), None);
    }
}
