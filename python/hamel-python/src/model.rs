//! What a model needs to be exported ([`Model`]), and what the export macro finds out about
//! it at its concrete type ([`Hooks`]): how to make one, its scene, its outputs.

use hamel::{HamelSystem, Trajectory};

/// A model the Python package can drive: any `#[hamel_system]` model (its parameter struct is
/// plain numbers, so it is `Send` and `Sync`).
pub trait Model: HamelSystem + Send + Sync + 'static {}

impl<S: HamelSystem + Send + Sync + 'static> Model for S {}

/// How to make a model before its parameters are set: from its `Default` (whose values are
/// then the parameters' defaults), or, for a parameter struct without one, from zeros, every
/// parameter then having to be given.
pub struct Factory<S> {
    pub make: fn() -> Option<S>,
    pub defaults: bool,
}

/// A model's scene as an HTML page (models with `#[bodies]`): the run, the columns shown
/// beside it (`None`: the coordinates), and a title.
pub type SceneFn<S> =
    fn(&S, &Trajectory, Option<&[String]>, Option<&str>) -> Result<String, String>;

/// A model's outputs y = h(t, x) (models with `#[outputs]`): their names and values.
pub struct OutputsHook<S: HamelSystem> {
    pub names: &'static [&'static str],
    pub values: fn(&S, f64, &S::State) -> Vec<f64>,
}

/// What `export_models!` finds out about a model at its concrete type (see `probe`).
pub struct Hooks<S: HamelSystem> {
    pub factory: Factory<S>,
    pub scene: Option<SceneFn<S>>,
    pub outputs: Option<OutputsHook<S>>,
}

impl<S: HamelSystem> Clone for Factory<S> {
    fn clone(&self) -> Self {
        Factory {
            make: self.make,
            defaults: self.defaults,
        }
    }
}

impl<S: HamelSystem> Clone for OutputsHook<S> {
    fn clone(&self) -> Self {
        OutputsHook {
            names: self.names,
            values: self.values,
        }
    }
}

impl<S: HamelSystem> Clone for Hooks<S> {
    fn clone(&self) -> Self {
        Hooks {
            factory: self.factory.clone(),
            scene: self.scene,
            outputs: self.outputs.clone(),
        }
    }
}
