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
