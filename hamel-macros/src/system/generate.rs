//! The generated code: `impl hamel::HamelSystem for Model` and the model's inherent items
//! (index constants, `rhs_generic`).

use super::equations::Equations;
use super::spec::Spec;
use crate::engine::emit::{Code, Emitter, Scalar};
use crate::engine::graph::{Graph, NodeId};
use crate::engine::lower::External;
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;
use syn::ext::IdentExt;

/// Relative size below which a pivot of the mass matrix counts as zero. For a positive
/// definite matrix 0 < D_j ≤ M_jj: the ratio is the share of the inertia along speed j that
/// the coupling to the speeds before it leaves, so each pivot is compared with its own
/// diagonal entry (which is also cheaper than finding the matrix's largest entry: these
/// checks run in every right-hand side).
const PIVOT_TOLERANCE: f64 = 1e-13;

fn lit(i: usize) -> Literal {
    Literal::usize_unsuffixed(i)
}

/// Where a method reads its inputs from.
#[derive(Clone, Copy, PartialEq)]
enum Source {
    /// `x: &State` (coordinates then speeds).
    State,
    /// `q: &Coordinates` only.
    Coordinates,
}

struct Context<'g> {
    graph: &'g Graph,
    eq: &'g Equations,
    externals: &'g [External],
    n: usize,
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
                if source == Source::State {
                    quote!(x[#i])
                } else {
                    quote!(q[#i])
                },
            );
        }
        for (k, &node) in inputs.w.iter().enumerate() {
            let i = lit(self.n + k);
            e.bind(node, quote!(x[#i]));
        }
        for (i, &node) in inputs.u.iter().enumerate() {
            let i = lit(i);
            e.bind(node, quote!(u[#i]));
        }
        e.bind(inputs.t, quote!(t));
        for ext in self.externals {
            e.bind(ext.node, wrap(ext.tokens.clone()));
        }
        e
    }

    /// Code computing `roots`, then, when B comes from a run-time LU of A(q), the checks of
    /// its pivots: a singular transformation returns an error before any result is used.
    fn emit(
        &self,
        source: Source,
        scalar: Scalar,
        roots: &[NodeId],
    ) -> syn::Result<(Code, TokenStream)> {
        let generic = matches!(scalar, Scalar::Generic(_));
        let emitter = self.emitter(source, scalar);
        let Some(t) = &self.eq.transformation else {
            return Ok((emitter.emit(roots)?, TokenStream::new()));
        };
        let mut all = roots.to_vec();
        all.extend(t.pivots.iter().map(|(p, _)| *p));
        all.extend(&t.entries);
        let code = emitter.emit(&all)?;
        let re = |id: NodeId| {
            let v = code.value(id);
            if generic {
                quote!(::hamel::Scalar::re(#v))
            } else {
                quote!(f64::from(#v))
            }
        };
        // The matrix's scale as a sum of magnitudes: a plain sum, where a NaN-aware `max`
        // chain would cost more than the factorization it guards.
        let scale = t.entries.iter().map(|&e| {
            let v = re(e);
            quote!(+ #v.abs())
        });
        let tolerance = (self.n as f64) * f64::EPSILON;
        let checks = t.pivots.iter().map(|&(p, coordinate)| {
            let v = re(p);
            let c = lit(coordinate);
            quote! {
                let pivot = #v;
                if !(pivot.abs() > #tolerance * scale_a) {
                    return ::core::result::Result::Err(::hamel::Singularity::Transformation { coordinate: #c, value: pivot });
                }
            }
        });
        let checks = quote! {
            let scale_a = 0.0f64 #(#scale)*;
            #(#checks)*
        };
        Ok((code, checks))
    }
}

pub fn generate(
    spec: &Spec<'_>,
    eq: &Equations,
    graph: &Graph,
    externals: &[External],
    imp: &syn::ItemImpl,
) -> syn::Result<TokenStream> {
    let (n, p, m) = (spec.dims.n, spec.dims.p, spec.dims.m);
    let free = spec.dims.free();
    let state = n + free;
    let cx = Context {
        graph,
        eq,
        externals,
        n,
    };
    let ty = &imp.self_ty;
    let (impl_generics, _, where_clause) = imp.generics.split_for_impl();
    let (n_l, p_l, m_l, free_l, state_l) = (lit(n), lit(p), lit(m), lit(free), lit(state));

    // Names.
    let plain =
        |ids: &[syn::Ident]| -> Vec<String> { ids.iter().map(|i| i.unraw().to_string()).collect() };
    let coordinate_names = plain(&spec.coordinates);
    let speed_names = plain(&spec.speeds);
    let input_names = plain(&spec.inputs);
    let state_names: Vec<&String> = coordinate_names.iter().chain(&speed_names).collect();
    let constraint_fn = &spec.constraints.sig.ident;
    let constraint_names: Vec<String> = (0..p)
        .map(|i| format!("{}[{i}]", constraint_fn.unraw()))
        .collect();

    // rhs, generic over the scalar type.
    let s = Ident::new("S", Span::call_site());
    let mut roots: Vec<NodeId> = eq.qd.clone();
    roots.extend(&eq.wdot);
    roots.extend(&eq.pivots);
    let diagonal: Vec<NodeId> = (0..free).map(|k| eq.mass[k][k]).collect();
    roots.extend(&diagonal);
    let (code, transformation_checks) =
        cx.emit(Source::State, Scalar::Generic(s.clone()), &roots)?;
    let stmts = &code.stmts;
    let re = |id: NodeId| {
        let v = code.value(id);
        quote!(::hamel::Scalar::re(#v))
    };
    let tolerance = PIVOT_TOLERANCE;
    let checks = eq.pivots.iter().zip(&diagonal).enumerate().map(|(j, (&d, &m))| {
        let (v, diag) = (re(d), re(m));
        let j = lit(j);
        quote! {
            let pivot = #v;
            if !(pivot > #tolerance * #diag.abs()) {
                return ::core::result::Result::Err(::hamel::Singularity::MassMatrix { speed: #j, value: pivot });
            }
        }
    });
    let writes = eq.qd.iter().chain(&eq.wdot).enumerate().map(|(i, &id)| {
        let v = code.value(id);
        let i = lit(i);
        quote!(dx[#i] = #v;)
    });
    let rhs_generic = quote! {
        /// The right-hand side ẋ = F(t, x, u) over any [`hamel::Scalar`]: with dual numbers
        /// it yields the Jacobian of F (linearization); with `f64` it is exactly
        /// [`hamel::HamelSystem::rhs`]. Generated by `#[hamel_system]`.
        #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]
        #[inline]
        pub fn rhs_generic<#s: ::hamel::Scalar>(
            &self,
            t: #s,
            x: &[#s; #state_l],
            u: &[#s; #m_l],
            dx: &mut [#s; #state_l],
        ) -> ::core::result::Result<(), ::hamel::Singularity> {
            #stmts
            #transformation_checks
            #(#checks)*
            #(#writes)*
            ::core::result::Result::Ok(())
        }
    };

    // The f64 inspection methods.
    let method = |source: Source,
                  roots: &[NodeId],
                  shape: &dyn Fn(&Code) -> TokenStream|
     -> syn::Result<TokenStream> {
        let (code, checks) = cx.emit(source, Scalar::F64, roots)?;
        let stmts = &code.stmts;
        let value = shape(&code);
        Ok(quote! {
            #stmts
            #checks
            ::core::result::Result::Ok(#value)
        })
    };
    let vector = |code: &Code, nodes: &[NodeId]| {
        let items = nodes.iter().map(|&id| code.value(id));
        quote!([#(#items),*])
    };
    let velocities_body = method(Source::State, &eq.qd, &|c| vector(c, &eq.qd))?;
    let energy_body = method(Source::State, &[eq.energy], &|c| c.value(eq.energy))?;
    let mass_flat: Vec<NodeId> = eq.mass.iter().flatten().copied().collect();
    let mass_body = method(Source::State, &mass_flat, &|c| {
        let rows = eq.mass.iter().map(|r| vector(c, r));
        quote!([#(#rows),*])
    })?;
    let gamma_flat: Vec<NodeId> = eq.gamma.iter().flatten().flatten().copied().collect();
    let gamma_body = method(Source::Coordinates, &gamma_flat, &|c| {
        let planes = eq.gamma.iter().map(|plane| {
            let rows = plane.iter().map(|r| vector(c, r));
            quote!([#(#rows),*])
        });
        quote!([#(#planes),*])
    })?;

    // max |A(q)·B(q) − I| for a user-given inverse; zero when B is computed from A.
    let defect_body = match &eq.inverse_defect {
        Some(defect) => method(Source::Coordinates, defect, &|c| {
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

    // The user's own row functions answer constraint_residual and speeds.
    let call = |f: &syn::ImplItemFn| {
        let name = &f.sig.ident;
        let args = f.sig.inputs.iter().filter_map(|a| match a {
            syn::FnArg::Typed(pt) => Some(matches!(*pt.ty, syn::Type::Reference(_))),
            syn::FnArg::Receiver(_) => None,
        });
        let passed = args
            .zip([quote!(q), quote!(qd)])
            .map(|(by_ref, name)| if by_ref { name } else { quote!(*#name) });
        let receiver = if f.sig.receiver().is_some() {
            quote!(self.)
        } else {
            quote!(Self::)
        };
        quote!(#receiver #name(#(#passed),*))
    };
    let constraint_call = call(spec.constraints);
    let speeds_call = call(spec.quasi_velocities);

    // Index constants: `Model::ALPHA` is the index of `alpha` in q.
    let index_consts = |idents: &[syn::Ident], what: &str| -> Vec<TokenStream> {
        // (`spec` has checked that every name upper-cases to an identifier.)
        idents
            .iter()
            .enumerate()
            .filter_map(|(i, id)| {
                let upper = id.unraw().to_string().to_uppercase();
                let mut name = syn::parse_str::<syn::Ident>(&upper).ok()?;
                name.set_span(id.span());
                let doc = format!("Index of `{id}` among the {what}.");
                let i = lit(i);
                Some(quote!(#[doc = #doc] pub const #name: usize = #i;))
            })
            .collect()
    };
    let coordinate_consts = index_consts(&spec.coordinates, "coordinates");
    let speed_consts = index_consts(&spec.speeds, "speeds");
    let input_consts = index_consts(&spec.inputs, "inputs");

    let allow = quote!(#[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)]);
    Ok(quote! {
        #imp

        impl #impl_generics #ty #where_clause {
            #(#coordinate_consts)*
            #(#speed_consts)*
            #(#input_consts)*
            #rhs_generic
        }

        impl #impl_generics ::hamel::HamelSystem for #ty #where_clause {
            type Coordinates = [f64; #n_l];
            type Speeds = [f64; #free_l];
            type Constraints = [f64; #p_l];
            type State = [f64; #state_l];
            type Inputs = [f64; #m_l];
            type MassMatrix = [[f64; #free_l]; #free_l];
            type Gamma = [[[f64; #free_l]; #free_l]; #n_l];

            const N: usize = #n_l;
            const P: usize = #p_l;
            const M: usize = #m_l;
            const COORDINATES: &'static [&'static str] = &[#(#coordinate_names),*];
            const SPEEDS: &'static [&'static str] = &[#(#speed_names),*];
            const CONSTRAINTS: &'static [&'static str] = &[#(#constraint_names),*];
            const INPUTS: &'static [&'static str] = &[#(#input_names),*];
            const STATE: &'static [&'static str] = &[#(#state_names),*];

            #[inline]
            fn rhs(
                &self,
                t: f64,
                x: &[f64; #state_l],
                u: &[f64; #m_l],
                dx: &mut [f64; #state_l],
            ) -> ::core::result::Result<(), ::hamel::Singularity> {
                self.rhs_generic::<f64>(t, x, u, dx)
            }

            #allow
            fn velocities(&self, x: &[f64; #state_l]) -> ::core::result::Result<[f64; #n_l], ::hamel::Singularity> {
                #velocities_body
            }

            #allow
            fn energy(&self, x: &[f64; #state_l]) -> ::core::result::Result<f64, ::hamel::Singularity> {
                #energy_body
            }

            fn constraint_residual(&self, q: &[f64; #n_l], qd: &[f64; #n_l]) -> [f64; #p_l] {
                #constraint_call
            }

            fn speeds(&self, q: &[f64; #n_l], qd: &[f64; #n_l]) -> [f64; #free_l] {
                #speeds_call
            }

            #allow
            fn mass_matrix(&self, x: &[f64; #state_l]) -> ::core::result::Result<[[f64; #free_l]; #free_l], ::hamel::Singularity> {
                #mass_body
            }

            #allow
            fn inverse_defect(&self, q: &[f64; #n_l]) -> ::core::result::Result<f64, ::hamel::Singularity> {
                #defect_body
            }

            #allow
            fn gamma(&self, q: &[f64; #n_l]) -> ::core::result::Result<[[[f64; #free_l]; #free_l]; #n_l], ::hamel::Singularity> {
                #gamma_body
            }
        }
    })
}
