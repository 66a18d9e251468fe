"""The paper's mobile robot as a CasADi SX model, written from its Hamel equations.

Franke, Zaiczek, Röbenack, "Simulation of Nonholonomic Mechanical Systems Using Algorithmic
Differentiation", section 4: q = (x, y, alpha, phi1, phi2), quasi-velocities
w3 = alpha', w4 = the path velocity, w5 = the yaw rate; state (q, w3, w4, w5). The
equations below are the paper's eq. (4) carried through for the robot, with the signs of the
last terms of f4 and f5 as they follow from its eq. (4), its gamma values and its
Lagrangian (12) (the paper prints both with the opposite sign; the tests check this model
against hamel's right-hand side before comparing any derivative):

    f3 = (Jy + m0 l^2) w3' + m0 l cos(a) w4' - 1/2 (Jx - Jz + m0 l^2) sin(2a) w5^2 - m0 l g sin(a)
    f4 = m0 l cos(a) w3' + (m0 + 3 mw) w4' - m0 l sin(a) (w3^2 + w5^2)
    f5 = J5 w5' + (Jx - Jz + m0 l^2) sin(2a) w3 w5 + m0 l sin(a) w4 w5

with J5 = (Jx + m0 l^2) sin^2(a) + Jz cos^2(a) + 3/4 mw b^2 + 1/2 mw r^2, the generalized
forces f3 = -(tau1 + tau2), f4 = (tau1 + tau2)/r, f5 = b (tau1 - tau2)/(2 r), and the
kinematics x' = cos(theta) w4, y' = sin(theta) w4, alpha' = w3,
phi1' = -w3 + w4/r + b/(2r) w5, phi2' = -w3 + w4/r - b/(2r) w5, theta = r (phi1 - phi2)/b.
"""

import casadi as ca

PARAMETERS = ["m0", "mw", "jx", "jy", "jz", "r", "b", "l", "g"]
DEFAULTS = [10.0, 1.0, 0.4, 0.3, 0.2, 0.1, 0.5, 0.2, 9.81]


def rhs(x, u, p):
    """xdot = F(x, u, p) as SX (or MX) expressions."""
    _, _, a, phi1, phi2, w3, w4, w5 = (x[i] for i in range(8))
    tau1, tau2 = u[0], u[1]
    m0, mw, jx, jy, jz, r, b, l, g = (p[i] for i in range(9))
    theta = r * (phi1 - phi2) / b
    sa, ca_ = ca.sin(a), ca.cos(a)
    ml2 = m0 * l * l
    j5 = (jx + ml2) * sa * sa + jz * ca_ * ca_ + 0.75 * mw * b * b + 0.5 * mw * r * r
    f3 = -(tau1 + tau2)
    f4 = (tau1 + tau2) / r
    f5 = b * (tau1 - tau2) / (2 * r)
    # M (w3', w4', w5') = rest: the mass matrix's 2x2 block and its last diagonal entry.
    m33, m34, m44 = jy + ml2, m0 * l * ca_, m0 + 3 * mw
    rest3 = f3 + 0.5 * (jx - jz + ml2) * ca.sin(2 * a) * w5 * w5 + m0 * l * g * sa
    rest4 = f4 + m0 * l * sa * (w3 * w3 + w5 * w5)
    rest5 = f5 - (jx - jz + ml2) * ca.sin(2 * a) * w3 * w5 - m0 * l * sa * w4 * w5
    det = m33 * m44 - m34 * m34
    dw3 = (m44 * rest3 - m34 * rest4) / det
    dw4 = (m33 * rest4 - m34 * rest3) / det
    dw5 = rest5 / j5
    return ca.vertcat(
        ca.cos(theta) * w4,
        ca.sin(theta) * w4,
        w3,
        -w3 + w4 / r + b / (2 * r) * w5,
        -w3 + w4 / r - b / (2 * r) * w5,
        dw3,
        dw4,
        dw5,
    )


def function(name="robot_sx"):
    """F as a CasADi Function of SX, with the inputs and output named as hamel's."""
    x, u, p = ca.SX.sym("x", 8), ca.SX.sym("u", 2), ca.SX.sym("p", 9)
    return ca.Function(name, [x, u, p], [rhs(x, u, p)], ["x", "u", "p"], ["xdot"])


def outputs(x, p):
    """y = h(x, p): hamel's robot's outputs (`look_ahead`), the point 0.3 m ahead of the
    axle's centre along the heading theta = r (phi1 - phi2) / b."""
    r, b = p[5], p[6]
    theta = r * (x[3] - x[4]) / b
    return ca.vertcat(x[0] + 0.3 * ca.cos(theta), x[1] + 0.3 * ca.sin(theta))
