//! `#[differentiate]`: derivative methods for every function of an impl block.
//!
//! The engine's direct interface. For each function `f(&self, x₁: T₁, …) -> R` whose
//! arguments are `f64` or arrays of `f64`, with the inputs flattened to x ∈ ℝᴺ (arguments in
//! order, arrays row-major) and the result to y ∈ ℝᴹ, it adds:
//!
//! | method | computes |
//! |---|---|
//! | `f_tangent(args, dir: &[f64; N]) -> [f64; M]` | F'(x)·dir |
//! | `f_gradient(args) -> [f64; N]` (M = 1) | ∇F(x) |
//! | `f_adjoint(args, weights: &[f64; M]) -> [f64; N]` (M > 1) | weightsᵀ·F'(x) |
//! | `f_jacobian(args) -> [[f64; N]; M]` | F'(x) |
//! | `f_hessian(args) -> [[f64; N]; N]` (M = 1; `weights` added for M > 1) | ∇²(wᵀF)(x) |
//! | `f_second(args, dir_u, dir_v: &[f64; N]) -> [f64; M]` | F''(x)[u, v] |
//! | `f_generic::<S: hamel::Scalar>(args over S) -> R over S` | F itself, over any scalar |
//! | `F_OPS: hamel::OpCounts` | operation counts of all of the above |
//!
//! Functions with integer arguments, or with values of the geometry vocabulary (`Vector3`,
//! `Rotation3`, ...) as arguments or result, are helpers: they can be called (and are
//! inlined) but get no derivative methods of their own.

use crate::engine::diff;
use crate::engine::emit::{Code, Emitter, Scalar};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::{ImplContext, Lowerer, Shape, Signature};
use crate::engine::ops;
use proc_macro2::{Literal, Span, TokenStream};
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::visit_mut::VisitMut;

pub fn expand(attr: TokenStream, item: TokenStream) -> TokenStream {
    let result = if attr.is_empty() {
        syn::parse2::<syn::ItemImpl>(item.clone()).and_then(|imp| expand_impl(&imp))
    } else {
        Err(syn::Error::new_spanned(
            attr,
            "`#[differentiate]` takes no arguments",
        ))
    };
    match result {
        Ok(tokens) => tokens,
        // Keep the user's code so that its own errors (and uses) still resolve.
        Err(e) => {
            let error = e.into_compile_error();
            quote!(#item #error)
        }
    }
}

fn expand_impl(imp: &syn::ItemImpl) -> syn::Result<TokenStream> {
    if let Some((path, _)) = &imp.trait_ {
        return Err(syn::Error::new_spanned(
            path,
            "`#[differentiate]` goes on an inherent impl block (`impl Model { .. }`), not a trait impl",
        ));
    }
    let ctx = ImplContext::new(&imp.items);
    let mut methods = Vec::new();
    let mut errors: Option<syn::Error> = None;
    for item in &imp.items {
        let syn::ImplItem::Fn(f) = item else { continue };
        match companions(&ctx, f) {
            Ok(tokens) => methods.push(tokens),
            Err(e) => match &mut errors {
                Some(all) => all.combine(e),
                None => errors = Some(e),
            },
        }
    }
    if let Some(e) = errors {
        return Err(e);
    }
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    let self_ty = &imp.self_ty;
    Ok(quote! {
        #imp
        impl #impl_generics #self_ty #where_clause {
            #(#methods)*
        }
    })
}

/// A generated method's argument: the user's argument, renamed if needed.
struct UserArg {
    name: syn::Ident,
    ty: syn::Type,
    shape: Shape,
}

/// Expression reading element `index` (row-major) of an argument.
fn element(arg: &UserArg, index: usize) -> TokenStream {
    let name = &arg.name;
    let mut path = Vec::new();
    let mut shape = &arg.shape;
    let mut rest = index;
    while let Shape::Array(_, inner) = shape {
        let stride = inner.len().max(1);
        path.push(rest / stride);
        rest %= stride;
        shape = inner;
    }
    let path: Vec<Literal> = path.into_iter().map(Literal::usize_unsuffixed).collect();
    if path.is_empty() {
        // A scalar, possibly behind references.
        let mut ty = &arg.ty;
        let mut derefs = 0;
        while let syn::Type::Reference(r) = ty {
            derefs += 1;
            ty = &r.elem;
        }
        let stars = (0..derefs).map(|_| quote!(*));
        quote!((#(#stars)* #name))
    } else {
        quote!(#name #([#path])*)
    }
}

/// Nested array expression of a shape from flat element expressions.
fn nest(shape: &Shape, flat: &mut impl Iterator<Item = TokenStream>) -> TokenStream {
    match shape {
        Shape::Array(n, inner) => {
            let items: Vec<TokenStream> = (0..*n).map(|_| nest(inner, flat)).collect();
            quote!([#(#items),*])
        }
        _ => flat
            .next()
            .unwrap_or_else(|| quote!(::core::compile_error!("hamel internal error: shape"))),
    }
}

/// Replace every `f64` in a type by the type parameter `S`.
struct ToGeneric(syn::Ident);

impl VisitMut for ToGeneric {
    fn visit_type_path_mut(&mut self, p: &mut syn::TypePath) {
        if p.qself.is_none() && p.path.is_ident("f64") {
            let s = &self.0;
            *p = syn::parse_quote!(#s);
        } else {
            syn::visit_mut::visit_type_path_mut(self, p);
        }
    }
}

fn companions(ctx: &ImplContext<'_>, f: &syn::ImplItemFn) -> syn::Result<TokenStream> {
    let mut graph = Graph::new();
    let mut lowerer = Lowerer::new(&mut graph, ctx);
    let Some(signature) = lowerer.signature(f) else {
        lowerer.take_errors()?;
        return Ok(TokenStream::new());
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
        return Ok(TokenStream::new());
    }
    let Some(output_shape) = signature.output.clone() else {
        lowerer.take_errors()?;
        return Ok(TokenStream::new());
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
    drop(lowerer);
    let y = match result.flatten() {
        Some(y) => y,
        None => {
            return Err(syn::Error::new_spanned(
                &f.sig.ident,
                format!(
                    "`{}` must evaluate to `f64` or an array of `f64`",
                    f.sig.ident
                ),
            ));
        }
    };
    let (n, m) = (
        Literal::usize_unsuffixed(x.len()),
        Literal::usize_unsuffixed(y.len()),
    );
    let (n_count, m_count) = (x.len(), y.len());

    // Fresh inputs for the extra arguments of the derivative methods.
    let fresh = |g: &mut Graph, name: &str, count: usize| -> Vec<NodeId> {
        (0..count)
            .map(|i| g.new_input(format!("{name}[{i}]")))
            .collect()
    };
    let g = &mut graph;
    let dir = fresh(g, "dir", n_count);
    let dir_u = fresh(g, "dir_u", n_count);
    let dir_v = fresh(g, "dir_v", n_count);
    let weights: Vec<NodeId> = if m_count == 1 {
        vec![g.one()]
    } else {
        fresh(g, "weights", m_count)
    };

    let seeds = |d: &[NodeId]| -> Vec<(NodeId, NodeId)> {
        x.iter().copied().zip(d.iter().copied()).collect()
    };
    let tangent = diff::tangent(g, &y, &seeds(&dir));
    let gradient = diff::adjoint(g, &y, &weights, &x);
    let one = g.one();
    let jacobian: Vec<Vec<NodeId>> = y
        .iter()
        .map(|&yi| diff::adjoint(g, &[yi], &[one], &x))
        .collect();
    let hessian = diff::hessian(g, &y, &weights, &x, &x);
    let second = diff::bidirectional(g, &y, &seeds(&dir_u), &seeds(&dir_v));

    let flat = |rows: &[Vec<NodeId>]| -> Vec<NodeId> { rows.iter().flatten().copied().collect() };
    let counts = [
        ops::count(&graph, &y).total(),
        ops::count(&graph, &tangent).total(),
        ops::count(&graph, &gradient).total(),
        ops::count(&graph, &flat(&jacobian)).total(),
        ops::count(&graph, &flat(&hessian)).total(),
        ops::count(&graph, &second).total(),
    ];

    // Bindings shared by every emitted method.
    let bind = |scalar: Scalar| -> Emitter<'_> {
        let generic = matches!(scalar, Scalar::Generic(_));
        let mut e = Emitter::new(&graph, scalar.clone());
        let mut k = 0;
        for arg in &args {
            for i in 0..arg.shape.len() {
                e.bind(x[k], element(arg, i));
                k += 1;
            }
        }
        for ext in &externals.items {
            let tokens = &ext.tokens;
            if let (true, Scalar::Generic(s)) = (generic, &scalar) {
                e.bind(ext.node, quote!(<#s as ::hamel::Scalar>::from_f64(#tokens)));
            } else {
                e.bind(ext.node, tokens.clone());
            }
        }
        for (name, nodes) in [("dir", &dir), ("dir_u", &dir_u), ("dir_v", &dir_v)] {
            let ident = format_ident!("{}", name);
            for (i, &node) in nodes.iter().enumerate() {
                let i = Literal::usize_unsuffixed(i);
                e.bind(node, quote!(#ident[#i]));
            }
        }
        if m_count > 1 {
            for (i, &node) in weights.iter().enumerate() {
                let i = Literal::usize_unsuffixed(i);
                e.bind(node, quote!(weights[#i]));
            }
        }
        e
    };
    let emitter = bind(Scalar::F64);
    let array = |code: &Code, nodes: &[NodeId]| -> TokenStream {
        let items = nodes.iter().map(|&id| code.value(id));
        quote!([#(#items),*])
    };
    let matrix = |code: &Code, rows: &[Vec<NodeId>]| -> TokenStream {
        let rows = rows.iter().map(|r| array(code, r));
        quote!([#(#rows),*])
    };

    let name = &f.sig.ident;
    let vis = &f.vis;
    let receiver = signature.receiver.then(|| quote!(&self,));
    let params: Vec<TokenStream> = args
        .iter()
        .map(|a| {
            let (id, ty) = (&a.name, &a.ty);
            quote!(#id: #ty)
        })
        .collect();
    let attrs = quote! {
        #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]
        #[inline]
    };
    let method = |suffix: &str,
                  doc: String,
                  extra: TokenStream,
                  ret: TokenStream,
                  body: syn::Result<(Code, TokenStream)>|
     -> syn::Result<TokenStream> {
        let (code, value) = body?;
        let stmts = &code.stmts;
        let ident = format_ident!("{}_{}", name, suffix);
        Ok(quote! {
            #[doc = #doc]
            #attrs
            #vis fn #ident(#receiver #(#params,)* #extra) -> #ret {
                #stmts
                #value
            }
        })
    };
    let emit_array = |nodes: &[NodeId]| -> syn::Result<(Code, TokenStream)> {
        let code = emitter.emit(nodes)?;
        let value = array(&code, nodes);
        Ok((code, value))
    };
    let emit_matrix = |rows: &[Vec<NodeId>]| -> syn::Result<(Code, TokenStream)> {
        let code = emitter.emit(&flat(rows))?;
        let value = matrix(&code, rows);
        Ok((code, value))
    };

    let of = format!("[`Self::{name}`]");
    let mut out = TokenStream::new();
    out.extend(method(
        "tangent",
        format!(
            "Directional derivative of {of}: F'(x)·dir. Generated by `#[hamel::differentiate]`."
        ),
        quote!(dir: &[f64; #n]),
        quote!([f64; #m]),
        emit_array(&tangent),
    )?);
    if m_count == 1 {
        out.extend(method(
            "gradient",
            format!("Gradient of {of} (reverse mode). Generated by `#[hamel::differentiate]`."),
            TokenStream::new(),
            quote!([f64; #n]),
            emit_array(&gradient),
        )?);
    } else {
        out.extend(method(
            "adjoint",
            format!("Weighted gradient of {of}: weightsᵀ·F'(x) (reverse mode). Generated by `#[hamel::differentiate]`."),
            quote!(weights: &[f64; #m]),
            quote!([f64; #n]),
            emit_array(&gradient),
        )?);
    }
    out.extend(method(
        "jacobian",
        format!("Jacobian of {of}, one row per output. Generated by `#[hamel::differentiate]`."),
        TokenStream::new(),
        quote!([[f64; #n]; #m]),
        emit_matrix(&jacobian),
    )?);
    let weights_param = (m_count > 1).then(|| quote!(weights: &[f64; #m]));
    out.extend(method(
        "hessian",
        format!("Hessian of {of} (of weightsᵀ·F for vector results), forward over reverse. Generated by `#[hamel::differentiate]`."),
        quote!(#weights_param),
        quote!([[f64; #n]; #n]),
        emit_matrix(&hessian),
    )?);
    out.extend(method(
        "second",
        format!("Bidirectional second derivative of {of}: F''(x)[dir_u, dir_v]. Generated by `#[hamel::differentiate]`."),
        quote!(dir_u: &[f64; #n], dir_v: &[f64; #n]),
        quote!([f64; #m]),
        emit_array(&second),
    )?);

    // The function itself over any `hamel::Scalar`.
    let s = syn::Ident::new("S", Span::call_site());
    let generic_emitter = bind(Scalar::Generic(s.clone()));
    let code = generic_emitter.emit(&y)?;
    let stmts = &code.stmts;
    let value = nest(&output_shape, &mut y.iter().map(|&id| code.value(id)));
    let mut to_generic = ToGeneric(s.clone());
    let generic_params: Vec<TokenStream> = args
        .iter()
        .map(|a| {
            let mut ty = a.ty.clone();
            to_generic.visit_type_mut(&mut ty);
            let id = &a.name;
            quote!(#id: #ty)
        })
        .collect();
    let mut ret = match &f.sig.output {
        syn::ReturnType::Type(_, ty) => (**ty).clone(),
        syn::ReturnType::Default => syn::parse_quote!(()),
    };
    to_generic.visit_type_mut(&mut ret);
    let generic_name = format_ident!("{}_generic", name);
    let generic_doc = format!(
        "{of} computed over any [`hamel::Scalar`] (e.g. dual numbers). Generated by `#[hamel::differentiate]`."
    );
    out.extend(quote! {
        #[doc = #generic_doc]
        #attrs
        #vis fn #generic_name<#s: ::hamel::Scalar>(#receiver #(#generic_params),*) -> #ret {
            #stmts
            #value
        }
    });

    let [
        function,
        tangent_ops,
        gradient_ops,
        jacobian_ops,
        hessian_ops,
        second_ops,
    ] = counts;
    let upper = format!("{}_OPS", name.unraw().to_string().to_uppercase());
    let Ok(mut ops_name) = syn::parse_str::<syn::Ident>(&upper) else {
        return Err(syn::Error::new_spanned(
            name,
            format!(
                "`{name}` has no upper-case form that is an identifier (`{upper}`), which names its operation counts"
            ),
        ));
    };
    ops_name.set_span(name.span());
    let ops_doc = format!("Operation counts of {of} and its generated derivatives.");
    out.extend(quote! {
        #[doc = #ops_doc]
        #vis const #ops_name: ::hamel::OpCounts = ::hamel::OpCounts {
            function: #function,
            tangent: #tangent_ops,
            gradient: #gradient_ops,
            jacobian: #jacobian_ops,
            hessian: #hessian_ops,
            second: #second_ops,
        };
    });
    Ok(out)
}

/// Names for the generated methods' copies of the user's arguments: the user's own name when
/// it is a plain identifier that cannot clash with generated names, else `arg{i}`.
fn user_args(signature: &Signature) -> Vec<UserArg> {
    let reserved = |s: &str| {
        matches!(s, "dir" | "dir_u" | "dir_v" | "weights" | "self")
            || (s.starts_with('v') && s.len() > 1 && s[1..].chars().all(|c| c.is_ascii_digit()))
    };
    signature
        .args
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let name = match &a.pat {
                syn::Pat::Ident(p) if p.subpat.is_none() && !reserved(&p.ident.to_string()) => {
                    p.ident.clone()
                }
                _ => format_ident!("arg{}", i),
            };
            UserArg {
                name,
                ty: a.ty.clone(),
                shape: a.shape.clone(),
            }
        })
        .collect()
}
