//! Procedural macros of [`hamel`](https://docs.rs/hamel). Use them through the `hamel` crate.
//!
//! The macros are thin entry points; the work is in `engine` (compile-time differentiation)
//! and in the expansion modules. Every entry point returns errors as `compile_error!` with the
//! span of the user's code, and never panics.

mod differentiate;
mod engine;
mod helpers;
mod stray_role;
mod system;

use proc_macro::TokenStream;

/// Generate derivative methods for every function of an impl block; see the `hamel` crate.
#[proc_macro_attribute]
pub fn differentiate(attr: TokenStream, item: TokenStream) -> TokenStream {
    guarded(|| differentiate::expand(attr.into(), item.into())).into()
}

/// Turn a model into a simulator: Hamel's equations, differentiated at compile time.
///
/// Goes on two items. On the parameter struct (no arguments): every field is a named `f64`,
/// and the struct gets an implementation of `hamel::Parameters` (get and set by name). On the
/// model's inherent impl block,
/// `#[hamel_system(coordinates(..), speeds(..), inputs(..), constraints(..))]` names the
/// coordinates (required), the free quasi-velocities (default `w{p+1}`…`w{n}`), the inputs
/// (default none) and the constraint rows, those of `#[constraints]` then those of
/// `#[holonomic]` (default `blade0`: the function's name and the row), and role attributes
/// mark the functions:
///
/// * the energy, in one of three forms: `#[lagrangian]` L(q, q̇), or `#[kinetic_energy]`
///   T(q, q̇) with an optional `#[potential_energy]` V(q), or `#[quasi_lagrangian]` L̃(q, ω);
/// * `#[constraints]` and `#[quasi_velocities]` (required): the rows of ω = A(q) q̇ + a(q),
///   affine in q̇, the constrained ones and those that complete them;
/// * `#[holonomic(determines(..))]` (optional): constraints f(q) = 0 on the configuration,
///   which the macro differentiates into constraint rows;
/// * `#[velocities]` (optional): the inverse q̇ = B(q)(ω − a) over all n quasi-velocities,
///   the constrained ones first; derived from A(q) when absent (its block-triangular form's
///   blocks inverted in closed form, or an LU factorization);
/// * `#[forces]` (optional): the generalized forces f(t, q, q̇, u).
///
/// Every role but `#[forces]` may take the time as a leading argument `t: f64`.
///
/// The macro implements `hamel::HamelSystem` for the model — the reduced ODE of dimension
/// 2n − p in the state x = (q, free quasi-velocities) — and adds an index constant per name
/// (`Model::THETA`) and `rhs_generic`. A malformed model is a compile error at the mistake.
///
/// See [`hamel::docs::model`](../hamel/docs/model/index.html) for every role's exact
/// signature, the state layout and worked examples,
/// [`hamel::docs::subset`](../hamel/docs/subset/index.html) for what a body may contain, and
/// [`hamel::docs::design`](../hamel/docs/design/index.html) for the mathematics.
#[proc_macro_attribute]
pub fn hamel_system(attr: TokenStream, item: TokenStream) -> TokenStream {
    guarded(|| system::expand(attr.into(), item.into())).into()
}

/// Marks the Lagrangian L(q, q̇) = T − V, in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N], qd: &[f64; N]) -> f64`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn lagrangian(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("lagrangian", item.into()).into()
}

/// Marks the kinetic energy T(q, q̇), in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N], qd: &[f64; N]) -> f64`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn kinetic_energy(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("kinetic_energy", item.into()).into()
}

/// Marks the potential energy V(q), with a `#[kinetic_energy]`, in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N]) -> f64`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn potential_energy(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("potential_energy", item.into()).into()
}

/// Marks the Lagrangian in quasi-velocities L̃(q, ω), in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N], w: &[f64; N]) -> f64`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn quasi_lagrangian(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("quasi_lagrangian", item.into()).into()
}

/// Marks the constraint rows ω¹…ωᵖ(q, q̇), affine in q̇ and zero on every motion, in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; P]`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn constraints(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("constraints", item.into()).into()
}

/// Marks the quasi-velocities ω^{p+1}…ωⁿ(q, q̇) that complete the constraints to an invertible ω = A(q)·q̇, in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N], qd: &[f64; N]) -> [f64; N - P]`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn quasi_velocities(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("quasi_velocities", item.into()).into()
}

/// Marks the inverse q̇ = B(q)·ω (optional: without it, B comes from A(q) at run time), in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, q: &[f64; N], w: &[f64; N]) -> [f64; N]`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn velocities(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("velocities", item.into()).into()
}

/// Marks the generalized forces f(t, q, q̇, u) (optional), in the model's impl block with `#[hamel_system]`, which reads
/// and removes the attribute: `fn(&self, t: f64, q: &[f64; N], qd: &[f64; N], u: &[f64; M]) -> [f64; N]`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn forces(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("forces", item.into()).into()
}

/// Run an expansion; should it ever panic, report an error instead of "proc macro panicked".
fn guarded(expand: impl FnOnce() -> proc_macro2::TokenStream) -> proc_macro2::TokenStream {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(expand)) {
        Ok(tokens) => tokens,
        Err(_) => syn::Error::new(
            proc_macro2::Span::call_site(),
            "hamel internal error: the macro failed on this input; please report it with the model",
        )
        .into_compile_error(),
    }
}

/// Marks the holonomic constraints f(q) = 0 (`#[holonomic(determines(theta))]`, naming the
/// coordinate each one is solved for), in the model's impl block with `#[hamel_system]`,
/// which reads and removes the attribute: `fn(&self, q: &[f64; N]) -> [f64; K]`. Anywhere else
/// it is an error that says where it belongs.
#[proc_macro_attribute]
pub fn holonomic(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("holonomic", item.into()).into()
}

/// Marks the rigid bodies (mass, inertia in their own axes, centre of mass and orientation as
/// functions of q), whose kinetic energy and, with `#[gravity]`, potential energy the macro
/// derives, in the model's impl block with `#[hamel_system]`, which reads and removes the
/// attribute: `fn(&self, q: &[f64; N]) -> [Body; B]`. Anywhere else it is an error that says
/// where it belongs.
#[proc_macro_attribute]
pub fn bodies(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("bodies", item.into()).into()
}

/// Marks the gravitational acceleration acting on the bodies of `#[bodies]`, in the model's
/// impl block with `#[hamel_system]`, which reads and removes the attribute:
/// `fn(&self) -> Vector3`. Anywhere else it is an error that says where it belongs.
#[proc_macro_attribute]
pub fn gravity(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("gravity", item.into()).into()
}

/// Marks the rolling contacts (`#[contacts]`, or `#[contacts(determines(theta))]` naming the
/// coordinates the contacts' heights determine), from which the macro derives the constraint
/// rows, in the model's impl block with `#[hamel_system]`, which reads and removes the
/// attribute: `fn(&self, q: &[f64; N]) -> [Contact; C]`. Anywhere else it is an error that
/// says where it belongs.
#[proc_macro_attribute]
pub fn contacts(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("contacts", item.into()).into()
}

/// Marks an impl block of shared helpers: functions that the roles of several models call as
/// `Helpers::name(..)`, once the models name them, `#[hamel_system(helpers(Helpers))]`. The
/// macro differentiates through them like a model's own functions. The impl is emitted as it
/// is (the helpers are ordinary functions at run time) together with a macro of the same name
/// that carries their source to the models; bring both into a model's module with `use`.
#[proc_macro_attribute]
pub fn helpers(attr: TokenStream, item: TokenStream) -> TokenStream {
    guarded(|| helpers::expand(attr.into(), item.into())).into()
}

/// The callback the macros of `#[hamel::helpers]` call with a model and the helpers' source.
/// Not for direct use.
#[doc(hidden)]
#[proc_macro]
pub fn __hamel_with_helpers(input: TokenStream) -> TokenStream {
    guarded(|| system::expand_with_helpers(input.into())).into()
}

/// Marks the outputs y = h(t, q) (or h(t, q, speeds)) whose Lie derivatives the macro
/// generates for control (`hamel::ControlAffine`), in the model's impl block with
/// `#[hamel_system]`, which reads and removes the attribute:
/// `fn(&self, q: &[f64; N]) -> [f64; R]`. Anywhere else it is an error that says where it
/// belongs.
#[proc_macro_attribute]
pub fn outputs(_attr: TokenStream, item: TokenStream) -> TokenStream {
    stray_role::expand("outputs", item.into()).into()
}
