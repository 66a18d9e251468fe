"""hamel's exported Whipple bicycle inside CasADi, against a model of the same bicycle whose
mechanics CasADi derives (whipple_sx.py: Lagrange-d'Alembert equations in Maggi's form,
every derivative CasADi's own): the right-hand sides agree, and so do the first and second
derivatives IPOPT asks for (by the state and the inputs), at random states that satisfy the
front wheel's contact (the pitch solved for the lean and steer)."""

import casadi as ca
import numpy as np
import pytest

import whipple_sx

RNG = np.random.default_rng(2007)


def close(a, b, rtol):
    """Every entry within rtol of the larger magnitude of the two matrices."""
    a, b = np.asarray(a), np.asarray(b)
    scale = max(np.max(np.abs(a)), np.max(np.abs(b)), 1e-300)
    return np.max(np.abs(a - b)) <= rtol * scale, np.max(np.abs(a - b)) / scale


def states(count, parameters):
    """Lean and steer within +-0.5 rad, the pitch that keeps the front wheel on the ground,
    rates within +-2 rad/s, forward speeds from -1.5 to 6 m/s; inputs within +-1 N m."""
    for _ in range(count):
        x = np.zeros(11)
        x[0:3] = RNG.uniform(-1.0, 1.0, 3)
        x[3], x[5] = RNG.uniform(-0.5, 0.5, 2)
        x[4] = whipple_sx.pitch(x[3], x[5], ca.DM(parameters))
        x[6:8] = RNG.uniform(-3.0, 3.0, 2)
        x[8:10] = RNG.uniform(-2.0, 2.0, 2)
        x[10] = RNG.uniform(-20.0, 5.0)
        yield x, RNG.uniform(-1.0, 1.0, 2)


@pytest.fixture(scope="module")
def models(bicycle_library, bicycle_parameters):
    return ca.external("whipple_bicycle_f", bicycle_library), whipple_sx.function()


def test_the_contact_fixes_the_pitch(bicycle_parameters):
    """Upright with the steer straight the pitch is zero (the parameters are given there)."""
    assert abs(whipple_sx.pitch(0.0, 0.0, ca.DM(bicycle_parameters))) < 1e-15


def test_the_right_hand_sides_agree(models, bicycle_parameters):
    ours, theirs = models
    worst = 0.0
    for x, u in states(100, bicycle_parameters):
        ok, err = close(ours(x, u, bicycle_parameters), theirs(x, u, bicycle_parameters),
                        1e-12)
        worst = max(worst, err)
        assert ok, err
    print(f"largest right-hand side difference, relative: {worst:.2e}")


def derivatives(f, p):
    """The Jacobian by (x, u) and the Hessian of lambda . F by (x, u), CasADi's way."""
    x, u, lam = ca.MX.sym("x", 11), ca.MX.sym("u", 2), ca.MX.sym("lam", 11)
    z, out = ca.vertcat(x, u), f(x, u, p)
    return (ca.Function("jacobian", [x, u], [ca.jacobian(out, z)]),
            ca.Function("hessian", [x, u, lam], [ca.hessian(ca.dot(lam, out), z)[0]]))


def test_first_and_second_derivatives_agree(models, bicycle_parameters):
    (jac_ours, hess_ours), (jac_theirs, hess_theirs) = (
        derivatives(f, bicycle_parameters) for f in models)
    worst = [0.0, 0.0]
    for x, u in states(30, bicycle_parameters):
        lam = RNG.uniform(-1.0, 1.0, 11)
        for k, (a, b) in enumerate([(jac_ours(x, u), jac_theirs(x, u)),
                                    (hess_ours(x, u, lam), hess_theirs(x, u, lam))]):
            ok, err = close(a, b, 1e-12)
            worst[k] = max(worst[k], err)
            assert ok, (k, err)
    print(f"largest Jacobian difference {worst[0]:.2e}, Hessian {worst[1]:.2e} (relative)")
