//! CasADi's external-function convention: for a primal function `f` (a model's right-hand
//! side `<model>_f`, or its outputs `<model>_h`), the functions CasADi loads by name beside
//! it — `jac_f`, `fwd1_f`, `adj1_f` and `jac_adj1_f` (what an exact Hessian of the Lagrangian
//! is built from), and `fwd2_f`, `fwd4_f`, `fwd8_f` (several forward directions in one call,
//! see [`Kind::directions`]) — each with the symbols `f`, `f_n_in`, `f_n_out`, `f_sparsity_in`,
//! `f_sparsity_out`, `f_name_in`, `f_name_out`, `f_work`, `f_default_in`, `f_incref`,
//! `f_decref`, `f_checkout`, `f_release`, `f_alloc_mem`, `f_init_mem`, `f_free_mem`, with
//! the inputs, outputs and names CasADi's own code generation gives the same derivatives
//! (`jac_f: (x, u, p, out_xdot) -> (jac_xdot_x, jac_xdot_u, jac_xdot_p)`, …), so that
//! `casadi.external` finds them and CasADi's checks of their shapes pass.
//!
//! [`Family`] describes the eight; [`eval`] evaluates one. The symbols themselves are written
//! by [`crate::casadi!`]. With compiled code (feature `compiled`), the sparsity of each
//! derivative block is the compiled code's own (the entries that are not a constant zero on
//! the model's graph), and [`plan`] says which outputs the compiled code fills (it writes
//! each entry straight into its place, [`crate::layout`]).

mod eval;
mod fast;
pub mod plan;
pub mod sparsity;
pub mod symbols;

pub use eval::{call, eval};
use plan::{Plans, Structure};
use sparsity::Pattern;

use crate::model::Model;
use crate::primal::{Primal, Which};
use std::ffi::CString;

/// The five functions of a family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `f`: the values.
    Value,
    /// `jac_f`: every block ∂out/∂input, sparse.
    Jacobian,
    /// `fwd1_f`: one forward directional derivative.
    Forward,
    /// `adj1_f`: one adjoint (reverse) directional derivative.
    Adjoint,
    /// `jac_adj1_f`: the Jacobian of `adj1_f`: the second derivatives λ·∂²out, and ∂outᵀ.
    AdjointJacobian,
    /// `fwd2_f`: two forward directional derivatives in one call.
    Forward2,
    /// `fwd4_f`: four.
    Forward4,
    /// `fwd8_f`: eight.
    Forward8,
}

impl Kind {
    pub const ALL: [Kind; 8] = [
        Kind::Value,
        Kind::Jacobian,
        Kind::Forward,
        Kind::Adjoint,
        Kind::AdjointJacobian,
        Kind::Forward2,
        Kind::Forward4,
        Kind::Forward8,
    ];

    /// How many forward directions one call takes (0: not a forward derivative).
    ///
    /// CasADi propagates d forward directions through a call of an external function in
    /// batches of the largest power of two N ≤ 64 with a `fwd<N>_f`, and calls `fwd<N>_f`
    /// for a batch of exactly N directions, `fwd1_f` once per direction for any other
    /// batch (`FunctionInternal::call_forward` and `External::get_forward`, CasADi 3.8). The
    /// largest N exported is thus the batch size: 8, because the Jacobian of a multiple
    /// shooting NLP over the robot propagates 8 or 9 directions a call (its coloring): with
    /// `fwd8_f` that is one call, or two (8 and 1); with `fwd16_f` a batch of 9 would be 9
    /// calls of `fwd1_f`.
    pub fn directions(self) -> usize {
        match self {
            Kind::Forward => 1,
            Kind::Forward2 => 2,
            Kind::Forward4 => 4,
            Kind::Forward8 => 8,
            Kind::Value | Kind::Jacobian | Kind::Adjoint | Kind::AdjointJacobian => 0,
        }
    }

    /// The prefix of the function's name: `jac_f` is `jac_` and `f`.
    pub fn prefix(self) -> &'static str {
        match self {
            Kind::Value => "",
            Kind::Jacobian => "jac_",
            Kind::Forward => "fwd1_",
            Kind::Adjoint => "adj1_",
            Kind::AdjointJacobian => "jac_adj1_",
            Kind::Forward2 => "fwd2_",
            Kind::Forward4 => "fwd4_",
            Kind::Forward8 => "fwd8_",
        }
    }
}

/// A named input or output with its sparsity.
#[derive(Clone, Debug)]
pub struct Port {
    /// The name for C (`_name_in`, `_name_out`).
    pub name: CString,
    /// The same name for messages, kept as text so that a call does not convert it.
    text: String,
    pub pattern: Pattern,
}

impl Port {
    fn new(name: &str, pattern: Pattern) -> Port {
        Port {
            name: CString::new(name).unwrap_or_default(),
            text: name.to_string(),
            pattern,
        }
    }

    pub fn name(&self) -> &str {
        &self.text
    }
}

/// What an output holds, for the evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Content {
    /// The primal output's values.
    Value,
    /// ∂out/∂(input block `i`).
    Jacobian(usize),
    /// The forward derivatives, one column per direction.
    Forward,
    /// (∂out/∂(input block `i`))ᵀ λ.
    Adjoint(usize),
    /// Σ_r λ_r ∂²out_r/∂(block i)∂(block j).
    Second(usize, usize),
    /// (∂out/∂(input block `i`))ᵀ: the derivative of the adjoint by λ.
    Transposed(usize),
    /// Structurally zero (a derivative by a nominal output).
    Zero,
}

/// One function: its ports and what each output holds.
#[derive(Clone, Debug)]
pub struct Function {
    pub kind: Kind,
    pub inputs: Vec<Port>,
    pub outputs: Vec<(Port, Content)>,
}

/// The eight functions of one primal function, described once (on first use) and shared
/// by every call, from any thread.
#[derive(Clone, Debug)]
pub struct Family {
    pub primal: Primal,
    pub functions: [Function; 8],
    /// Where the compiled code's entries go; `None` without compiled code.
    pub plans: Option<Plans>,
}

impl Family {
    pub fn new<M: Model>(which: Which) -> Family {
        let primal = Primal::new::<M>(which);
        let structure = Structure::new::<M>(&primal);
        let functions = Kind::ALL.map(|kind| function(&primal, &structure, kind));
        let scratch = M::scratch().as_mut().len();
        let plans = Plans::new(&primal, &structure, &functions, scratch);
        Family {
            primal,
            functions,
            plans,
        }
    }

    pub fn function(&self, kind: Kind) -> &Function {
        &self.functions[kind as usize]
    }
}

/// The ports of `kind` for `primal`, named as CasADi names them, with the sparsity of
/// `structure`.
fn function(primal: &Primal, structure: &Structure, kind: Kind) -> Function {
    let (out, no) = primal.output;
    let column = |name: &str, n: usize| Port::new(name, Pattern::dense(n, 1));
    let nominal = |name: &str, n: usize| Port::new(&format!("out_{name}"), Pattern::empty(n, 1));
    let mut inputs: Vec<Port> = primal
        .inputs
        .iter()
        .map(|b| column(b.name, b.len))
        .collect();
    let mut outputs = Vec::new();
    let blocks = &primal.inputs;
    let jacobian = |i: usize| structure.jacobian(primal, i);
    match kind {
        Kind::Value => outputs.push((column(out, no), Content::Value)),
        Kind::Jacobian => {
            inputs.push(nominal(out, no));
            for (i, b) in blocks.iter().enumerate() {
                let name = format!("jac_{out}_{}", b.name);
                outputs.push((Port::new(&name, jacobian(i)), Content::Jacobian(i)));
            }
        }
        Kind::Forward | Kind::Forward2 | Kind::Forward4 | Kind::Forward8 => {
            // One column per direction, as CasADi stacks them (`horzcat` of the seeds).
            let n = kind.directions();
            let columns = |name: &str, len: usize| Port::new(name, Pattern::dense(len, n));
            inputs.push(nominal(out, no));
            inputs.extend(
                blocks
                    .iter()
                    .map(|b| columns(&format!("fwd_{}", b.name), b.len)),
            );
            outputs.push((columns(&format!("fwd_{out}"), no), Content::Forward));
        }
        Kind::Adjoint => {
            inputs.push(nominal(out, no));
            inputs.push(column(&format!("adj_{out}"), no));
            for (i, b) in blocks.iter().enumerate() {
                let port = column(&format!("adj_{}", b.name), b.len);
                outputs.push((port, Content::Adjoint(i)));
            }
        }
        Kind::AdjointJacobian => {
            inputs.push(nominal(out, no));
            inputs.push(column(&format!("adj_{out}"), no));
            inputs.extend(
                blocks
                    .iter()
                    .map(|b| nominal(&format!("adj_{}", b.name), b.len)),
            );
            for (i, bi) in blocks.iter().enumerate() {
                let name = |with: &str| format!("jac_adj_{}_{with}", bi.name);
                for (j, bj) in blocks.iter().enumerate() {
                    let pattern = structure.second(primal, i, j);
                    outputs.push((Port::new(&name(bj.name), pattern), Content::Second(i, j)));
                }
                let zero = Port::new(&name(&format!("out_{out}")), Pattern::empty(bi.len, no));
                outputs.push((zero, Content::Zero));
                let transposed = structure.jacobian(primal, i).transposed();
                let port = Port::new(&name(&format!("adj_{out}")), transposed);
                outputs.push((port, Content::Transposed(i)));
            }
        }
    }
    Function {
        kind,
        inputs,
        outputs,
    }
}
