//! A model as the export sees it: its functions over any scalar type with every argument in
//! one flat vector z = (x, u, p, t), what the generated code knows of them (which arguments
//! each result depends on), and — with this crate's feature `compiled` — the straight-line
//! derivative code `#[hamel_system]` emits for the export. Implemented for a model by
//! [`crate::model!`] (from the items `#[hamel_system]` generates), on a marker type of the
//! exporting crate.

use crate::layout::{Destinations, Layout};
use crate::primal::Which;
use hamel_runtime::{HamelSystem, Parameters, Scalar, Singularity};

/// What the generated code tells of a compiled function (`Which`): its sparse derivatives'
/// entries over its local columns (x, u, the parameters it reads, t), in the order its code
/// writes them.
#[derive(Clone, Copy, Debug)]
pub struct Tables {
    /// How many output components.
    pub outputs: usize,
    /// The Jacobian's entries (row, column), those by x, u and t first.
    pub jacobian: &'static [(usize, usize)],
    /// The weighted second derivatives' entries (row ≥ column), likewise ordered.
    pub second: &'static [(usize, usize)],
    /// Which stages are compiled: the Jacobian by x, u, t; by p; the second derivatives
    /// likewise. A stage that is not is computed by dual numbers.
    pub compiled: [bool; 4],
    /// How many entries of `jacobian` and of `second` are by x, u and t.
    pub states: [usize; 2],
    /// For each output component, the columns it depends on.
    pub depends: &'static [&'static [usize]],
    /// Where the compiled code puts each entry in CasADi's output blocks.
    pub layout: Layout,
}

/// The functions of a model, over any [`Scalar`], on the flat argument vector
/// z = (x, u, p, t): the state (`HamelSystem::STATE`), the inputs (`HamelSystem::INPUTS`), the
/// parameters (`Parameters::NAMES`, the order of the struct's fields) and the time.
pub trait Model: 'static {
    /// The model's type (its parameter struct, with `HamelSystem` on it).
    type System: HamelSystem + Default;
    /// A stack array at least as long as z and as each function's output (the macro knows
    /// the sizes; this crate's generic code does not, and allocates nothing).
    type Array<S: Copy>: AsRef<[S]> + AsMut<[S]> + Copy;
    /// The values of the compiled code that depend on the parameters alone (`()` without
    /// compiled code).
    type Prepared: 'static;
    /// A buffer for the outputs CasADi does not ask for, which the compiled code writes
    /// all the same: at least as long as any output of `jac_f` and `jac_adj1_f`.
    type Scratch: AsMut<[core::mem::MaybeUninit<f64>]>;

    /// Whether the model has the compiled derivative code (feature `compiled`): then every
    /// family has its [`crate::casadi::plan::Plans`].
    const COMPILED: bool;
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
    /// The parameters the generated code reads, as positions in `Parameters::NAMES`: the
    /// compiled code's parameter columns.
    const READ: &'static [usize];
    /// Whether [`Model::READ`] holds every parameter (then the derivatives by the
    /// parameters have no entry the compiled code leaves out).
    const READS_ALL: bool;
    /// How many Lie derivatives (L_f^k h for k = 0 … order, then L_{g_j} L_f^k h for
    /// k < order); zero without compiled code or `control(..)`.
    const LIE: usize;

    /// An array every entry `fill`.
    fn array<S: Copy>(fill: S) -> Self::Array<S>;

    /// An array whose values are all written: `a` as values.
    ///
    /// # Safety
    /// Every value of `a` is initialized.
    unsafe fn assume_init_ref(a: &Self::Array<core::mem::MaybeUninit<f64>>) -> &Self::Array<f64>;

    /// A scratch buffer, not initialized.
    fn scratch() -> Self::Scratch;

    /// ẋ = F(t, x, u; p) into `dx` (its first `nx` entries), from z.
    fn rhs<S: Scalar>(z: &Self::Array<S>, dx: &mut Self::Array<S>) -> Result<(), Singularity>;

    /// y = h(t, x; p) into `y` (its first `ny` entries), from z; nothing for a model without
    /// outputs.
    fn outputs<S: Scalar>(z: &Self::Array<S>, y: &mut Self::Array<S>);

    /// The Lie derivatives into `out` (its first `LIE` entries), from z.
    fn lie<S: Scalar>(z: &Self::Array<S>, out: &mut Self::Array<S>) -> Result<(), Singularity>;

    /// The tables of `which`'s compiled code; `None` without it.
    fn tables(which: Which) -> Option<Tables>;

    /// `then` with the values the compiled code prepares for the parameters `p` (z's
    /// parameter block), computed once per parameter set and thread.
    fn with_prepared<R>(p: &[f64], then: impl FnOnce(&Self::Prepared) -> R) -> R;

    /// The compiled code of family `W` ([`crate::units::RHS`], `OUTPUTS` or `LIE`), called
    /// by [`crate::units`] only (where it is optimized), each `None` without compiled code
    /// (these defaults; `model!` overrides them where the code is compiled) or when an array
    /// is too short: the values into `out`.
    fn value_of<const W: u8>(
        _prepared: &Self::Prepared,
        _z: &Self::Array<f64>,
        _out: &mut [f64],
    ) -> Option<Result<(), Singularity>> {
        None
    }

    /// The Jacobian's entries, each into its place in `jac_f`'s outputs (`Layout::jacobian`)
    /// through `to` (`Ok(false)`, nothing written: that stage is not compiled).
    ///
    /// # Safety
    /// Each pointer of `to` points to writable values for every slot `Layout::jacobian`
    /// gives its output (the stages asked for).
    unsafe fn jacobian_of<const W: u8>(
        _prepared: &Self::Prepared,
        _z: &Self::Array<f64>,
        _parameters: bool,
        _to: &Destinations,
    ) -> Option<Result<bool, Singularity>> {
        None
    }

    /// The right-hand side's `N` forward derivatives by x, u and t as products of its
    /// compiled Jacobian (the stage by x, u and t) with the directions, each entry
    /// multiplied as the compiled code gives it, not stored: `out[r] += J[r][c] ·
    /// directions[c]` over the compiled code's columns (x, u, the parameters it reads, t).
    /// `None` without compiled code; `Some(Ok(false))` if that stage is not compiled.
    ///
    /// # Safety
    /// Every row of `directions` below the compiled code's number of columns, and every row
    /// of `out` below the number of outputs, is initialized (the rows the entries read and
    /// add to: [`crate::casadi::plan::Products`] checks the tables against those bounds).
    unsafe fn products_of<const N: usize>(
        _prepared: &Self::Prepared,
        _z: &Self::Array<f64>,
        _directions: &Self::Array<core::mem::MaybeUninit<[f64; N]>>,
        _out: &mut Self::Array<core::mem::MaybeUninit<[f64; N]>>,
    ) -> Option<Result<bool, Singularity>> {
        None
    }

    /// The derivative along `direction` into `out`.
    fn forward_of<const W: u8>(
        _prepared: &Self::Prepared,
        _z: &Self::Array<f64>,
        _direction: &[f64],
        _parameters: bool,
        _out: &mut [f64],
    ) -> Option<Result<(), Singularity>> {
        None
    }

    /// The adjoint derivative into `out`: on `Some(Ok(()))`, every one of its first
    /// `Sizes::p() + READ.len() + 1` values (the local columns) is written, the
    /// parameters' only if `parameters`.
    fn adjoint_of<const W: u8>(
        _prepared: &Self::Prepared,
        _z: &Self::Array<f64>,
        _weights: &[f64],
        _parameters: bool,
        _out: &mut Self::Array<core::mem::MaybeUninit<f64>>,
    ) -> Option<Result<(), Singularity>> {
        None
    }

    /// The weighted second derivatives' entries and the Jacobian's, each into its places in
    /// `jac_adj1_f`'s outputs (`Layout::second`, `Layout::transposed`) through `to`
    /// (`Ok(false)`, nothing written: that stage is not compiled).
    ///
    /// # Safety
    /// As [`Model::jacobian_of`], for the slots of `Layout::second` and `Layout::transposed`.
    unsafe fn second_of<const W: u8>(
        _prepared: &Self::Prepared,
        _z: &Self::Array<f64>,
        _weights: &[f64],
        _parameters: bool,
        _to: &Destinations,
    ) -> Option<Result<bool, Singularity>> {
        None
    }

    /// The values of `which` at z into `out`; `None` without compiled code.
    fn compiled_value(
        which: Which,
        prepared: &Self::Prepared,
        z: &Self::Array<f64>,
        out: &mut [f64],
    ) -> Option<Result<(), Singularity>>;

    /// The Jacobian's entries (by the parameters only if `parameters`) into `jac_f`'s outputs
    /// through `to`: `Ok(true)`; `Ok(false)` (nothing written) where a stage asked for is not
    /// compiled; `None` without compiled code.
    ///
    /// # Safety
    /// As [`Model::jacobian_of`].
    unsafe fn compiled_jacobian(
        which: Which,
        prepared: &Self::Prepared,
        z: &Self::Array<f64>,
        parameters: bool,
        to: &Destinations,
    ) -> Option<Result<bool, Singularity>>;

    /// The derivative along `direction` (over the local columns) into `out`; with the
    /// parameters' part only if `parameters`.
    fn compiled_forward(
        which: Which,
        prepared: &Self::Prepared,
        z: &Self::Array<f64>,
        direction: &[f64],
        parameters: bool,
        out: &mut [f64],
    ) -> Option<Result<(), Singularity>>;

    /// The adjoint derivative with `weights` into `out` (over the local columns): on
    /// `Some(Ok(()))`, every one of the first `Sizes::p() + READ.len() + 1` values of
    /// `out` (the local columns) is written, the parameters' only if `parameters`, as the
    /// tables the generated code states beside it say (`__HAMEL_EXPORT_*_ADJOINT_WRITES`,
    /// checked at compile time by `model!`; the test `compiled_adjoint_writes_every_column`
    /// checks the code against them).
    fn compiled_adjoint(
        which: Which,
        prepared: &Self::Prepared,
        z: &Self::Array<f64>,
        weights: &[f64],
        parameters: bool,
        out: &mut Self::Array<core::mem::MaybeUninit<f64>>,
    ) -> Option<Result<(), Singularity>>;

    /// The weighted second derivatives and the transposed Jacobian into `jac_adj1_f`'s
    /// outputs through `to`, as [`Model::compiled_jacobian`].
    ///
    /// # Safety
    /// As [`Model::second_of`].
    unsafe fn compiled_second(
        which: Which,
        prepared: &Self::Prepared,
        z: &Self::Array<f64>,
        weights: &[f64],
        parameters: bool,
        to: &Destinations,
    ) -> Option<Result<bool, Singularity>>;
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

/// The compiled code's columns (x, u, the parameters it reads, t) as indices into z.
pub fn local_columns<M: Model>() -> Vec<usize> {
    let s = Sizes::of::<M>();
    (0..s.p())
        .chain(M::READ.iter().map(|&i| s.p() + i))
        .chain([s.t()])
        .collect()
}
