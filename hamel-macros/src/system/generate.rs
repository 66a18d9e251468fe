//! The generated code: `impl hamel::HamelSystem for Model` and the model's inherent items
//! (index constants, `rhs_generic`).

use super::equations::{Equations, TransformationPivots};
use super::interface::{self, Bodies, Dims, Header, lit};
use super::spec::Spec;
use crate::engine::emit::{Code, Emitter, Scalar};
use crate::engine::graph::{Graph, Node, NodeId};
use crate::engine::lower::External;
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote, quote_spanned};
use std::collections::BTreeMap;
use syn::ext::IdentExt;

/// Relative size below which a pivot of the mass matrix counts as zero, against the matrix's
/// scale: the sum of its diagonal entries' magnitudes, which for a positive definite matrix is
/// its trace and nuclear norm (the sum of its eigenvalues), between its largest eigenvalue and
/// n − p times it (an indefinite matrix's trace could be zero or negative, and let a zero pivot
/// pass). A pivot that small makes
/// the solve return what the rounding of the entries decides (a model whose inertia I·cos²θ
/// vanishes at θ = π/2 has the pivot 4e-34 there, from cos(π/2) = 6e-17 in floating point, and
/// the acceleration 1.6e16). A pivot is not compared with its own diagonal entry only: for a
/// speed that no other one couples to, they are equal, whatever their size. The scale costs
/// n − p − 1 additions in every right-hand side, and a NaN in it fails every check.
const PIVOT_TOLERANCE: f64 = 1e-13;

/// What a method reads: `x: &State` (coordinates then speeds) and `u`, or `q` alone, or `q`
/// and `qd`. Every method has `t`.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Source {
    State,
    Coordinates,
    Velocities,
}

/// Which checks must pass before a method's results are used: the pivots of the LU of A
/// (when B is computed from A), and those of the LDLᵀ of the mass matrix.
#[derive(Clone, Copy)]
pub(super) struct Checks {
    transformation: bool,
    mass: bool,
}

pub(super) const NONE: Checks = Checks {
    transformation: false,
    mass: false,
};
pub(super) const TRANSFORMATION: Checks = Checks {
    transformation: true,
    mass: false,
};
pub(super) const ALL: Checks = Checks {
    transformation: true,
    mass: true,
};

pub(super) struct Context<'g> {
    pub(super) graph: &'g Graph,
    pub(super) eq: &'g Equations,
    pub(super) externals: &'g [External],
    pub(super) n: usize,
}

impl<'g> Context<'g> {
    /// An emitter with every input bound for a method reading from `source`.
    fn emitter(&self, source: Source, scalar: Scalar) -> Emitter<'g> {
        let mut e = Emitter::new(self.graph, scalar.clone());
        let inputs = &self.eq.inputs;
        let wrap = |tokens: TokenStream| match &scalar {
            Scalar::F64 => tokens,
            Scalar::Generic(s) => quote!(<#s as ::hamel::Scalar>::from_f64(#tokens)),
        };
        for (i, &node) in inputs.q.iter().enumerate() {
            let i = lit(i);
            e.bind(
                node,
                match source {
                    Source::State => quote!(x[#i]),
                    Source::Coordinates | Source::Velocities => quote!(q[#i]),
                },
            );
        }
        if source == Source::State {
            for (k, &node) in inputs.w.iter().enumerate() {
                let i = lit(self.n + k);
                e.bind(node, quote!(x[#i]));
            }
            for (i, &node) in inputs.u.iter().enumerate() {
                let i = lit(i);
                e.bind(node, quote!(u[#i]));
            }
        }
        if source == Source::Velocities {
            for (i, &node) in inputs.v.iter().enumerate() {
                let i = lit(i);
                e.bind(node, quote!(qd[#i]));
            }
        }
        e.bind(inputs.t, quote!(t));
        for ext in self.externals {
            e.bind(ext.node, wrap(ext.tokens.clone()));
        }
        e
    }

    /// Code computing `roots`, then the checks asked for: a singular transformation or mass
    /// matrix returns an error before any result is used.
    pub(super) fn emit(
        &self,
        source: Source,
        scalar: Scalar,
        roots: &[NodeId],
        checks: Checks,
    ) -> syn::Result<(Code, TokenStream)> {
        self.emit_prepared(source, scalar, roots, checks, &[])
    }

    /// The roots and what their checks read.
    pub(super) fn checked_roots(&self, roots: &[NodeId], checks: Checks) -> Vec<NodeId> {
        let mut all = roots.to_vec();
        if let Some(t) = self.eq.transformation.as_ref() {
            if checks.transformation {
                all.extend(t.checks.iter().flat_map(|c| [c.value, c.scale]));
            }
        }
        if checks.mass {
            all.extend(&self.eq.pivots);
            all.extend(self.diagonal());
        }
        all
    }

    /// The mass matrix's diagonal entries, which its pivots are checked against.
    fn diagonal(&self) -> Vec<NodeId> {
        (0..self.eq.mass.len())
            .map(|k| self.eq.mass[k][k])
            .collect()
    }

    /// [`Self::emit`], reading the nodes of `prepared` from the array `prepared` instead of
    /// computing them.
    fn emit_prepared(
        &self,
        source: Source,
        scalar: Scalar,
        roots: &[NodeId],
        checks: Checks,
        prepared: &[NodeId],
    ) -> syn::Result<(Code, TokenStream)> {
        let bindings: Vec<(NodeId, TokenStream)> = prepared
            .iter()
            .enumerate()
            .map(|(i, &node)| {
                let i = lit(i);
                let read = match &scalar {
                    Scalar::F64 => quote!(prepared[#i]),
                    Scalar::Generic(s) => quote!(<#s as ::hamel::Scalar>::from_f64(prepared[#i])),
                };
                (node, read)
            })
            .collect();
        self.emit_bound(source, scalar, roots, checks, &bindings)
    }

    /// [`Self::emit`], reading the nodes of `bindings` as their tokens say (prepared values,
    /// parameters read from a slice) instead of computing them or reading them from `self`.
    pub(super) fn emit_bound(
        &self,
        source: Source,
        scalar: Scalar,
        roots: &[NodeId],
        checks: Checks,
        bindings: &[(NodeId, TokenStream)],
    ) -> syn::Result<(Code, TokenStream)> {
        let (mut stages, tokens) =
            self.emit_bound_stages(source, scalar, &[roots], checks, bindings)?;
        let code = stages
            .pop()
            .ok_or_else(|| syn::Error::new(Span::call_site(), "hamel internal error: no stage"))?;
        Ok((code, tokens))
    }

    /// [`Self::emit_bound`] in stages (`Emitter::emit_stages`): each later stage computes
    /// only what the earlier ones did not, and may be skipped at run time. The checks read
    /// the first stage's values.
    pub(super) fn emit_bound_stages(
        &self,
        source: Source,
        scalar: Scalar,
        stages: &[&[NodeId]],
        checks: Checks,
        bindings: &[(NodeId, TokenStream)],
    ) -> syn::Result<(Vec<Code>, TokenStream)> {
        let generic = matches!(scalar, Scalar::Generic(_));
        let mut emitter = self.emitter(source, scalar.clone());
        for (node, read) in bindings {
            emitter.bind(*node, read.clone());
        }
        let first = self.checked_roots(stages.first().copied().unwrap_or_default(), checks);
        let mut all: Vec<&[NodeId]> = vec![&first];
        all.extend(stages.iter().skip(1).copied());
        let transformation = self
            .eq
            .transformation
            .as_ref()
            .filter(|_| checks.transformation);
        let diagonal = self.diagonal();
        let codes = emitter.emit_stages(&all)?;
        let Some(code) = codes.first() else {
            return Err(syn::Error::new(
                Span::call_site(),
                "hamel internal error: no stage",
            ));
        };
        let re = |id: NodeId| {
            let v = code.value(id);
            if generic {
                quote!(::hamel::Scalar::re(#v))
            } else {
                quote!(f64::from(#v))
            }
        };
        let mut tokens = TokenStream::new();
        if let Some(t) = transformation {
            tokens.extend(self.transformation_checks(t, &re));
        }
        if checks.mass {
            tokens.extend(self.mass_checks(&diagonal, &re));
        }
        Ok((codes, tokens))
    }

    /// The checks of the LU pivots of A(q), `re` giving a node's value as an `f64`.
    fn transformation_checks(
        &self,
        t: &TransformationPivots,
        re: &dyn Fn(NodeId) -> TokenStream,
    ) -> TokenStream {
        let tolerance = (self.n as f64) * f64::EPSILON;
        // A NaN or infinite entry fails its pivot's test (NaN compares false, an infinite
        // scale is beyond every pivot): told apart there, off the hot path.
        let checks = t.checks.iter().map(|check| {
            let (v, scale) = (re(check.value), re(check.scale));
            let c = lit(check.coordinate);
            quote! {
                let pivot = #v;
                let scale = #scale;
                if !(pivot.abs() > #tolerance * scale) {
                    return ::core::result::Result::Err(if scale.is_finite() && pivot.is_finite() {
                        ::hamel::Singularity::Transformation { coordinate: #c, value: pivot }
                    } else {
                        ::hamel::Singularity::NonFinite { speed: ::core::option::Option::None }
                    });
                }
            }
        });
        quote! {
            #(#checks)*
        }
    }

    /// The checks of the mass matrix's LDLᵀ pivots against its scale, Σ|M_kk|
    /// (`PIVOT_TOLERANCE`): one comparison per pivot on the hot path; which pivot failed, and
    /// whether for a value that is not finite, an indefinite or a singular matrix, the runtime
    /// sorts out from all of them on the cold path.
    fn mass_checks(&self, diagonal: &[NodeId], re: &dyn Fn(NodeId) -> TokenStream) -> TokenStream {
        let tolerance = PIVOT_TOLERANCE;
        let diagonal: Vec<TokenStream> = diagonal.iter().map(|&m| re(m)).collect();
        let pivots: Vec<TokenStream> = self.eq.pivots.iter().map(|&d| re(d)).collect();
        let (ds, ps): (Vec<Ident>, Vec<Ident>) = (0..pivots.len())
            .map(|j| (format_ident!("diagonal{}", j), format_ident!("pivot{}", j)))
            .unzip();
        let checks = ps.iter().map(|p| {
            quote! {
                if !(#p > #tolerance * scale) {
                    return ::core::result::Result::Err(::hamel::Singularity::mass_pivots(&[#(#ps),*], &[#(#ds),*], #tolerance));
                }
            }
        });
        quote! {
            #(let #ds = #diagonal;)*
            #(let #ps = #pivots;)*
            let scale = #(f64::abs(#ds))+*;
            #(#checks)*
        }
    }

    /// An `f64` method body returning `Ok(value)` after the checks.
    pub(super) fn method(
        &self,
        source: Source,
        roots: &[NodeId],
        checks: Checks,
        shape: &dyn Fn(&Code) -> TokenStream,
    ) -> syn::Result<TokenStream> {
        let (code, checks) = self.emit(source, Scalar::F64, roots, checks)?;
        let stmts = &code.stmts;
        let value = shape(&code);
        Ok(quote! {
            #stmts
            #checks
            ::core::result::Result::Ok(#value)
        })
    }

    /// An `f64` method body returning an array of `nodes` (no checks: no solve involved).
    pub(super) fn plain(&self, source: Source, nodes: &[NodeId]) -> syn::Result<TokenStream> {
        let (code, _) = self.emit(source, Scalar::F64, nodes, NONE)?;
        let stmts = &code.stmts;
        let value = vector(&code, nodes);
        Ok(quote! {
            #stmts
            #value
        })
    }
}

pub(super) fn vector(code: &Code, nodes: &[NodeId]) -> TokenStream {
    let items = nodes.iter().map(|&id| code.value(id));
    quote!([#(#items),*])
}

/// What the bodies read from outside: the parameters and constants (graph inputs), and the
/// largest index read of each array parameter, with where it is written.
pub struct Read<'r> {
    pub externals: &'r [External],
    pub arrays: &'r BTreeMap<String, (usize, Span)>,
}

pub fn generate(
    spec: &Spec<'_>,
    (eq, control): (&Equations, Option<&super::control::ControlNodes>),
    exported: Option<&super::export::ExportNodes>,
    graph: &Graph,
    read: &Read<'_>,
    imp: &syn::ItemImpl,
) -> syn::Result<TokenStream> {
    let externals = read.externals;
    let (n, p, m, k) = (spec.dims.n, spec.dims.p, spec.dims.m, spec.dims.k);
    let dims = Dims { n, p, m, k };
    let cx = Context {
        graph,
        eq,
        externals,
        n,
    };
    let plain =
        |ids: &[syn::Ident]| -> Vec<String> { ids.iter().map(|i| i.unraw().to_string()).collect() };
    let constraints = constraint_names(spec);
    let header = Header {
        imp,
        dims,
        coordinates: plain(&spec.coordinates),
        speeds: plain(&spec.speeds),
        inputs: plain(&spec.inputs),
        constraints,
        dependent: spec.dependent(),
        conservative: eq.conservative,
        power_vanishes_without_inputs: eq.power_vanishes_without_inputs,
        reversible: eq.reversible,
        constant_determinant: constant_determinant(eq, graph),
        units: spec.units.clone(),
        check_bodies: check_bodies(spec),
        singular: spec
            .geometry
            .bodies
            .and_then(|_| super::orientations::singular(imp, &spec.coordinates)),
    };
    let (rhs_generic, prepared) = rhs_generic(&cx, dims)?;
    let outputs = control
        .and_then(|nodes| Some((nodes.outputs.as_slice(), nodes.lie.first()?.as_slice())))
        .unwrap_or((&[], &[]));
    let parametric = super::parametric::emit(&cx, dims, outputs, exported)?;
    let bodies = bodies(&cx, prepared)?;
    let consts = index_consts(spec);
    // A generic impl is of a generic parameter struct, an error of the struct's own: an array
    // pattern on an array of generic length would add rustc's.
    let bounds = if imp.generics.params.is_empty() {
        parameter_bounds(read.arrays)
    } else {
        TokenStream::new()
    };
    let system = interface::trait_impl(&header, &bodies);
    let control = match control {
        Some(nodes) => Some(super::control::emit::trait_impl(&cx, imp, nodes)?),
        None => None,
    };
    let notes = super::notes::notes(spec, &header.constraints);
    let mechanism = mechanism(spec, imp, &notes);
    let ty = &imp.self_ty;
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    Ok(quote! {
        #imp

        impl #impl_generics #ty #where_clause {
            #(#consts)*
            #rhs_generic
            #parametric
            #bounds
        }

        #system
        #control
        #mechanism
    })
}

/// The constraint rows' names: as `constraints(..)` gives them, or after the functions and the
/// rows' indices, as an indexed group is (`theta[3]` is `theta0`…): `blade0`, then
/// `wheel0_x`, `wheel0_y` (the contacts' rows kept), `rail0`, `wheel0_height`. Each is then
/// an identifier, and so is its force column in a CSV header (`lambda_blade0`).
fn constraint_names(spec: &Spec<'_>) -> Vec<String> {
    if let Some(names) = &spec.constraint_names {
        return names.iter().map(|i| i.unraw().to_string()).collect();
    }
    let row_names = |f: &syn::ImplItemFn, count: usize| -> Vec<String> {
        (0..count)
            .map(|i| super::equations::constraint_row(f, i))
            .collect()
    };
    let mut rows = spec
        .constraints
        .map(|f| row_names(f, spec.written_constraints()))
        .unwrap_or_default();
    let contacts = spec.geometry.contacts.as_ref();
    if let Some(c) = contacts {
        let name = c.f.sig.ident.unraw();
        let axis = |row: usize| ["x", "y"][row % 2];
        rows.extend(
            c.reading
                .kept
                .iter()
                .map(|&row| format!("{name}{}_{}", row / 2, axis(row))),
        );
    }
    if let Some(h) = &spec.holonomic {
        rows.extend(row_names(h.f, h.dependent.len()));
    }
    if let Some(c) = contacts {
        let name = c.f.sig.ident.unraw();
        rows.extend((0..c.dependent.len()).map(|i| format!("{name}{i}_height")));
    }
    rows
}

/// `HamelSystem::check_bodies` for a model stated from its bodies: the run-time check of
/// each body's mass, inertia, orientation and shape, on the model's own `#[bodies]`
/// function, and of its contacts' surfaces and points, on its `#[contacts]`.
fn check_bodies(spec: &Spec<'_>) -> Option<TokenStream> {
    let (f, _) = spec.geometry.bodies?;
    let call = |f: &syn::ImplItemFn| {
        let ident = &f.sig.ident;
        if spec.takes_time(f) {
            quote!(Self::#ident(self, t, q))
        } else {
            quote!(Self::#ident(self, q))
        }
    };
    let bodies = call(f);
    let names = &spec.body_names;
    let contacts = spec.geometry.contacts.as_ref().map(|c| {
        let contacts = call(c.f);
        quote!(::hamel::geometry::check_contacts(&#contacts, &bodies, names)?;)
    });
    Some(quote! {
        let bodies = #bodies;
        let names: &[&str] = &[#(#names),*];
        ::hamel::geometry::check_bodies(&bodies, names)?;
        #contacts
        ::core::result::Result::Ok(())
    })
}

/// `impl Mechanism` for a model stated from its bodies.
fn mechanism(spec: &Spec<'_>, imp: &syn::ItemImpl, notes: &[String]) -> Option<TokenStream> {
    let (bodies, _) = spec.geometry.bodies?;
    let call = |f| super::mechanism::Call {
        f,
        timed: spec.takes_time(f),
    };
    let roles = super::mechanism::Roles {
        bodies: call(bodies),
        contacts: spec.geometry.contacts.as_ref().map(|c| call(c.f)),
        gravity: spec.geometry.gravity.map(call),
    };
    Some(super::mechanism::mechanism_impl(
        imp,
        spec.dims.n,
        &spec.body_names,
        Some((&roles, notes)),
    ))
}

/// The right-hand side's values that depend on the parameters alone: every such node that
/// a node depending on (t, x, u) reads, or that is a result, and is an operation (not a
/// parameter read as it is). `prepare` computes them once per parameter set; the right-hand
/// side reads them.
fn prepared_nodes(cx: &Context<'_>, roots: &[NodeId]) -> Vec<NodeId> {
    parameter_only_nodes(cx.graph, &cx.eq.inputs.varying(), roots)
}

/// The values of `roots`' code that depend on none of `varying` and are worth computing once
/// per parameter set: those an operation that varies reads, and the roots that do not vary (a
/// Jacobian entry 1/r), except constants, inputs and conditions. The right-hand side's
/// preparation and the export's (`export::emit`) both take them.
pub(crate) fn parameter_only_nodes(g: &Graph, varying: &[NodeId], roots: &[NodeId]) -> Vec<NodeId> {
    let active = g.depends_on(varying);
    let live = g.live_set(roots);
    let mut wanted = vec![false; g.len()];
    for &r in roots {
        wanted[r.index()] = true;
    }
    for &id in &live {
        if active[id.index()] {
            for &o in g.node(id).operands().as_slice() {
                wanted[o.index()] = true;
            }
        }
    }
    live.into_iter()
        .filter(|&id| {
            let node = g.node(id);
            wanted[id.index()]
                && !active[id.index()]
                && !node.is_bool()
                && !matches!(node, Node::Const(_) | Node::Input(_))
        })
        .collect()
}

/// The right-hand side over any [`hamel::Scalar`], in three inherent methods: the
/// parameter-only values (`__hamel_prepare`), the right-hand side reading them
/// (`__hamel_rhs_prepared`, which `HamelSystem::rhs_prepared` calls with the values a
/// simulation prepared once), and `rhs_generic`, the two in one call.
fn rhs_generic(cx: &Context<'_>, dims: Dims) -> syn::Result<(TokenStream, usize)> {
    let eq = cx.eq;
    let s = Ident::new("S", Span::call_site());
    let roots: Vec<NodeId> = eq.qd.iter().chain(&eq.wdot).copied().collect();
    // The power shares q̇ (and the multipliers) with the right-hand side: prepared with it.
    let with_power: Vec<NodeId> = roots
        .iter()
        .copied()
        .chain((!eq.conservative).then_some(eq.power))
        .collect();
    let prepared = prepared_nodes(cx, &cx.checked_roots(&with_power, ALL));
    let count = lit(prepared.len());
    let (values, _) = cx.emit(Source::Coordinates, Scalar::F64, &prepared, NONE)?;
    let value_stmts = &values.stmts;
    let value_array = vector(&values, &prepared);
    let (code, checks) =
        cx.emit_prepared(Source::State, Scalar::Generic(s), &roots, ALL, &prepared)?;
    let stmts = &code.stmts;
    let writes = roots.iter().enumerate().map(|(i, &id)| {
        let v = code.value(id);
        let i = lit(i);
        quote!(dx[#i] = #v;)
    });
    let signature = interface::rhs_generic_signature(dims);
    let state = lit(2 * dims.n - dims.p);
    let m = lit(dims.m);
    let rhs_power = rhs_power_prepared(cx, &with_power, &prepared, dims)?;
    Ok((
        quote! {
            /// The right-hand side's values that depend on the parameters alone. Generated by
            /// `#[hamel_system]`.
            #[doc(hidden)]
            #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]
            #[inline]
            pub fn __hamel_prepare(&self) -> [f64; #count] {
                #value_stmts
                #value_array
            }

            /// The right-hand side with the parameter-only values of `__hamel_prepare`.
            /// Generated by `#[hamel_system]`.
            #[doc(hidden)]
            #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]
            #[inline]
            pub fn __hamel_rhs_prepared<S: ::hamel::Scalar>(
                &self,
                prepared: &[f64; #count],
                t: S,
                x: &[S; #state],
                u: &[S; #m],
                dx: &mut [S; #state],
            ) -> ::core::result::Result<(), ::hamel::Singularity> {
                #stmts
                #checks
                #(#writes)*
                ::core::result::Result::Ok(())
            }

            /// The right-hand side ẋ = F(t, x, u) over any [`hamel::Scalar`]: with dual numbers
            /// it yields the Jacobian of F (linearization); with `f64` it is exactly
            /// [`hamel::HamelSystem::rhs`]. Generated by `#[hamel_system]`.
            #[inline]
            #signature {
                self.__hamel_rhs_prepared(&self.__hamel_prepare(), t, x, u, dx)
            }

            #rhs_power
        },
        prepared.len(),
    ))
}

/// The right-hand side and the power in one pass (`__hamel_rhs_power_prepared`), for a
/// model that is not conservative: the power f·q̇ − λᵀa_c − ∂L/∂t reads the q̇ (and λ) the
/// right-hand side computes, where `power` alone computes them again. Nothing for a
/// conservative model, whose power is zero.
fn rhs_power_prepared(
    cx: &Context<'_>,
    roots: &[NodeId],
    prepared: &[NodeId],
    dims: Dims,
) -> syn::Result<TokenStream> {
    let eq = cx.eq;
    if eq.conservative {
        return Ok(TokenStream::new());
    }
    let (code, checks) = cx.emit_prepared(Source::State, Scalar::F64, roots, ALL, prepared)?;
    let stmts = &code.stmts;
    let writes = roots[..roots.len() - 1].iter().enumerate().map(|(i, &id)| {
        let v = code.value(id);
        let i = lit(i);
        quote!(dx[#i] = #v;)
    });
    let power = code.value(eq.power);
    let (count, state, m) = (lit(prepared.len()), lit(2 * dims.n - dims.p), lit(dims.m));
    Ok(quote! {
        /// The right-hand side with the parameter-only values of `__hamel_prepare`, and the
        /// power. Generated by `#[hamel_system]`.
        #[doc(hidden)]
        #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]
        #[inline]
        pub fn __hamel_rhs_power_prepared(
            &self,
            prepared: &[f64; #count],
            t: f64,
            x: &[f64; #state],
            u: &[f64; #m],
            dx: &mut [f64; #state],
        ) -> ::core::result::Result<f64, ::hamel::Singularity> {
            #stmts
            #checks
            #(#writes)*
            ::core::result::Result::Ok(#power)
        }
    })
}

/// Whether det A(q, t) depends on the parameters alone, so that no motion can cross a
/// configuration where A is singular: B is derived from A (not given) and no pivot or block
/// determinant checked before it is used varies with t or q (a constant one is not checked).
fn constant_determinant(eq: &Equations, graph: &Graph) -> bool {
    let time_and_configuration: Vec<NodeId> = std::iter::once(eq.inputs.t)
        .chain(eq.inputs.q.iter().copied())
        .collect();
    let active = graph.depends_on(&time_and_configuration);
    eq.inverse_defect.is_none()
        && eq
            .transformation
            .as_ref()
            .is_none_or(|pivots| pivots.checks.iter().all(|c| !active[c.value.index()]))
}

/// The body of every method of the trait; `prepared` values are prepared for the
/// right-hand side.
fn bodies(cx: &Context<'_>, prepared: usize) -> syn::Result<Bodies> {
    let eq = cx.eq;
    let mass_flat: Vec<NodeId> = eq.mass.iter().flatten().copied().collect();
    let gamma_flat: Vec<NodeId> = eq.gamma.iter().flatten().flatten().copied().collect();
    let power = if eq.conservative {
        quote!(::core::result::Result::Ok(0.0))
    } else {
        cx.method(Source::State, &[eq.power], ALL, &|c| c.value(eq.power))?
    };
    let (residual, jacobian) = match &eq.holonomic {
        Some(h) => (
            cx.plain(Source::Coordinates, &h.residual)?,
            cx.plain(Source::Coordinates, &h.jacobian)?,
        ),
        None => (quote!([]), quote!([])),
    };
    // max |A·B − I| for a user-given inverse; zero when B is computed from A.
    let inverse_defect = match &eq.inverse_defect {
        Some(defect) => cx.method(Source::Coordinates, defect, NONE, &|c| {
            let terms = defect.iter().map(|&id| {
                let v = c.value(id);
                quote!(.max(f64::abs(#v)))
            });
            quote!(0.0f64 #(#terms)*)
        })?,
        // B is computed from A: nothing to check (a singular A(q) is the dynamics' business,
        // reported by the right-hand side at the time it is met).
        None => quote!(::core::result::Result::Ok(0.0)),
    };
    let count = lit(prepared);
    Ok(Bodies {
        rhs: quote!(self.rhs_generic::<f64>(t, x, u, dx)),
        prepared_len: prepared,
        prepare: quote! {
            if let ::core::result::Result::Ok(out) = <&mut [f64; #count]>::try_from(prepared) {
                *out = self.__hamel_prepare();
            }
        },
        rhs_prepared: quote! {
            match <&[f64; #count]>::try_from(prepared) {
                ::core::result::Result::Ok(prepared) => self.__hamel_rhs_prepared::<f64>(prepared, t, x, u, dx),
                ::core::result::Result::Err(_) => self.rhs_generic::<f64>(t, x, u, dx),
            }
        },
        rhs_power_prepared: rhs_power_prepared_body(eq.conservative, prepared),
        generalized_velocities: cx.method(Source::State, &eq.qd, TRANSFORMATION, &|c| {
            vector(c, &eq.qd)
        })?,
        energy: cx.method(Source::State, &[eq.energy], TRANSFORMATION, &|c| {
            c.value(eq.energy)
        })?,
        power,
        constraint_forces: cx.method(Source::State, &eq.multipliers, ALL, &|c| {
            vector(c, &eq.multipliers)
        })?,
        constraint_residual: cx.plain(Source::Velocities, &eq.constraint_rows)?,
        speeds: cx.plain(Source::Velocities, &eq.quasi_rows)?,
        holonomic_residual: residual,
        holonomic_jacobian: jacobian,
        mass_matrix: cx.method(Source::State, &mass_flat, TRANSFORMATION, &|c| {
            let rows = eq.mass.iter().map(|r| vector(c, r));
            quote!([#(#rows),*])
        })?,
        gamma: cx.method(Source::Coordinates, &gamma_flat, TRANSFORMATION, &|c| {
            let planes = eq.gamma.iter().map(|plane| {
                let rows = plane.iter().map(|r| vector(c, r));
                quote!([#(#rows),*])
            });
            quote!([#(#planes),*])
        })?,
        inverse_defect,
        jacobian: dual_jacobian(cx),
        time_derivative: dual_time_derivative(cx),
    })
}

/// `rhs_power_prepared`: the right-hand side and, for a model that is not conservative, the
/// power, in one pass with the values `prepare` computes. Only inherent methods are called
/// here: a call through the trait would add an error of its own where the parameter struct
/// lacks `#[hamel_system]`.
fn rhs_power_prepared_body(conservative: bool, prepared: usize) -> TokenStream {
    let count = lit(prepared);
    if conservative {
        quote! {
            match <&[f64; #count]>::try_from(prepared) {
                ::core::result::Result::Ok(prepared) => self.__hamel_rhs_prepared::<f64>(prepared, t, x, u, dx)?,
                ::core::result::Result::Err(_) => self.rhs_generic::<f64>(t, x, u, dx)?,
            }
            ::core::result::Result::Ok(0.0)
        }
    } else {
        quote! {
            match <&[f64; #count]>::try_from(prepared) {
                ::core::result::Result::Ok(prepared) => self.__hamel_rhs_power_prepared(prepared, t, x, u, dx),
                ::core::result::Result::Err(_) => self.__hamel_rhs_power_prepared(&self.__hamel_prepare(), t, x, u, dx),
            }
        }
    }
}

/// The entries of array parameters the bodies read must exist. The struct is not in view of
/// this macro, so the check is left to rustc, in a form it makes in `cargo check` already (an
/// out-of-range constant index is only a lint of code generation): an array pattern that
/// needs as many entries, written at the largest index read, so that rustc's error
/// ("pattern requires at least 3 elements but array has 2") points at it.
fn parameter_bounds(arrays: &BTreeMap<String, (usize, Span)>) -> TokenStream {
    if arrays.is_empty() {
        return TokenStream::new();
    }
    let checks = arrays.iter().map(|(field, &(largest, span))| {
        let field = Ident::new(field, span);
        let wildcards = (0..=largest).map(|_| quote_spanned!(span=> _,));
        quote_spanned!(span=> let [#(#wildcards)* ..] = self.#field;)
    });
    quote! {
        #[doc(hidden)]
        #[allow(dead_code, clippy::all)]
        fn __hamel_parameter_bounds(&self) {
            #(#checks)*
        }
    }
}

/// Dual numbers through the generic right-hand side, one pass per state or input component
/// that the right-hand side depends on at all (the others' columns are exactly zero: found
/// on the graph, the inputs the results are computed from).
fn dual_jacobian(cx: &Context<'_>) -> TokenStream {
    let eq = cx.eq;
    let mut roots: Vec<NodeId> = eq.qd.iter().chain(&eq.wdot).copied().collect();
    if let Some(t) = &eq.transformation {
        roots.extend(t.checks.iter().map(|c| c.value));
    }
    let live: crate::engine::hash::HashSet<NodeId> =
        cx.graph.live_set(&roots).into_iter().collect();
    let inputs = &eq.inputs;
    let directions = inputs
        .q
        .iter()
        .chain(&inputs.w)
        .chain(&inputs.u)
        .enumerate()
        .filter(|(_, node)| live.contains(node))
        .map(|(i, _)| lit(i));
    quote! {
        ::hamel::jacobian_by_duals(t, x, u, &[#(#directions),*], |t, x, u, dx| self.rhs_generic(t, x, u, dx))
    }
}

/// ∂F/∂t: one pass of dual numbers with t seeded, or zeros without a pass when the right-hand
/// side does not depend on t (found on the graph, as the Jacobian's directions are).
fn dual_time_derivative(cx: &Context<'_>) -> TokenStream {
    let eq = cx.eq;
    let mut roots: Vec<NodeId> = eq.qd.iter().chain(&eq.wdot).copied().collect();
    if let Some(t) = &eq.transformation {
        roots.extend(t.checks.iter().map(|c| c.value));
    }
    if cx.graph.live_set(&roots).contains(&eq.inputs.t) {
        quote! {
            ::hamel::time_derivative_by_duals(t, x, u, |t, x, u, dx| self.rhs_generic(t, x, u, dx))
                .map(::core::option::Option::Some)
        }
    } else {
        quote! {
            let _ = (t, x, u);
            ::core::result::Result::Ok(::core::option::Option::Some(::core::array::from_fn(|_| 0.0)))
        }
    }
}

/// Index constants: `Model::ALPHA` is the index of `alpha` in q; an indexed group `theta[3]`
/// also gives `Model::THETA`, the index of its first member. Named constraints have them
/// too: `Model::BLADE` is the index of `blade` among the constraint rows.
fn index_consts(spec: &Spec<'_>) -> Vec<TokenStream> {
    let none = Vec::new();
    let lists = [
        (&spec.coordinates, "coordinates"),
        (&spec.speeds, "speeds"),
        (&spec.inputs, "inputs"),
        (
            spec.constraint_names.as_ref().unwrap_or(&none),
            "constraints",
        ),
    ];
    let mut out = Vec::new();
    for ((idents, what), groups) in lists.into_iter().zip(&spec.groups) {
        // (`spec` has checked that every name upper-cases to an identifier.)
        for (i, id) in idents.iter().enumerate() {
            let upper = id.unraw().to_string().to_uppercase();
            let Ok(mut name) = syn::parse_str::<syn::Ident>(&upper) else {
                continue;
            };
            name.set_span(id.span());
            let doc = format!("Index of `{id}` among the {what}.");
            let i = lit(i);
            out.push(quote!(#[doc = #doc] pub const #name: usize = #i;));
        }
        for group in groups {
            let upper = group.base.unraw().to_string().to_uppercase();
            let Ok(mut name) = syn::parse_str::<syn::Ident>(&upper) else {
                continue;
            };
            name.set_span(group.base.span());
            let doc = format!(
                "Index among the {what} of `{base}0`, the first of the group `{base}[{}]`.",
                group.len,
                base = group.base
            );
            let i = lit(group.start);
            out.push(quote!(#[doc = #doc] pub const #name: usize = #i;));
        }
    }
    out
}
