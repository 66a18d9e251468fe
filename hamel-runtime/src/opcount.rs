//! Operation counts of generated derivative code, as the macro measured them.

/// How many arithmetic operations and elementary-function calls the code generated for one
/// function performs: the function itself and each of its derivatives. Each count includes
/// the evaluation of the function that the derivative code needs. The cheap-gradient
/// principle says `gradient` and `tangent` stay within a small multiple of `function`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OpCounts {
    pub function: usize,
    /// One directional derivative F'(x)·d.
    pub tangent: usize,
    /// The gradient (scalar functions) or one weighted gradient wᵀF'(x).
    pub gradient: usize,
    /// The full Jacobian.
    pub jacobian: usize,
    /// The full Hessian (of wᵀF for vector functions).
    pub hessian: usize,
    /// One bidirectional second derivative F''(x)[u, v].
    pub second: usize,
}
