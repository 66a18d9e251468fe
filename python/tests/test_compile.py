"""`hamel.compile`: the README's sleigh built into an extension module and run; a second call
builds nothing; a malformed model is a `hamel.CompileError` with rustc's message at the
user's line."""

import math
import os
import subprocess

import numpy as np
import pytest

import hamel
from hamel import _compile


@pytest.fixture(scope="module", autouse=True)
def cache(tmp_path_factory):
    # CI shares one cache between its runs (HAMEL_CACHE); a developer's run gets its own.
    if not os.environ.get("HAMEL_CACHE"):
        os.environ["HAMEL_CACHE"] = str(tmp_path_factory.mktemp("hamel-cache"))
    yield


def test_the_readme_sleigh_compiles_and_runs(readme_sleigh):
    Sleigh = hamel.compile(readme_sleigh)
    assert Sleigh.__name__ == "Sleigh"
    assert issubclass(Sleigh, hamel.Model)
    # The README's sleigh has no Default: every parameter is given.
    with pytest.raises(TypeError, match=r"Sleigh\(\) has no default parameters"):
        Sleigh(m=2.0)
    sleigh = Sleigh(m=2.0, inertia=0.5, a=0.4)
    assert sleigh.coordinates == ("x", "y", "theta") and sleigh.speeds == ("v", "omega")
    run = sleigh.simulate(sleigh.state(v=1.0, omega=2.0), t_end=20.0, rtol=1e-10, atol=1e-12)
    # The README's own check: the speed tends to √(2E/m).
    limit = math.sqrt(2.0 * run["energy"][0] / 2.0)
    assert abs(run["v"][-1] - limit) < 1e-6
    # The same model as the catalogue's sleigh gives the same numbers.
    catalogue = hamel.models.ChaplyginSleigh(m=2.0, inertia=0.5, a=0.4)
    same = catalogue.simulate(catalogue.state(v=1.0, omega=2.0), t_end=20.0, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(same["v"] - run["v"])) < 1e-9
    # Its errors are hamel's classes.
    with pytest.raises(hamel.errors.InvalidParameter):
        Sleigh(m=math.nan, inertia=0.5, a=0.4)


def test_a_second_call_builds_nothing(readme_sleigh, monkeypatch):
    first = hamel.compile(readme_sleigh)
    # Forget the classes loaded in this process: the module is found in the cache.
    _compile._LOADED.clear()

    real_run = subprocess.run

    def no_cargo(command, *args, **kwargs):
        if command and command[0] == "cargo":
            raise AssertionError("cargo was run for a source already built")
        return real_run(command, *args, **kwargs)

    monkeypatch.setattr(_compile.subprocess, "run", no_cargo)
    second = hamel.compile(readme_sleigh)
    assert second.__name__ == first.__name__ == "Sleigh"
    sleigh = second(m=2.0, inertia=0.5, a=0.4)
    assert len(sleigh.simulate(sleigh.state(v=1.0), t_end=1.0)) == 101


def test_a_malformed_model_is_a_compile_error_at_the_users_line(tmp_path):
    source = """use hamel::prelude::*;

#[hamel_system]
pub struct Skate { pub m: f64 }

#[hamel_system(coordinates(x, y), speeds(v))]
impl Skate {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 2], qd: &[f64; 2]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
    }

    #[constraints]
    fn blade(&self, _q: &[f64; 2], qd: &[f64; 2]) -> [f64; 1] {
        [qd[1].unknown_method()]
    }

    #[quasi_velocities]
    fn speeds(&self, _q: &[f64; 2], qd: &[f64; 2]) -> [f64; 1] {
        [qd[0]]
    }
}
"""
    path = tmp_path / "skate.rs"
    path.write_text(source)
    with pytest.raises(hamel.CompileError) as caught:
        hamel.compile(path)
    message = str(caught.value)
    assert f"{path}:15:" in message, message
    assert "unknown_method" in message
    assert "hamel_model_" not in message and "models/" not in message
    assert caught.value.diagnostics and caught.value.diagnostics[0]["line"] == 15


def test_a_source_without_a_model():
    with pytest.raises(hamel.CompileError, match="no model found"):
        hamel.compile("fn main() {}\n")


def test_a_module_of_models_loads_as_the_same_classes(readme_sleigh):
    # A crate's own module (`hamel_python::export_models!` and `maturin develop`) is loaded by
    # `hamel.load`; here the module `compile` built, loaded from its file under its name.
    Sleigh = hamel.compile(readme_sleigh)
    module = next(name for name, classes in _compile._LOADED.items()
                  if isinstance(classes, dict) and classes.get("Sleigh") is Sleigh)
    library = next((_compile.cache_directory()).glob(f"*/lib/{module}*"))
    _compile._LOADED.pop(module)
    classes = hamel.load(module, library)
    assert set(classes) == {"Sleigh"}
    sleigh = classes["Sleigh"](m=2.0, inertia=0.5, a=0.4)
    assert isinstance(sleigh, hamel.Model)
    assert sleigh.simulate(sleigh.state(v=1.0), t_end=1.0)["v"][0] == 1.0
    with pytest.raises(TypeError, match="not a module of hamel models"):
        hamel.load("json")
