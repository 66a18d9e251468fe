"""hamel against PyDy + scipy on the Chaplygin sleigh and the rolling disk, per run.

    bash python/benches/pydy.sh [rounds]

(the script makes its own virtual environment with pydy, sympy, scipy, cython and numpy from
PyPI, installs ./python into it and runs this file).

Each model is written in sympy.physics.mechanics from its textbook description, in minimal
generalized speeds with the rolling constraints embedded (Kane's method; the same reduced
ODE of 2n − p states as hamel's): the sleigh (x, y, θ; forward speed v, turning rate ω; the
blade a behind the centre of mass), the disk (x, y, yaw ψ, lean φ, spin θ about the axle;
their rates). PyDy generates the right-hand side with its Cython backend, in both of its
forms — the mass matrix and forcing solved numerically at each call, and the explicit
right-hand side M⁻¹f from sympy — and scipy's `solve_ivp` (RK45, Dormand–Prince 5(4), as
hamel's `dopri5`) integrates it at the same rtol and atol, sampled at the same times. The
faster of the two PyDy forms counts. Both runs start from the same state; their final states
are printed beside each other (they agree to the tolerance). Printed: per model, the median
time of a run on each side and the ratio, interleaved over rounds (median, p10–p90).
"""

import statistics
import sys
import time

import numpy as np
import sympy as sm
import sympy.physics.mechanics as me
from pydy.codegen.ode_function_generators import generate_ode_function
from scipy.integrate import solve_ivp

import hamel

RTOL, ATOL = 1e-9, 1e-12


def sleigh_equations():
    x, y, th = me.dynamicsymbols("x y theta")
    v, w = me.dynamicsymbols("v omega")
    m, inertia, a = sm.symbols("m inertia a")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [th, N.z])
    B.set_ang_vel(N, w * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", x * N.x + y * N.y)
    # The blade, a behind G, does not slide sideways: G's sideways speed is a ω.
    G.set_vel(N, v * B.x + a * w * B.y)
    kd = [x.diff() - (v * sm.cos(th) - a * w * sm.sin(th)),
          y.diff() - (v * sm.sin(th) + a * w * sm.cos(th)),
          th.diff() - w]
    body = me.RigidBody("sleigh", G, B, m, (me.inertia(B, 0, 0, inertia), G))
    kane = me.KanesMethod(N, q_ind=[x, y, th], u_ind=[v, w], kd_eqs=kd)
    kane.kanes_equations([body], [])
    return kane, [x, y, th], [v, w], [m, inertia, a]


def disk_equations():
    x, y, psi, phi, th = me.dynamicsymbols("x y psi phi theta")
    u1, u2, u3 = me.dynamicsymbols("u1 u2 u3")  # yaw, lean and spin rates
    m, r, g = sm.symbols("m r g")
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [psi, N.z])        # heading
    H = A.orientnew("H", "Axis", [phi, A.x])        # leaning
    D = H.orientnew("D", "Axis", [th, H.y])         # the disk, its axle H.y
    D.set_ang_vel(N, u1 * N.z + u2 * A.x + u3 * H.y)
    # The disk's material point at the contact is at rest; its centre is r above it in the
    # disk's plane. The contact point moves along the heading at r θ̇.
    P = me.Point("P")
    P.set_vel(N, 0)
    C = P.locatenew("C", r * H.z)
    C.v2pt_theory(P, N, D)
    kd = [x.diff() - r * u3 * sm.cos(psi), y.diff() - r * u3 * sm.sin(psi),
          psi.diff() - u1, phi.diff() - u2, th.diff() - u3]
    inertia = me.inertia(H, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4)
    body = me.RigidBody("disk", C, D, m, (inertia, C))
    kane = me.KanesMethod(N, q_ind=[x, y, psi, phi, th], u_ind=[u1, u2, u3], kd_eqs=kd)
    kane.kanes_equations([body], [(C, -m * g * N.z)])
    return kane, [x, y, psi, phi, th], [u1, u2, u3], [m, r, g]


def pydy_functions(kane, q, u, constants):
    """PyDy's Cython right-hand sides: with the mass matrix solved at each call, and explicit."""
    solved = generate_ode_function(kane.forcing_full, q, u, constants,
                                   mass_matrix=kane.mass_matrix_full, generator="cython")
    explicit_rhs = kane.mass_matrix_full.LUsolve(kane.forcing_full)
    explicit = generate_ode_function(explicit_rhs, q, u, constants, generator="cython")
    return {"mass matrix": solved, "explicit": explicit}


def pydy_run(rhs, y0, p, t_end, dt):
    t_eval = np.linspace(0.0, t_end, int(round(t_end / dt)) + 1)
    solution = solve_ivp(lambda t, y: rhs(y, t, p), (0.0, t_end), y0, method="RK45",
                         rtol=RTOL, atol=ATOL, t_eval=t_eval)
    assert solution.success, solution.message
    return solution.y[:, -1]


def quantile(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, max(0, round(q * (len(values) - 1))))]


def compare(name, model, equations, x0, t_end, dt, rounds):
    kane, q, u, constants = equations()
    p = np.array([model.parameters[str(c)] for c in constants])
    functions = pydy_functions(kane, q, u, constants)
    run = model.simulate(x0, t_end=t_end, dt=dt, rtol=RTOL, atol=ATOL)
    hamel_final = np.array([run[n][-1] for n in model.state_names])
    for form, rhs in functions.items():
        final = pydy_run(rhs, x0, p, t_end, dt)
        print(f"{name}, PyDy ({form}) final state {np.array2string(final, precision=9)}")
    print(f"{name}, hamel final state             {np.array2string(hamel_final, precision=9)}")
    times = {form: [] for form in functions}
    times["hamel"] = []
    for r in range(rounds):
        for form in (list(functions) + ["hamel"]) if r % 2 == 0 else (["hamel"] + list(functions)):
            start = time.perf_counter()
            if form == "hamel":
                model.simulate(x0, t_end=t_end, dt=dt, rtol=RTOL, atol=ATOL)
            else:
                pydy_run(functions[form], x0, p, t_end, dt)
            times[form].append(time.perf_counter() - start)
    best = min(functions, key=lambda f: statistics.median(times[f]))
    ratios = [pd / h for pd, h in zip(times[best], times["hamel"])]
    print(f"{name}: {t_end:g} s, samples every {dt:g} s, rtol {RTOL:g}, atol {ATOL:g}; "
          f"hamel {statistics.median(times['hamel']) * 1e3:.3f} ms a run, PyDy "
          + ", ".join(f"({f}) {statistics.median(times[f]) * 1e3:.1f} ms" for f in functions))
    print(f"{name}: PyDy ({best}) / hamel: median {statistics.median(ratios):.0f}x "
          f"(p10-p90 {quantile(ratios, 0.1):.0f}-{quantile(ratios, 0.9):.0f}), {rounds} rounds\n")


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 11
    sleigh = hamel.models.ChaplyginSleigh()
    compare("Chaplygin sleigh", sleigh, sleigh_equations,
            sleigh.state(theta=0.3, v=1.0, omega=2.0), 20.0, 0.01, rounds)
    disk = hamel.models.RollingDisk()
    compare("rolling disk", disk, disk_equations,
            disk.state(phi=0.2, yaw_rate=1.0, spin_rate=15.0), 5.0, 0.01, rounds)


if __name__ == "__main__":
    main()
