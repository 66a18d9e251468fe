"""hamel's exported robot inside CasADi: it loads as an external function, its values are
hamel's right-hand side bit for bit, and its first and second derivatives equal CasADi's own
derivatives of an SX model of the same robot written from the paper's equations."""

import ctypes

import casadi as ca
import numpy as np
import pytest

import robot_sx

RNG = np.random.default_rng(20261129)


def points(count):
    """States, inputs and parameters around the defaults, pitch over a full turn."""
    for _ in range(count):
        x = RNG.uniform(-1.0, 1.0, 8)
        x[2] = RNG.uniform(-np.pi, np.pi)
        u = RNG.uniform(-1.0, 1.0, 2)
        p = np.array(robot_sx.DEFAULTS) * RNG.uniform(0.8, 1.25, 9)
        yield x, u, p


def hamel_rhs(lib, x, u, p):
    """mobile_robot_rhs: the model's own HamelSystem::rhs (what a hamel simulation runs)."""
    d = ctypes.POINTER(ctypes.c_double)
    out = np.zeros(8)
    args = [np.ascontiguousarray(v, dtype=float) for v in (x, u, p)]
    status = lib.mobile_robot_rhs(0.0, args[0].ctypes.data_as(d), 8, args[1].ctypes.data_as(d), 2,
                                  args[2].ctypes.data_as(d), 9, out.ctypes.data_as(d), 8)
    assert status == 0, lib.mobile_robot_last_error()
    return out


def close(a, b, rtol):
    """Every entry within rtol of the larger magnitude of the two matrices (entries that are
    zero in one are compared on that scale, not on their own)."""
    a, b = np.asarray(a), np.asarray(b)
    scale = max(np.max(np.abs(a)), np.max(np.abs(b)), 1e-300)
    return np.max(np.abs(a - b)) <= rtol * scale, np.max(np.abs(a - b)) / scale


def test_the_external_function_loads_with_hamels_names(robot_library):
    f = ca.external("mobile_robot_f", robot_library)
    assert [f.name_in(i) for i in range(f.n_in())] == ["x", "u", "p"]
    assert [f.name_out(i) for i in range(f.n_out())] == ["xdot"]
    assert [f.size1_in(i) for i in range(3)] == [8, 2, 9]
    library = ca.Importer(robot_library, "dll")
    for derivative in ("jac_", "fwd1_", "fwd2_", "fwd4_", "fwd8_", "adj1_", "jac_adj1_"):
        assert library.has_function(derivative + "mobile_robot_f"), derivative
        assert library.has_function(derivative + "mobile_robot_h"), derivative


def test_values_are_hamels_right_hand_side_bit_for_bit(robot_library, robot_c):
    f = ca.external("mobile_robot_f", robot_library)
    for x, u, p in points(200):
        ours = np.asarray(f(x, u, p)).ravel()
        rust = hamel_rhs(robot_c, x, u, p)
        assert ours.tobytes() == rust.tobytes(), (ours, rust)


def test_the_sx_model_is_the_same_robot(robot_library):
    """Before any derivative: the SX model's values are hamel's to rounding."""
    f = ca.external("mobile_robot_f", robot_library)
    sx = robot_sx.function()
    for x, u, p in points(200):
        ok, err = close(f(x, u, p), sx(x, u, p), 1e-13)
        assert ok, err


def symbolic(f):
    """z = (x, u, p), F(z) with MX symbols, and the Jacobian and Lagrangian Hessian functions."""
    x, u, p = ca.MX.sym("x", 8), ca.MX.sym("u", 2), ca.MX.sym("p", 9)
    lam = ca.MX.sym("lam", 8)
    z = ca.vertcat(x, u, p)
    out = f(x, u, p)
    jac = ca.Function("jacobian_z", [x, u, p], [ca.jacobian(out, z)])
    hess = ca.Function("hessian_z", [x, u, p, lam], [ca.hessian(ca.dot(lam, out), z)[0]])
    return jac, hess


def test_jacobian_equals_casadis_derivative_of_the_sx_model(robot_library):
    jac_ext, _ = symbolic(ca.external("mobile_robot_f", robot_library))
    jac_sx, _ = symbolic(robot_sx.function())
    worst = 0.0
    for x, u, p in points(100):
        ok, err = close(jac_ext(x, u, p), jac_sx(x, u, p), 1e-12)
        worst = max(worst, err)
        assert ok, err
    print(f"largest Jacobian difference, relative: {worst:.2e}")


def test_lagrangian_hessian_equals_casadis_of_the_sx_model(robot_library):
    _, hess_ext = symbolic(ca.external("mobile_robot_f", robot_library))
    _, hess_sx = symbolic(robot_sx.function())
    worst = 0.0
    for x, u, p in points(100):
        lam = RNG.uniform(-1.0, 1.0, 8)
        ok, err = close(hess_ext(x, u, p, lam), hess_sx(x, u, p, lam), 1e-12)
        worst = max(worst, err)
        assert ok, err
    print(f"largest Hessian difference, relative: {worst:.2e}")


def test_several_forward_directions_equal_casadis_of_the_sx_model(robot_library):
    """CasADi takes fwd2_, fwd4_ and fwd8_ for 2, 4 and 8 directions through a call (not its
    map of fwd1_), and they equal CasADi's forward derivatives of the SX model."""
    f = ca.external("mobile_robot_f", robot_library)
    sx = robot_sx.function()
    worst = 0.0
    for n in (2, 4, 8):
        ours, theirs = f.forward(n), sx.forward(n)
        assert ours.name() == f"fwd{n}_mobile_robot_f"
        assert ours.class_name() == "External", ours.class_name()  # not a Map of fwd1_
        for x, u, p in points(20):
            seeds = [RNG.uniform(-1.0, 1.0, (k, n)) for k in (8, 2, 9)]
            for dp in (seeds[2], np.zeros((9, n))):
                nominal = f(x, u, p)
                args = [x, u, p, nominal, seeds[0], seeds[1], dp]
                ok, err = close(ours(*args), theirs(*args), 1e-12)
                worst = max(worst, err)
                assert ok, (n, err)
    print(f"largest forward difference, relative: {worst:.2e}")


def test_the_jacobians_sparsity_holds_every_nonzero(robot_library):
    """The pattern from the generated code covers what CasADi's SX model finds nonzero."""
    f = ca.external("mobile_robot_f", robot_library)
    jf = f.jacobian()
    sx = robot_sx.function().jacobian()
    for i in range(3):
        ours, theirs = jf.sparsity_out(i), sx.sparsity_out(i)
        dense_ours = np.array(ca.DM(ours, 1))
        dense_theirs = np.array(ca.DM(theirs, 1))
        assert np.all(dense_ours >= dense_theirs), jf.name_out(i)


def test_a_nan_is_an_error_with_a_message(robot_library, robot_c):
    f = ca.external("mobile_robot_f", robot_library)
    x, u, p = next(points(1))
    x[5] = np.nan
    with pytest.raises(RuntimeError):
        f(x, u, p)
    message = robot_c.mobile_robot_last_error().decode()
    assert message == "mobile_robot_f: x[5] (w3) = NaN is not a finite number", message
