"""Where the exported libraries are: HAMEL_EXPORT_DIR, the OUTDIR of
`cargo run --release --example export -- casadi MODEL OUTDIR` (the `.ci/run` stage sets it)."""

import ctypes
import os
import pathlib

import pytest


@pytest.fixture(scope="session")
def outdir():
    path = os.environ.get("HAMEL_EXPORT_DIR")
    if not path:
        raise RuntimeError(
            "set HAMEL_EXPORT_DIR to the OUTDIR of "
            "`cargo run --release --example export -- casadi mobile_robot OUTDIR`"
        )
    return pathlib.Path(path)


@pytest.fixture(scope="session")
def robot_library(outdir):
    return str(outdir / "libmobile_robot.so")


@pytest.fixture(scope="session")
def robot_c(robot_library):
    """The library's plain C functions, through ctypes."""
    lib = ctypes.CDLL(robot_library)
    d = ctypes.POINTER(ctypes.c_double)
    lib.mobile_robot_rhs.argtypes = [ctypes.c_double, d, ctypes.c_size_t, d, ctypes.c_size_t,
                                     d, ctypes.c_size_t, d, ctypes.c_size_t]
    lib.mobile_robot_rhs.restype = ctypes.c_int
    lib.mobile_robot_last_error.restype = ctypes.c_char_p
    lib.mobile_robot_default_parameters.argtypes = [d, ctypes.c_size_t]
    return lib


@pytest.fixture(scope="session")
def bicycle_library(outdir):
    """`cargo run --release --example export -- casadi whipple_bicycle OUTDIR` (the `.ci/run`
    stage exports it beside the robot)."""
    path = outdir / "libwhipple_bicycle.so"
    if not path.exists():
        raise RuntimeError(
            f"{path} is missing: `cargo run --release --example export -- casadi "
            f"whipple_bicycle {outdir}` writes it"
        )
    return str(path)


@pytest.fixture(scope="session")
def bicycle_parameters(bicycle_library):
    """The benchmark's parameters, from the library's whipple_bicycle_default_parameters."""
    import numpy as np

    lib = ctypes.CDLL(bicycle_library)
    d = ctypes.POINTER(ctypes.c_double)
    lib.whipple_bicycle_default_parameters.argtypes = [d, ctypes.c_size_t]
    p = np.zeros(26)
    assert lib.whipple_bicycle_default_parameters(p.ctypes.data_as(d), 26) == 0
    return p
