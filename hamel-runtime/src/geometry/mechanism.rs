//! What a model stated from geometry says about itself at run time: its bodies, where they
//! touch their surfaces, and gravity, at any configuration. Scenes and pictures of a model
//! are drawn from this, so they show the model as the macro reads it: a body's shape, where
//! it has one, is [`Body::shape`], and what a contact rolls on is [`Contact::surface`].

use super::{Body, Contact, Vector3};
use crate::system::HamelSystem;

/// A model stated from its rigid bodies (`#[bodies]`): `#[hamel_system]` implements this for
/// every such model, by calling the model's own role functions, so what is drawn is exactly
/// what the equations were derived from.
#[diagnostic::on_unimplemented(
    message = "`{Self}` states no bodies to draw",
    label = "`{Self}` has no `#[bodies]` role",
    note = "scenes and pictures draw the rigid bodies a model states in a `#[bodies]` function \
            (`hamel::docs::geometry`); a model written from its energy has none"
)]
pub trait Mechanism: HamelSystem {
    /// The bodies' names, in the order `#[bodies]` returns them: as given in
    /// `#[hamel_system(bodies(..))]`, or `body0`, `body1`, … by default.
    const BODIES: &'static [&'static str];

    /// What the macro noted while reading the model's geometry: each contact row left out
    /// because it repeats the others at every configuration (two wheels on one axle), with
    /// what the kept rows' constraint forces then are. Empty for most models.
    const NOTES: &'static [&'static str] = &[];

    /// The bodies at time `t` and configuration `q`: the model's `#[bodies]` function.
    fn bodies_at(&self, t: f64, q: &Self::Coordinates) -> Vec<Body>;

    /// Where bodies roll without slipping at (t, q): the model's `#[contacts]` function, or
    /// none.
    fn contacts_at(&self, t: f64, q: &Self::Coordinates) -> Vec<Contact>;

    /// The gravitational acceleration at time `t` that the model's `#[gravity]` gives, if it
    /// has one.
    fn gravity_vector(&self, t: f64) -> Option<Vector3>;
}
