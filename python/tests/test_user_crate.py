"""A user's own crate (`tests/user_crate`: `hamel_python::export_models!(my_models: ...)`)
built as a user builds it, `maturin build` then `pip install` of the wheel, and driven
through `hamel.load`: its classes are `hamel.Model`s with the struct's doc comment as their
docstring, and a Rust panic inside a run or an ensemble's case (the crate's hand-written
model indexes past its table) comes back as a Python exception, the interpreter going on."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hamel

HERE = Path(__file__).resolve().parent
PYTHON_DIR = HERE.parent


def maturin() -> str:
    # The venv's maturin (the one `pip install ./python` builds with), else the PATH's.
    beside = Path(sys.executable).with_name("maturin")
    found = str(beside) if beside.exists() else shutil.which("maturin")
    if found is None:
        pytest.fail("maturin is needed to build a crate of models: pip install maturin")
    return found


@pytest.fixture(scope="module")
def my_models(tmp_path_factory):
    """The crate built by maturin into a wheel, installed by pip into a directory of its own
    put on `sys.path`, and loaded."""
    work = tmp_path_factory.mktemp("user-crate")
    crate = work / "my_models"
    shutil.copytree(HERE / "user_crate", crate)
    # The crate's path dependencies, from its copy; the wheel's lock file, so that it builds
    # with the versions the wheel was built with.
    manifest = (crate / "Cargo.toml").read_text()
    manifest = manifest.replace('path = "../../.."', f'path = "{PYTHON_DIR.parent.as_posix()}"')
    manifest = manifest.replace('path = "../../hamel-python"',
                                f'path = "{(PYTHON_DIR / "hamel-python").as_posix()}"')
    (crate / "Cargo.toml").write_text(manifest)
    shutil.copyfile(PYTHON_DIR / "Cargo.lock", crate / "Cargo.lock")
    # Built beside the wheel's own build (the same profile and features): hamel, PyO3 and
    # hamel-python are compiled once for both.
    env = dict(os.environ, CARGO_TARGET_DIR=str(PYTHON_DIR / "target"))
    wheels = work / "wheels"
    subprocess.run([maturin(), "build", "--release", "--interpreter", sys.executable,
                    "--out", str(wheels)], cwd=crate, env=env, check=True)
    site = work / "site"
    wheel = next(wheels.glob("my_models-*.whl"))
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
                    "--disable-pip-version-check", "--target", str(site), str(wheel)], check=True)
    sys.path.insert(0, str(site))
    try:
        yield hamel.load("my_models")
    finally:
        sys.path.remove(str(site))


def test_a_crates_models_are_hamel_models_with_their_doc_comments(my_models):
    assert set(my_models) == {"Sleigh", "TabulatedSpring"}
    Sleigh = my_models["Sleigh"]
    assert issubclass(Sleigh, hamel.Model)
    assert Sleigh.__doc__.startswith(
        "The Chaplygin sleigh: a rigid body on a plane whose blade, at distance `a` behind the\n"
        "centre of mass, cannot slide sideways.\n\nIts forward speed tends to √(2E/m)")
    assert "    m: mass (kg) [2]" in Sleigh.__doc__
    sleigh = Sleigh()
    run = sleigh.simulate(sleigh.state(v=1.0, omega=2.0), t_end=20.0, rtol=1e-10, atol=1e-12)
    # The README's check: the speed tends to √(2E/m), the same numbers as the catalogue's.
    assert abs(run["v"][-1] - np.sqrt(2.0 * run["energy"][0] / 2.0)) < 1e-6
    same = hamel.models.ChaplyginSleigh(m=2.0, inertia=0.5, a=0.4)
    reference = same.simulate(same.state(v=1.0, omega=2.0), t_end=20.0, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(reference["v"] - run["v"])) < 1e-9
    assert my_models["TabulatedSpring"].__doc__.startswith(
        "A mass on a spring whose stiffness is read from a table.")


def test_the_catalogues_classes_carry_their_structs_doc_comments():
    assert hamel.models.MobileRobot.__doc__.startswith("Parameters of the mobile robot.")


def test_a_rust_panic_in_a_run_is_a_python_exception(my_models):
    Spring = my_models["TabulatedSpring"]
    spring = Spring(m=1.0)
    # Inside the table (|x| < 0.8 m) the motion is harmonic: x = 0.5 cos 2t.
    inside = spring.simulate(spring.state(x=0.5), t_end=3.0, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(inside["x"] - 0.5 * np.cos(2.0 * inside.t))) < 1e-8
    # Out of it, the hand-written model indexes past its table and panics, in the run, with
    # the interpreter released: a Python exception, not a crash.
    with pytest.raises(hamel.errors.Panic) as caught:
        spring.simulate(spring.state(x=0.7, v=1.0), t_end=3.0)
    message = str(caught.value)
    assert message.startswith("hamel panicked (a bug in hamel or in the model")
    assert "index out of bounds: the len is 8 but the index is 8" in message
    assert caught.value.kind == "panic"
    # The same panic in an ensemble's case fails that case only.
    table = Spring().ensemble(states={"x": [0.5, 0.7, 0.3], "v": [0.0, 1.0, 0.0]}, t_end=3.0,
                              rtol=1e-10, atol=1e-12)
    assert table.failed == 1 and table.errors[0] is None and table.errors[2] is None
    kind, message = table.errors[1]
    assert kind == "case_panicked" and "index out of bounds" in message
    assert table["final_x"][0] == inside["x"][-1]
    # The interpreter goes on, and so do the crate's models.
    assert len(spring.simulate(spring.state(x=0.5), t_end=1.0)) == 101

