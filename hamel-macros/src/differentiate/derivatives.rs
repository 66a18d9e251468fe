//! A function lowered onto a graph, and its derivatives built on the same graph: the
//! tangent, the gradient (or weighted adjoint), the Jacobian, the Hessian and the
//! bidirectional second derivative, with fresh inputs for their extra arguments.

use super::{UserArg, user_args};
use crate::engine::diff;
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::{Externals, ImplContext, Lowerer, Shape};

/// The function on the graph: its arguments and their inputs x, its result y.
pub struct Lowered {
    pub args: Vec<UserArg>,
    pub receiver: bool,
    pub output_shape: Shape,
    pub x: Vec<NodeId>,
    pub y: Vec<NodeId>,
    pub externals: Externals,
}

/// Lower `f` for differentiation; `None` for a helper, which gets no methods (integer or
/// geometry arguments, or a signature already reported).
pub fn lower(
    ctx: &ImplContext<'_>,
    graph: &mut Graph,
    f: &syn::ImplItemFn,
) -> syn::Result<Option<Lowered>> {
    let mut lowerer = Lowerer::new(graph, ctx);
    let Some(signature) = lowerer.signature(f) else {
        lowerer.take_errors()?;
        return Ok(None);
    };
    // A helper with integer arguments, or with values of the geometry vocabulary, is callable
    // and inlined, not differentiated itself: its derivative methods take flat arrays.
    let helper = |shape: &Shape| {
        let mut inner = shape;
        while let Shape::Array(_, next) = inner {
            inner = next;
        }
        matches!(inner, Shape::Int | Shape::Geo(_))
    };
    if signature.args.iter().any(|a| helper(&a.shape))
        || signature.output.as_ref().is_some_and(helper)
    {
        return Ok(None);
    }
    let Some(output_shape) = signature.output.clone() else {
        lowerer.take_errors()?;
        return Ok(None);
    };
    let args = user_args(&signature);
    let mut arg_values = Vec::new();
    let mut x = Vec::new();
    for arg in &args {
        if let Some((value, nodes)) = arg.shape.fresh_inputs(lowerer.graph, &arg.name.to_string()) {
            arg_values.push(value);
            x.extend(nodes);
        }
    }
    let result = lowerer.call(f, arg_values, &f.sig.ident);
    lowerer.take_errors()?;
    let externals = lowerer.externals.clone();
    let Some(y) = result.flatten() else {
        return Err(syn::Error::new_spanned(
            &f.sig.ident,
            format!(
                "`{}` must evaluate to `f64` or an array of `f64`",
                f.sig.ident
            ),
        ));
    };
    Ok(Some(Lowered {
        args,
        receiver: signature.receiver,
        output_shape,
        x,
        y,
        externals,
    }))
}

/// The derivatives of y(x), with the inputs of the derivative methods' extra arguments.
pub struct Derivatives {
    pub dir: Vec<NodeId>,
    pub dir_u: Vec<NodeId>,
    pub dir_v: Vec<NodeId>,
    /// The adjoint's weights: the constant 1 for a scalar result.
    pub weights: Vec<NodeId>,
    pub tangent: Vec<NodeId>,
    pub gradient: Vec<NodeId>,
    pub jacobian: Vec<Vec<NodeId>>,
    pub hessian: Vec<Vec<NodeId>>,
    pub second: Vec<NodeId>,
}

/// Every derivative of y(x), built in this order (the graph's node numbers, and so the
/// generated code, follow it).
pub fn derive(g: &mut Graph, x: &[NodeId], y: &[NodeId]) -> Derivatives {
    let fresh = |g: &mut Graph, name: &str, count: usize| -> Vec<NodeId> {
        (0..count)
            .map(|i| g.new_input(format!("{name}[{i}]")))
            .collect()
    };
    let dir = fresh(g, "dir", x.len());
    let dir_u = fresh(g, "dir_u", x.len());
    let dir_v = fresh(g, "dir_v", x.len());
    let weights: Vec<NodeId> = if y.len() == 1 {
        vec![g.one()]
    } else {
        fresh(g, "weights", y.len())
    };
    let seeds = |d: &[NodeId]| -> Vec<(NodeId, NodeId)> {
        x.iter().copied().zip(d.iter().copied()).collect()
    };
    let tangent = diff::tangent(g, y, &seeds(&dir));
    let gradient = diff::adjoint(g, y, &weights, x);
    let one = g.one();
    let jacobian: Vec<Vec<NodeId>> = y
        .iter()
        .map(|&yi| diff::adjoint(g, &[yi], &[one], x))
        .collect();
    let hessian = diff::hessian(g, y, &weights, x, x);
    let second = diff::bidirectional(g, y, &seeds(&dir_u), &seeds(&dir_v));
    Derivatives {
        dir,
        dir_u,
        dir_v,
        weights,
        tangent,
        gradient,
        jacobian,
        hessian,
        second,
    }
}
