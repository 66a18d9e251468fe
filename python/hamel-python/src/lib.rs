//! hamel's models from Python: one `#[pyclass]` for every model, the generic machinery behind
//! an object-safe trait ([`ModelObject`], implemented once for every `#[hamel_system]` model),
//! and [`export_models!`], which makes an extension module of a crate's models.
//!
//! The prebuilt catalogue (`hamel._native` in the wheel), the modules `hamel.compile` builds
//! from a user's source, and a user's own crate (`maturin develop`) are each one line:
//!
//! ```text
//! hamel_python::export_models!(my_models: Sleigh, Skate);
//! ```
//!
//! The Python package `hamel` wraps what such a module returns in the same Python classes
//! (`hamel.Model`, `hamel.Run`, `hamel.Linearization`, the errors of `hamel.errors`), so a
//! model from any of the three behaves the same.

mod describe;
mod ensemble;
mod errors;
mod events;
mod inputs;
mod interrupt;
mod linear;
mod model;
mod native;
mod object;
mod probe;
mod run;
mod settings;
mod study;

pub use describe::Description;
pub use model::{Hooks, Model};
pub use object::{ModelObject, NativeModel, NativeModelType};
pub use probe::{
    Probe, ViaControl, ViaDefault, ViaMechanism, ViaNoControl, ViaNoMechanism, ViaZeroed,
};

/// The crates the macro's expansion names, so that a crate exporting models needs only
/// `hamel` and `hamel-python` among its dependencies.
pub use {hamel, numpy, pyo3};

use pyo3::prelude::*;

/// Adds the model type `S`, called `name`, to the module being made (what
/// [`export_models!`] expands to, once per model).
pub fn register<S: Model>(
    module: &Bound<'_, PyModule>,
    name: &'static str,
    hooks: Hooks<S>,
) -> PyResult<()> {
    let ty = NativeModelType::new::<S>(name, hooks);
    let types = match module.getattr("models") {
        Ok(existing) => existing,
        Err(_) => {
            let dict = pyo3::types::PyDict::new(module.py());
            module.add("models", &dict)?;
            dict.into_any()
        }
    };
    types.set_item(name, Py::new(module.py(), ty)?)?;
    Ok(())
}

/// Adds what every module of models has beside them: its version of hamel, to check against
/// the Python package's.
pub fn register_module(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("hamel_version", env!("CARGO_PKG_VERSION"))?;
    module.add_class::<NativeModel>()?;
    module.add_class::<NativeModelType>()?;
    module.add_class::<run::NativeRun>()?;
    module.add_class::<linear::NativeLinearization>()?;
    module.add_class::<linear::NativeLqr>()?;
    module.add_class::<ensemble::NativeTable>()?;
    Ok(())
}

/// An extension module of models: `export_models!(module_name: Model, Other)` defines
/// `PyInit_module_name`, whose module holds a dictionary `models` of the model types by name.
/// The crate's library must be a `cdylib` named `module_name`, and depend on `hamel` and on
/// this crate under its name, `hamel_python`. Import the module through the Python package:
/// `hamel.load("module_name")` returns its model classes.
///
/// Each model needs `#[hamel_system]` on its parameter struct and impl block; its parameters'
/// defaults are its `Default` where it has one (otherwise every parameter must be given), its
/// scene needs `#[bodies]` (`Mechanism`), its outputs `#[outputs]` (`ControlAffine`).
/// `export_models!(name: A, B; functions(f, g))` also adds the `#[pyfunction]`s `f` and `g`.
#[macro_export]
macro_rules! export_models {
    ($module:ident : $($model:ident),+ $(,)?) => {
        $crate::export_models!($module: $($model),+ ; functions());
    };
    ($module:ident : $($model:ident),+ $(,)? ; functions($($function:path),* $(,)?)) => {
        #[$crate::pyo3::pymodule]
        #[pyo3(crate = "::hamel_python::pyo3")]
        fn $module(
            module: &$crate::pyo3::Bound<'_, $crate::pyo3::types::PyModule>,
        ) -> $crate::pyo3::PyResult<()> {
            #[allow(unused_imports)]
            use $crate::{ViaControl, ViaDefault, ViaMechanism, ViaNoControl, ViaNoMechanism, ViaZeroed};
            $crate::register_module(module)?;
            $(
                $crate::register::<$model>(
                    module,
                    ::core::stringify!($model),
                    $crate::Hooks {
                        factory: (&$crate::Probe::<$model>::new()).factory(),
                        scene: (&$crate::Probe::<$model>::new()).scene(),
                        outputs: (&$crate::Probe::<$model>::new()).outputs(),
                    },
                )?;
            )+
            $(
                $crate::pyo3::types::PyModuleMethods::add_function(
                    module,
                    $crate::pyo3::wrap_pyfunction!($function, module)?,
                )?;
            )*
            ::core::result::Result::Ok(())
        }
    };
}
