//! `impl hamel::HamelSystem for Model`: the associated types, constants and method
//! signatures, written once for the generated model (`generate`) and for the stand-in that
//! a model with mistakes gets (`fallback`), which differ only in the method bodies.

use proc_macro2::{Literal, TokenStream};
use quote::quote;

/// n, p, m, k: coordinates, constraint rows (holonomic ones included), inputs, holonomic
/// constraints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dims {
    pub n: usize,
    pub p: usize,
    pub m: usize,
    pub k: usize,
}

/// Everything of the implementation but the method bodies.
pub struct Header<'a> {
    pub imp: &'a syn::ItemImpl,
    pub dims: Dims,
    pub coordinates: Vec<String>,
    pub speeds: Vec<String>,
    pub inputs: Vec<String>,
    pub constraints: Vec<String>,
    pub dependent: Vec<usize>,
    pub conservative: bool,
    pub power_vanishes_without_inputs: bool,
    pub reversible: bool,
    /// det A(q, t) depends on the parameters alone (`TRANSFORMATION_DETERMINANT_CONSTANT`).
    pub constant_determinant: bool,
    /// `units(..)`: a quantity's name and its unit (`UNITS`, emitted when there are any).
    pub units: Vec<(String, String)>,
    /// `check_bodies`'s body, for a model with `#[bodies]` (the default checks nothing).
    pub check_bodies: Option<TokenStream>,
    /// `singular`'s body, for a model oriented by three turns (the default names the
    /// singularity alone).
    pub singular: Option<TokenStream>,
}

/// The body of each method (a block's contents).
pub struct Bodies {
    pub rhs: TokenStream,
    /// How many parameter-only values `prepare` computes for `rhs_prepared`.
    pub prepared_len: usize,
    pub prepare: TokenStream,
    pub rhs_prepared: TokenStream,
    pub rhs_power_prepared: TokenStream,
    pub generalized_velocities: TokenStream,
    pub energy: TokenStream,
    pub power: TokenStream,
    pub constraint_forces: TokenStream,
    pub constraint_residual: TokenStream,
    pub speeds: TokenStream,
    pub holonomic_residual: TokenStream,
    pub holonomic_jacobian: TokenStream,
    pub mass_matrix: TokenStream,
    pub gamma: TokenStream,
    pub inverse_defect: TokenStream,
    pub jacobian: TokenStream,
    pub time_derivative: TokenStream,
}

impl Bodies {
    /// Every body `unreachable!()`: for a model whose errors keep the crate from building.
    pub fn unreachable() -> Bodies {
        let never = quote!(::core::unreachable!(
            "hamel: the model has errors, reported at build time"
        ));
        Bodies {
            rhs: never.clone(),
            prepared_len: 0,
            prepare: never.clone(),
            rhs_prepared: never.clone(),
            rhs_power_prepared: never.clone(),
            generalized_velocities: never.clone(),
            energy: never.clone(),
            power: never.clone(),
            constraint_forces: never.clone(),
            constraint_residual: never.clone(),
            speeds: never.clone(),
            holonomic_residual: never.clone(),
            holonomic_jacobian: never.clone(),
            mass_matrix: never.clone(),
            gamma: never.clone(),
            inverse_defect: never.clone(),
            jacobian: never.clone(),
            time_derivative: never,
        }
    }
}

pub fn lit(i: usize) -> Literal {
    Literal::usize_unsuffixed(i)
}

/// The signature of the inherent `rhs_generic` (its body follows).
pub fn rhs_generic_signature(dims: Dims) -> TokenStream {
    let (state, m) = (lit(2 * dims.n - dims.p), lit(dims.m));
    quote! {
        pub fn rhs_generic<S: ::hamel::Scalar>(
            &self,
            t: S,
            x: &[S; #state],
            u: &[S; #m],
            dx: &mut [S; #state],
        ) -> ::core::result::Result<(), ::hamel::Singularity>
    }
}

/// The literals the signatures are written with: n, p, m, k, n − p, the state's length and
/// the lengths derived from them.
struct Lengths {
    n: Literal,
    p: Literal,
    m: Literal,
    k: Literal,
    free: Literal,
    state: Literal,
    extended: Literal,
    holonomic_jacobian: Literal,
    state_jacobian: Literal,
    input_jacobian: Literal,
}

impl Lengths {
    fn of(dims: Dims) -> Self {
        let Dims { n, p, m, k } = dims;
        let s = 2 * n - p;
        Lengths {
            n: lit(n),
            p: lit(p),
            m: lit(m),
            k: lit(k),
            free: lit(n - p),
            state: lit(s),
            extended: lit(s + 1),
            holonomic_jacobian: lit(k * n),
            state_jacobian: lit(s * s),
            input_jacobian: lit(s * m),
        }
    }
}

pub fn trait_impl(h: &Header<'_>, b: &Bodies) -> TokenStream {
    let l = Lengths::of(h.dims);
    let ty = &h.imp.self_ty;
    let (impl_generics, _, where_clause) = h.imp.generics.split_for_impl();
    let types = associated_types(&l);
    let consts = associated_consts(h, &l, b.prepared_len);
    let right_hand_side = right_hand_side(&l, b);
    let motion = motion(&l, b);
    let rows = rows(&l, b);
    let matrices = matrices(&l, b);
    let check_bodies = h.check_bodies.as_ref().map(|body| {
        let n = &l.n;
        quote! {
            fn check_bodies(&self, t: f64, q: &[f64; #n]) -> ::core::result::Result<(), ::hamel::Error> {
                #body
            }
        }
    });
    let singular = h.singular.as_ref().map(|body| {
        quote! {
            fn singular(s: ::hamel::Singularity, t: f64, x: &Self::State) -> ::hamel::Error {
                #body
            }
        }
    });
    // `do_not_recommend`: rustc's "the trait `HamelSystem` is not implemented for `Model`"
    // would otherwise list every model of the program (the catalogue's too) as the types that
    // do implement it, ten lines of no help under each such error.
    quote! {
        #[allow(clippy::all)]
        #[diagnostic::do_not_recommend]
        impl #impl_generics ::hamel::HamelSystem for #ty #where_clause {
            #types
            #consts
            #right_hand_side
            #motion
            #rows
            #matrices
            #check_bodies
            #singular
        }
    }
}

/// The array types of the coordinates, speeds, rows, state and matrices.
fn associated_types(l: &Lengths) -> TokenStream {
    let Lengths {
        n,
        p,
        m,
        k,
        free,
        state,
        extended,
        holonomic_jacobian,
        state_jacobian,
        input_jacobian,
    } = l;
    quote! {
        type Coordinates = [f64; #n];
        type Speeds = [f64; #free];
        type Constraints = [f64; #p];
        type State = [f64; #state];
        type Inputs = [f64; #m];
        type Holonomic = [f64; #k];
        type HolonomicJacobian = [f64; #holonomic_jacobian];
        type Extended = [f64; #extended];
        type MassMatrix = [[f64; #free]; #free];
        type Gamma = [[[f64; #free]; #free]; #n];
        type StateJacobian = [f64; #state_jacobian];
        type InputJacobian = [f64; #input_jacobian];
    }
}

/// The dimensions, the names and what the macro knows of the model.
fn associated_consts(h: &Header<'_>, l: &Lengths, prepared_len: usize) -> TokenStream {
    let Lengths { n, p, m, k, .. } = l;
    let (coordinates, speeds, inputs, constraints) =
        (&h.coordinates, &h.speeds, &h.inputs, &h.constraints);
    let state_names = coordinates.iter().chain(speeds);
    let dependent = h.dependent.iter().map(|&i| lit(i));
    let (conservative, reversible) = (h.conservative, h.reversible);
    let constant_determinant = h.constant_determinant;
    let power_vanishes = h.power_vanishes_without_inputs;
    let prepared_len = lit(prepared_len);
    let units = (!h.units.is_empty()).then(|| {
        let pairs = h.units.iter().map(|(name, unit)| quote!((#name, #unit)));
        quote!(const UNITS: &'static [(&'static str, &'static str)] = &[#(#pairs),*];)
    });
    quote! {
        const N: usize = #n;
        const P: usize = #p;
        const M: usize = #m;
        const K: usize = #k;
        const COORDINATES: &'static [&'static str] = &[#(#coordinates),*];
        const SPEEDS: &'static [&'static str] = &[#(#speeds),*];
        const CONSTRAINTS: &'static [&'static str] = &[#(#constraints),*];
        const INPUTS: &'static [&'static str] = &[#(#inputs),*];
        const STATE: &'static [&'static str] = &[#(#state_names),*];
        const DEPENDENT: &'static [usize] = &[#(#dependent),*];
        const CONSERVATIVE: bool = #conservative;
        const POWER_VANISHES_WITHOUT_INPUTS: bool = #power_vanishes;
        const REVERSIBLE: bool = #reversible;
        const PREPARED_LEN: usize = #prepared_len;
        const TRANSFORMATION_DETERMINANT_CONSTANT: bool = #constant_determinant;
        #units
    }
}

fn result() -> TokenStream {
    quote!(::core::result::Result)
}

fn singularity() -> TokenStream {
    quote!(::hamel::Singularity)
}

/// `#[inline]` on every method: besides inlining, it makes their code generated only in the
/// crates that call them, so a library of models (the catalogue) does not compile the
/// Jacobian, the constraint forces or γ of every model for nobody.
fn allow() -> TokenStream {
    quote!(#[inline] #[allow(clippy::all, clippy::pedantic, unused_parens, unused_variables, non_snake_case)])
}

/// The right-hand side, plain and with the parameter-only values prepared.
fn right_hand_side(l: &Lengths, b: &Bodies) -> TokenStream {
    let Lengths { m, state, .. } = l;
    let (result, singularity) = (result(), singularity());
    let Bodies {
        rhs,
        prepare,
        rhs_prepared,
        rhs_power_prepared,
        ..
    } = b;
    quote! {
        #[inline]
        fn rhs(&self, t: f64, x: &[f64; #state], u: &[f64; #m], dx: &mut [f64; #state]) -> #result<(), #singularity> {
            #rhs
        }
        #[inline]
        fn prepare(&self, prepared: &mut [f64]) {
            #prepare
        }
        #[inline]
        fn rhs_prepared(&self, prepared: &[f64], t: f64, x: &[f64; #state], u: &[f64; #m], dx: &mut [f64; #state]) -> #result<(), #singularity> {
            #rhs_prepared
        }
        #[inline]
        fn rhs_power_prepared(&self, prepared: &[f64], t: f64, x: &[f64; #state], u: &[f64; #m], dx: &mut [f64; #state]) -> #result<f64, #singularity> {
            #rhs_power_prepared
        }
    }
}

/// What a state implies: the velocities, the energy, the power and the constraint forces.
fn motion(l: &Lengths, b: &Bodies) -> TokenStream {
    let Lengths { n, p, m, state, .. } = l;
    let (result, singularity, allow) = (result(), singularity(), allow());
    let Bodies {
        generalized_velocities,
        energy,
        power,
        constraint_forces,
        ..
    } = b;
    quote! {
        #allow
        fn generalized_velocities(&self, t: f64, x: &[f64; #state]) -> #result<[f64; #n], #singularity> {
            #generalized_velocities
        }
        #allow
        fn energy(&self, t: f64, x: &[f64; #state]) -> #result<f64, #singularity> {
            #energy
        }
        #allow
        fn power(&self, t: f64, x: &[f64; #state], u: &[f64; #m]) -> #result<f64, #singularity> {
            #power
        }
        #allow
        fn multipliers(&self, t: f64, x: &[f64; #state], u: &[f64; #m]) -> #result<[f64; #p], #singularity> {
            #constraint_forces
        }
    }
}

/// The rows of the velocity transformation and the holonomic constraints, as written.
fn rows(l: &Lengths, b: &Bodies) -> TokenStream {
    let Lengths {
        n,
        p,
        k,
        free,
        holonomic_jacobian,
        ..
    } = l;
    let allow = allow();
    let Bodies {
        constraint_residual,
        speeds,
        holonomic_residual,
        holonomic_jacobian: holonomic_jacobian_body,
        ..
    } = b;
    quote! {
        #allow
        fn constraint_residual(&self, t: f64, q: &[f64; #n], qd: &[f64; #n]) -> [f64; #p] {
            #constraint_residual
        }
        #allow
        fn speeds(&self, t: f64, q: &[f64; #n], qd: &[f64; #n]) -> [f64; #free] {
            #speeds
        }
        #allow
        fn holonomic_residual(&self, t: f64, q: &[f64; #n]) -> [f64; #k] {
            #holonomic_residual
        }
        #allow
        fn holonomic_jacobian(&self, t: f64, q: &[f64; #n]) -> [f64; #holonomic_jacobian] {
            #holonomic_jacobian_body
        }
    }
}

/// The matrices for inspection and linearization: the mass matrix, γ, the inverse's defect
/// and the Jacobian of the right-hand side.
fn matrices(l: &Lengths, b: &Bodies) -> TokenStream {
    let Lengths {
        n,
        m,
        free,
        state,
        state_jacobian,
        input_jacobian,
        ..
    } = l;
    let (result, singularity, allow) = (result(), singularity(), allow());
    let Bodies {
        mass_matrix,
        gamma,
        inverse_defect,
        jacobian,
        time_derivative,
        ..
    } = b;
    quote! {
        #allow
        fn mass_matrix(&self, t: f64, x: &[f64; #state]) -> #result<[[f64; #free]; #free], #singularity> {
            #mass_matrix
        }
        #allow
        fn gamma(&self, t: f64, q: &[f64; #n]) -> #result<[[[f64; #free]; #free]; #n], #singularity> {
            #gamma
        }
        #allow
        fn inverse_defect(&self, t: f64, q: &[f64; #n]) -> #result<f64, #singularity> {
            #inverse_defect
        }
        #allow
        fn jacobian(&self, t: f64, x: &[f64; #state], u: &[f64; #m]) -> #result<([f64; #state_jacobian], [f64; #input_jacobian]), #singularity> {
            #jacobian
        }
        #allow
        fn time_derivative(&self, t: f64, x: &[f64; #state], u: &[f64; #m]) -> #result<::core::option::Option<[f64; #state]>, #singularity> {
            #time_derivative
        }
    }
}
