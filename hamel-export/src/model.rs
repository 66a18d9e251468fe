//! A model as the export sees it: its functions over any scalar type with every argument in
//! one flat vector z = (x, u, p, t), and what the generated code knows of them (which
//! arguments each result depends on). Implemented for a model by [`crate::model!`] (from the
//! items `#[hamel_system]` generates), on a marker type of the exporting crate.

use hamel_runtime::{HamelSystem, Parameters, Scalar, Singularity};

/// The functions of a model, over any [`Scalar`], on the flat argument vector
/// z = (x, u, p, t): the state (`HamelSystem::STATE`), the inputs (`HamelSystem::INPUTS`), the
/// parameters (`Parameters::NAMES`, the order of the struct's fields) and the time.
pub trait Model: 'static {
    /// The model's type (its parameter struct, with `HamelSystem` on it).
    type System: HamelSystem + Default;
    /// A stack array of the length of z (the macro knows the sizes; this crate's generic
    /// code does not, and allocates nothing).
    type Array<S: Copy>: AsRef<[S]> + AsMut<[S]> + Copy;

    /// Whether the right-hand side depends on the time explicitly (then the exported
    /// functions take it as their last argument).
    const TIME_DEPENDENT: bool;
    /// For each component of ẋ, the components of (x, u) it depends on (indices into x,
    /// then u), from the generated code's graph.
    const RHS_COLUMNS: &'static [&'static [usize]];
    /// For each component of ẋ, the parameters it depends on, by name.
    const RHS_PARAMETERS: &'static [&'static [&'static str]];
    /// The outputs' names (`ControlAffine::OUTPUTS`); empty for a model without outputs.
    const OUTPUTS: &'static [&'static str];
    /// For each output, the components of x it depends on.
    const OUTPUT_COLUMNS: &'static [&'static [usize]];
    /// For each output, the parameters it depends on, by name.
    const OUTPUT_PARAMETERS: &'static [&'static [&'static str]];

    /// An array of the length of z, every entry `fill`.
    fn array<S: Copy>(fill: S) -> Self::Array<S>;

    /// ẋ = F(t, x, u; p) into `dx` (its first `nx` entries), from z.
    fn rhs<S: Scalar>(z: &Self::Array<S>, dx: &mut Self::Array<S>) -> Result<(), Singularity>;

    /// y = h(t, x; p) into `y` (its first `ny` entries), from z; nothing for a model without
    /// outputs.
    fn outputs<S: Scalar>(z: &Self::Array<S>, y: &mut Self::Array<S>);
}

/// The sizes of z's parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sizes {
    pub nx: usize,
    pub nu: usize,
    pub np: usize,
    pub ny: usize,
}

impl Sizes {
    pub fn of<M: Model>() -> Sizes {
        Sizes {
            nx: <M::System as HamelSystem>::STATE.len(),
            nu: <M::System as HamelSystem>::INPUTS.len(),
            np: <M::System as Parameters>::NAMES.len(),
            ny: M::OUTPUTS.len(),
        }
    }

    /// Where u starts in z.
    pub fn u(&self) -> usize {
        self.nx
    }

    /// Where p starts in z.
    pub fn p(&self) -> usize {
        self.nx + self.nu
    }

    /// Where t is in z.
    pub fn t(&self) -> usize {
        self.nx + self.nu + self.np
    }

    /// The length of z.
    pub fn z(&self) -> usize {
        self.t() + 1
    }
}
