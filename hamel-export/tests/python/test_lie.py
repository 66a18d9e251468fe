"""The exported Lie derivatives (`<model>_lie`, feature `compiled`) against CasADi's own
algorithmic differentiation.

`<model>_lie(x, p)` holds L_f^k h_i for k = 0 ... order, then L_{g_j} L_f^k h_i for k < order
(k outermost, then the output i, then the input j), where f is the drift F(x, 0, p) and g_j
the input fields dF/du_j of the control-affine right-hand side F. Here the same quantities
are built by CasADi from their definitions, L_f phi = (d phi / dx) f and
L_{g_j} phi = (d phi / dx) g_j:

- for the robot, from the SX model of the paper's equations (robot_sx.py, with its outputs
  written out): CasADi's symbolic derivatives, nothing of hamel's;
- for the Whipple bicycle, from the SX model whose mechanics CasADi derives (whipple_sx.py,
  its outputs the lean and the steer angle), likewise nothing of hamel's; and through the
  external functions `whipple_bicycle_f` and
  `whipple_bicycle_h` themselves: the Jacobians and Hessians CasADi takes of the external
  calls (hamel's exported first and second derivative functions, a code path of their own:
  the Lie derivatives are emitted by the macro from their own derivation). CasADi cannot
  differentiate an external's derivative function again (`jac_` of `jac_`), so the second
  Lie derivatives are written out with the Hessians it can take (reverse, then `jac_adj1_`):
  L_f^2 h_i = f' H_i f + (dh_i/dx) (df/dx) f and L_g L_f h_i = f' H_i g + (dh_i/dx)(df/dx) g.
"""

import casadi as ca
import numpy as np

import robot_sx
import whipple_sx

RNG = np.random.default_rng(35)


def close(a, b, rtol):
    """Every entry within rtol of its own magnitude (the larger of the two), or of 1e-3 of
    the vector's largest where both are smaller (an entry that cancels to nearly zero keeps
    the rounding of its terms); the largest error in those units."""
    a, b = np.asarray(a, dtype=float).ravel(), np.asarray(b, dtype=float).ravel()
    floor = 1e-3 * max(np.max(np.abs(a)), np.max(np.abs(b)), 1e-300)
    errors = np.abs(a - b) / np.maximum(np.maximum(np.abs(a), np.abs(b)), floor)
    return np.max(errors) <= rtol, np.max(errors)


def lie_by_definition(rhs, outputs, x, u, p, order):
    """L_f^k h for k = 0 ... order, then L_{g_j} L_f^k h for k < order, from `rhs(x, u, p)`
    and `outputs(x, p)` by CasADi's jacobian (of SX or MX expressions alike)."""
    zero = ca.DM.zeros(u.shape[0])
    drift = ca.substitute(rhs(x, u, p), u, zero)
    fields = ca.substitute(ca.jacobian(rhs(x, u, p), u), u, zero)
    powers = [outputs(x, p)]
    for _ in range(order):
        powers.append(ca.jacobian(powers[-1], x) @ drift)
    along_inputs = []
    for k in range(order):
        # Rows: output i, then input j within it.
        lg = ca.jacobian(powers[k], x) @ fields
        along_inputs.append(ca.reshape(lg.T, -1, 1))
    return ca.vertcat(*powers, *along_inputs)


def lie_of_order_two(rhs, outputs, x, u, p):
    """The same as `lie_by_definition(.., order=2)` from first derivatives and Hessians only,
    which CasADi takes of external functions."""
    zero = ca.DM.zeros(u.shape[0])
    drift = ca.substitute(rhs(x, u, p), u, zero)
    fields = ca.substitute(ca.jacobian(rhs(x, u, p), u), u, zero)
    h = outputs(x, p)
    dh = ca.jacobian(h, x)
    df = ca.jacobian(drift, x)
    second, along = [], []
    for i in range(h.shape[0]):
        hessian = ca.hessian(h[i], x)[0]
        second.append(drift.T @ hessian @ drift + dh[i, :] @ df @ drift)
        along.append((drift.T @ hessian @ fields + dh[i, :] @ df @ fields).T)
    return ca.vertcat(h, dh @ drift, *second, ca.reshape((dh @ fields).T, -1, 1), *along)


def test_the_two_forms_agree_on_the_sx_robot():
    """The form the bicycle's test takes, against the definition, both by CasADi alone."""
    x, u, p = ca.SX.sym("x", 8), ca.SX.sym("u", 2), ca.SX.sym("p", 9)
    a = lie_by_definition(robot_sx.rhs, robot_sx.outputs, x, u, p, 2)
    b = lie_of_order_two(robot_sx.rhs, robot_sx.outputs, x, u, p)
    both = ca.Function("both", [x, p], [a, b])
    for _ in range(20):
        xv = RNG.uniform(-1.0, 1.0, 8)
        pv = np.array(robot_sx.DEFAULTS) * RNG.uniform(0.8, 1.25, 9)
        va, vb = both(xv, pv)
        ok, err = close(va, vb, 1e-13)
        assert ok, err


def test_the_robots_lie_derivatives_are_casadis_of_the_sx_model(robot_library):
    lie = ca.external("mobile_robot_lie", robot_library)
    assert [lie.name_in(i) for i in range(lie.n_in())] == ["x", "p"]
    x, u, p = ca.SX.sym("x", 8), ca.SX.sym("u", 2), ca.SX.sym("p", 9)
    # order 2, two outputs, two inputs: (2 + 1) 2 + 2 * 2 * 2 components.
    reference = ca.Function("lie_sx", [x, p],
                            [lie_by_definition(robot_sx.rhs, robot_sx.outputs, x, u, p, 2)])
    assert lie.size1_out(0) == reference.size1_out(0) == 14
    worst = 0.0
    for _ in range(100):
        xv = RNG.uniform(-1.0, 1.0, 8)
        xv[2] = RNG.uniform(-np.pi, np.pi)
        pv = np.array(robot_sx.DEFAULTS) * RNG.uniform(0.8, 1.25, 9)
        ok, err = close(lie(xv, pv), reference(xv, pv), 1e-12)
        worst = max(worst, err)
        assert ok, err
    print(f"robot: largest Lie derivative difference, relative: {worst:.2e}")


def test_the_bicycles_lie_derivatives_are_casadis_through_the_external_functions(
        bicycle_library, bicycle_parameters):
    f = ca.external("whipple_bicycle_f", bicycle_library)
    h = ca.external("whipple_bicycle_h", bicycle_library)
    lie = ca.external("whipple_bicycle_lie", bicycle_library)
    x, u, p = ca.MX.sym("x", 11), ca.MX.sym("u", 2), ca.MX.sym("p", 26)
    reference = ca.Function("lie_mx", [x, p], [lie_of_order_two(f, h, x, u, p)])
    assert lie.size1_out(0) == reference.size1_out(0) == 14
    defaults = bicycle_parameters
    worst = 0.0
    for _ in range(50):
        # Lean and steer within +-0.5 rad, the frame's pitch small, any speed up to 10 m/s.
        xv = RNG.uniform(-0.5, 0.5, 11)
        xv[4] = RNG.uniform(-0.05, 0.05)
        xv[8:10] = RNG.uniform(-2.0, 2.0, 2)
        xv[10] = RNG.uniform(-30.0, 30.0)
        pv = defaults * RNG.uniform(0.9, 1.1, 26)
        ok, err = close(lie(xv, pv), reference(xv, pv), 1e-12)
        worst = max(worst, err)
        assert ok, err
    print(f"bicycle: largest Lie derivative difference, relative: {worst:.2e}")


def test_the_bicycles_lie_derivatives_are_casadis_of_the_sx_model(bicycle_library,
                                                                  bicycle_parameters):
    lie = ca.external("whipple_bicycle_lie", bicycle_library)
    x, u, p = ca.SX.sym("x", 11), ca.SX.sym("u", 2), ca.SX.sym("p", 26)

    def lean_and_steer(x, _p):
        return ca.vertcat(x[3], x[5])

    reference = ca.Function("lie_sx", [x, p],
                            [lie_by_definition(whipple_sx.rhs, lean_and_steer, x, u, p, 2)])
    worst = 0.0
    for _ in range(30):
        # States on the contact: the pitch solved for the lean and steer.
        xv = RNG.uniform(-0.5, 0.5, 11)
        xv[8:10] = RNG.uniform(-2.0, 2.0, 2)
        xv[10] = RNG.uniform(-30.0, 30.0)
        xv[4] = whipple_sx.pitch(xv[3], xv[5], ca.DM(bicycle_parameters))
        ok, err = close(lie(xv, bicycle_parameters), reference(xv, bicycle_parameters), 1e-12)
        worst = max(worst, err)
        assert ok, err
    print(f"bicycle (SX model): largest Lie derivative difference, relative: {worst:.2e}")
