"""The Whipple bicycle as a CasADi SX model, by Lagrangian mechanics in CasADi itself.

The geometry is the catalogue's (hamel-models/src/whipple_bicycle.rs, after Meijaard,
Papadopoulos, Ruina and Schwab, Proc. R. Soc. A 463, 2007): four bodies — the rear wheel, the
rear frame with the rider, the front frame, the front wheel — placed by the coordinates
q = (x, y, psi, phi, theta, delta, theta_r, theta_f), x forward, y right, z down. The
mechanics is not hamel's: CasADi's symbolic derivatives give the kinetic energy's mass
matrix and velocity terms, and the equations of motion are the Lagrange-d'Alembert
equations projected on the admissible velocities (Maggi's form):

    S(q)' [ M(q) q'' + (d/dq (dT/dq')) q' - dT/dq + dV/dq - Q ] = 0,   q' = S(q) w,

where the five rows of A(q) q' = 0 say that the material points of both wheels at their
contacts do not move (the rear one across x and y; the front one in x, y and z, whose z row
is the time derivative of the constraint that fixes the pitch theta), and S spans A's null
space with w = (roll rate, steer rate, rear wheel rate) = (phi', delta', theta_r'). With
q'' = S w' + (d(S w)/dq) q' this is a 3x3 linear system for w'. The state (q, w) and the
inputs (roll torque on phi, steer torque on delta) are hamel's, so the two right-hand sides
can be compared value for value.
"""

import casadi as ca

PARAMETERS = ["w", "c", "lambda", "g", "r_r", "m_r", "i_rxx", "i_ryy", "x_b", "z_b", "m_b",
              "i_bxx", "i_byy", "i_bzz", "i_bxz", "x_h", "z_h", "m_h", "i_hxx", "i_hyy",
              "i_hzz", "i_hxz", "r_f", "m_f", "i_fxx", "i_fyy"]


def about_x(a):
    c, s = ca.cos(a), ca.sin(a)
    return ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, c, -s), ca.horzcat(0, s, c))


def about_y(a):
    c, s = ca.cos(a), ca.sin(a)
    return ca.vertcat(ca.horzcat(c, 0, s), ca.horzcat(0, 1, 0), ca.horzcat(-s, 0, c))


def about_z(a):
    c, s = ca.cos(a), ca.sin(a)
    return ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))


def about_axis(k, a):
    """Rodrigues' formula for a unit axis k."""
    c, s = ca.cos(a), ca.sin(a)
    cross = ca.vertcat(ca.horzcat(0, -k[2], k[1]), ca.horzcat(k[2], 0, -k[0]),
                       ca.horzcat(-k[1], k[0], 0))
    return c * ca.SX.eye(3) + s * cross + (1 - c) * (k @ k.T)


def inertia(xx, yy, zz, xz):
    return ca.vertcat(ca.horzcat(xx, 0, xz), ca.horzcat(0, yy, 0), ca.horzcat(xz, 0, zz))


def bodies(q, p):
    """[(mass, inertia in body axes, centre, orientation)] of the four bodies."""
    x, y, psi, phi, theta, delta, theta_r, theta_f = (q[i] for i in range(8))
    (w, c, lam, _, r_r, m_r, i_rxx, i_ryy, x_b, z_b, m_b, i_bxx, i_byy, i_bzz, i_bxz, x_h,
     z_h, m_h, i_hxx, i_hyy, i_hzz, i_hxz, r_f, m_f, i_fxx, i_fyy) = (p[i] for i in range(26))
    yaw_roll = about_z(psi) @ about_x(phi)
    rear = yaw_roll @ about_y(theta)
    steer_axis = ca.vertcat(ca.sin(lam), 0, ca.cos(lam))
    front = rear @ about_axis(steer_axis, delta)
    rear_centre = ca.vertcat(x, y, 0) + yaw_roll @ ca.vertcat(0, 0, -r_r)
    hinge = rear_centre + rear @ ca.vertcat(w + c, 0, r_r)
    return [
        (m_r, inertia(i_rxx, i_ryy, i_rxx, 0), rear_centre, rear @ about_y(theta_r)),
        (m_b, inertia(i_bxx, i_byy, i_bzz, i_bxz),
         rear_centre + rear @ ca.vertcat(x_b, 0, z_b + r_r), rear),
        (m_h, inertia(i_hxx, i_hyy, i_hzz, i_hxz),
         hinge + front @ ca.vertcat(x_h - w - c, 0, z_h), front),
        (m_f, inertia(i_fxx, i_fyy, i_fxx, 0), hinge + front @ ca.vertcat(-c, 0, -r_f),
         front @ about_y(theta_f)),
    ]


def front_contact(centre, orientation, r_f):
    """The front wheel's lowest point: from its centre along the steepest descent in its
    plane (up is -z)."""
    axle = orientation @ ca.vertcat(0, 1, 0)
    up = ca.vertcat(0, 0, -1)
    along = ca.dot(up, axle)
    return centre - r_f / ca.sqrt(1 - along * along) * (up - along * axle)


def point_velocity(centre, orientation, point, q, qd):
    """The velocity of the body's material point at `point` (the body's angular velocity
    from R' R^T, in world axes)."""
    v = ca.jtimes(centre, q, qd)
    rdot = ca.jtimes(ca.vec(orientation), q, qd)
    omega_skew = ca.reshape(rdot, 3, 3) @ orientation.T
    omega = ca.vertcat(omega_skew[2, 1], omega_skew[0, 2], omega_skew[1, 0])
    return v + ca.cross(omega, point - centre)


def rhs(x, u, p):
    """xdot = F(x, u, p) as SX, x = (q, roll rate, steer rate, rear wheel rate)."""
    q, w = x[:8], x[8:11]
    qd = ca.SX.sym("qd", 8)
    parts = bodies(q, p)
    g, r_f = p[3], p[22]
    kinetic, potential = 0, 0
    for mass, tensor, centre, orientation in parts:
        v = ca.jtimes(centre, q, qd)
        rdot = ca.reshape(ca.jtimes(ca.vec(orientation), q, qd), 3, 3)
        omega_skew = orientation.T @ rdot  # body axes
        omega = ca.vertcat(omega_skew[2, 1], omega_skew[0, 2], omega_skew[1, 0])
        kinetic += 0.5 * mass * ca.dot(v, v) + 0.5 * ca.dot(omega, tensor @ omega)
        potential += -mass * g * centre[2]
    rear_wheel, front_wheel = parts[0], parts[3]
    rear_point = ca.vertcat(q[0], q[1], 0)
    front_point = front_contact(front_wheel[2], front_wheel[3], r_f)
    constraints = ca.vertcat(
        point_velocity(rear_wheel[2], rear_wheel[3], rear_point, q, qd)[:2],
        point_velocity(front_wheel[2], front_wheel[3], front_point, q, qd),
    )
    a = ca.jacobian(constraints, qd)  # 5 x 8, linear in qd
    independent, dependent = [3, 5, 6], [0, 1, 2, 4, 7]
    s = ca.SX.zeros(8, 3)
    s[independent, :] = ca.SX.eye(3)
    s[dependent, :] = -ca.solve(a[:, dependent], a[:, independent])
    momentum = ca.gradient(kinetic, qd)
    mass_matrix = ca.jacobian(momentum, qd)
    velocity_terms = (ca.jtimes(momentum, q, qd) - ca.gradient(kinetic, q)
                      + ca.gradient(potential, q))
    forces = ca.vertcat(0, 0, 0, u[0], 0, u[1], 0, 0)
    qdot = s @ w
    sdot_w = ca.jtimes(qdot, q, qdot)
    rest = s.T @ (forces - velocity_terms - mass_matrix @ sdot_w)
    reduced = s.T @ mass_matrix @ s
    wdot = ca.solve(reduced, rest)
    xdot = ca.vertcat(qdot, wdot)
    return ca.substitute(xdot, qd, qdot)


def function(name="whipple_sx"):
    """F as a CasADi Function of SX, with the inputs and output named as hamel's, its common
    subexpressions merged (CasADi's `cse`: 13,567 operations instead of 19,135)."""
    x, u, p = ca.SX.sym("x", 11), ca.SX.sym("u", 2), ca.SX.sym("p", 26)
    return ca.Function(name, [x, u, p], [rhs(x, u, p)], ["x", "u", "p"], ["xdot"],
                       {"cse": True})


def pitch(phi, delta, p):
    """The rear frame's pitch theta at which the front wheel touches the ground (its
    lowest point at z = 0), by Newton's method from 0."""
    theta = ca.SX.sym("theta")
    q = ca.vertcat(0, 0, 0, phi, theta, delta, 0, 0)
    front_wheel = bodies(q, p)[3]
    height = front_contact(front_wheel[2], front_wheel[3], p[22])[2]
    solve = ca.rootfinder("pitch", "newton", ca.Function("h", [theta], [height]),
                          {"abstol": 1e-15})
    return float(solve(0.0))
