//! Which optional traits a model implements, decided at its concrete type in the expansion of
//! `export_models!` by autoref specialization: `(&Probe::<M>::new()).factory()` resolves to
//! the `Default` implementation when `M: Default` and to the fallback otherwise (method
//! lookup tries the receiver `&Probe<M>` before `&&Probe<M>`). Likewise the scene for models
//! with bodies (`Mechanism`) and the outputs for models with `#[outputs]` (`ControlAffine`).

use core::marker::PhantomData;

use hamel::geometry::Mechanism;
use hamel::{ControlAffine, Trajectory};

use crate::model::{Factory, Model, OutputsHook, SceneFn};

/// The type a probe asks about.
pub struct Probe<S>(PhantomData<fn() -> S>);

impl<S> Probe<S> {
    #[allow(clippy::new_without_default)]
    pub fn new() -> Self {
        Probe(PhantomData)
    }
}

/// A model with `Default`: made from it, its values the parameters' defaults.
pub trait ViaDefault {
    type Model: Model;
    fn factory(&self) -> Factory<Self::Model>;
}

impl<S: Model + Default> ViaDefault for Probe<S> {
    type Model = S;
    fn factory(&self) -> Factory<S> {
        Factory {
            make: || Some(S::default()),
            defaults: true,
        }
    }
}

/// A model without `Default`: made from zeros, every parameter to be given.
pub trait ViaZeroed {
    type Model: Model;
    fn factory(&self) -> Factory<Self::Model>;
}

impl<S: Model> ViaZeroed for &Probe<S> {
    type Model = S;
    fn factory(&self) -> Factory<S> {
        Factory {
            make: zeroed::<S>,
            defaults: false,
        }
    }
}

/// A parameter struct of zeros, when the struct is nothing but its parameters: a
/// `#[hamel_system]` parameter struct has only `f64` fields and arrays of them (the macro
/// refuses any other), `Parameters::NAMES` naming each of those numbers once, so a struct
/// exactly as large as its named numbers holds no other data, and all-zero bits are the
/// number 0 in each. Any other struct (a hand-written `Parameters` with more fields) gives
/// `None`.
fn zeroed<S: Model>() -> Option<S> {
    let plain = size_of::<S>() == S::NAMES.len() * size_of::<f64>()
        && (align_of::<S>() == align_of::<f64>() || size_of::<S>() == 0);
    // SAFETY: as said above, every byte of `S` belongs to an `f64`, for which zero bits are a
    // valid value (0.0).
    plain.then(|| unsafe { core::mem::zeroed() })
}

/// A model with bodies: its scene.
pub trait ViaMechanism {
    type Model: Model;
    fn scene(&self) -> Option<SceneFn<Self::Model>>;
}

impl<S: Model + Mechanism> ViaMechanism for Probe<S> {
    type Model = S;
    fn scene(&self) -> Option<SceneFn<S>> {
        Some(scene_of::<S>)
    }
}

/// A model without bodies has no scene.
pub trait ViaNoMechanism {
    type Model: Model;
    fn scene(&self) -> Option<SceneFn<Self::Model>>;
}

impl<S: Model> ViaNoMechanism for &Probe<S> {
    type Model = S;
    fn scene(&self) -> Option<SceneFn<S>> {
        None
    }
}

fn scene_of<S: Model + Mechanism>(
    model: &S,
    run: &Trajectory,
    show: Option<&[String]>,
    title: Option<&str>,
) -> Result<String, String> {
    let mut scene = hamel::scene::Scene::new(model, run).map_err(|e| e.to_string())?;
    if let Some(columns) = show {
        scene = scene.show(columns.iter().cloned());
    }
    if let Some(title) = title {
        scene = scene.title(title);
    }
    scene.to_html().map_err(|e| e.to_string())
}

/// A model with outputs (`#[outputs]`): their names and values.
pub trait ViaControl {
    type Model: Model;
    fn outputs(&self) -> Option<OutputsHook<Self::Model>>;
}

impl<S: Model + ControlAffine> ViaControl for Probe<S> {
    type Model = S;
    fn outputs(&self) -> Option<OutputsHook<S>> {
        Some(OutputsHook {
            names: S::OUTPUTS,
            values: |model, t, x| model.output_values(t, x).as_ref().to_vec(),
        })
    }
}

/// A model without outputs.
pub trait ViaNoControl {
    type Model: Model;
    fn outputs(&self) -> Option<OutputsHook<Self::Model>>;
}

impl<S: Model> ViaNoControl for &Probe<S> {
    type Model = S;
    fn outputs(&self) -> Option<OutputsHook<S>> {
        None
    }
}
