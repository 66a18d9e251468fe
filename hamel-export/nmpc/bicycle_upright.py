"""NMPC on hamel's exact derivatives: the benchmark bicycle held upright by its steer torque.

The Whipple bicycle of Meijaard, Papadopoulos, Ruina and Schwab (Proc. R. Soc. A 463,
1955-1982, 2007; hamel's `whipple_bicycle`, the full nonlinear model: 11 states, the
benchmark's parameters) runs at SPEED = 2 m/s, below its weave speed (4.29 m/s): there the
uncontrolled bicycle is unstable (the paper's Table 2 at 2 m/s: the weave pair
2.682 +- 1.681i) and falls. It starts leaning LEAN rad; a nonlinear model predictive
controller holds it upright with the steer torque alone, bounded by TAU_MAX (the roll
torque, between the ground and the rear frame, is no actuator a rider has: it stays zero).

Each sampling period DT the controller solves, from the measured state, an optimal control
problem over a horizon of N periods: multiple shooting (one RK4 step per period) in CasADi's
Opti with IPOPT and its exact Hessian, on hamel's CasADi external functions
(libwhipple_bicycle.so from `cargo run --release --example export -- casadi whipple_bicycle
OUTDIR`: `whipple_bicycle_f` and its Jacobian and second derivatives, straight-line code
that `#[hamel_system]` emits), warm-started from the previous solution; it applies the
first torque for DT. The plant is not the controller's discretization: CasADi's CVODES
(BDF, tolerances 1e-10) integrates the same external right-hand side over each period.

Then the first period's problem (from the initial lean, cold start) is solved again, on
hamel's functions and on CasADi's own model of the bicycle (tests/python/whipple_sx.py: the
same bodies, the mechanics derived by CasADi in SX), interleaved: the same optimum, and the
time per solve and per IPOPT iteration. (The closed loop runs on hamel's functions alone:
on the SX model its 60 solves would take minutes.)

    python bicycle_upright.py OUTDIR [--repeat 1] [--figure bicycle.svg] [--json out.json]

checks, and exits nonzero when one fails:

1. the external function linearized by CasADi (`jac_whipple_bicycle_f`) about upright
   straight running at 0, 2 and 5 m/s has the lateral eigenvalues of the paper's Table 2
   (within 1e-12), and at 2 m/s an eigenvalue with a positive real part;
2. without control (torques zero, the same integrator) the lean grows past FALLEN rad;
3. with the controller every solve converges, the torque stays within its bound, and the lean
   is below SETTLED rad for the last second and never above BOUNDED (1.5 times the initial
   lean);
4. the first period's optimum on the SX model is hamel's (states within 1e-6).

It prints the eigenvalues, the open and closed loops' lean, the closed loop's time per solve
(median and p10-p90 over its solves, and IPOPT iterations) and the comparison; writes the
figure of lean, steer and steer torque over time.
"""

import argparse
import ctypes
import json
import pathlib
import statistics
import sys
import time

import casadi as ca
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tests" / "python"))
import whipple_sx  # noqa: E402

SPEED = 2.0  # m/s, below the weave speed 4.29 m/s
LEAN = 0.1  # rad, the initial lean (to the right)
DT = 0.05  # s, the sampling period
N = 20  # periods in the horizon (1 s)
T_END = 3.0  # s, the closed loop's run
TAU_MAX = 2.0  # N m, the steer torque's bound
FALLEN = 0.5  # rad: a lean the open loop must pass (it does well before T_END)
SETTLED = 1e-3  # rad: the closed loop's lean in its last second
BOUNDED = 1.5 * LEAN  # rad: the closed loop's largest lean (steering into the fall, the
# bicycle leans a little further first, as under a rider)

# The state, in the model's order (whipple_bicycle.h lists it with units).
STATE = ["x", "y", "psi", "phi", "theta", "delta", "theta_r", "theta_f",
         "roll_rate", "steer_rate", "rear_wheel_rate"]
PHI, DELTA, ROLL_RATE, STEER_RATE, WHEEL_RATE = (STATE.index(s) for s in (
    "phi", "delta", "roll_rate", "steer_rate", "rear_wheel_rate"))
NX, NU, NP = 11, 2, 26

# Table 2 of the paper (as printed): at 2 and 5 m/s the capsize mode, the weave pair and the
# castering mode; at rest, four real values.
TABLE_2 = {
    0.0: [-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393],
    2.0: [-3.07158645641514, 2.68234517512745 + 1.68066296590675j,
          2.68234517512745 - 1.68066296590675j, -8.67387984831735],
    5.0: [-0.32286642900409, -0.77534188219585 + 4.46486771378823j,
          -0.77534188219585 - 4.46486771378823j, -14.07838969279822],
}


class Bicycle:
    """hamel's exported bicycle: the external right-hand side and the default parameters."""

    def __init__(self, outdir):
        library = str(pathlib.Path(outdir) / "libwhipple_bicycle.so")
        self.f = ca.external("whipple_bicycle_f", library)
        sizes = [self.f.size1_in(i) for i in range(3)]
        if sizes != [NX, NU, NP]:
            sys.exit(f"{library}: inputs of sizes {sizes}, expected {[NX, NU, NP]}")
        c = ctypes.CDLL(library)
        c.whipple_bicycle_default_parameters.argtypes = [ctypes.POINTER(ctypes.c_double),
                                                          ctypes.c_size_t]
        p = np.zeros(NP)
        status = c.whipple_bicycle_default_parameters(
            p.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), NP)
        if status != 0:
            sys.exit(f"whipple_bicycle_default_parameters failed ({status})")
        self.p = p
        self.r_r = p[4]  # the rear wheel's radius (the struct's fifth field)

    def upright(self, speed, lean=0.0):
        """Upright (or leaning `lean`), steer straight, rolling forward at `speed`."""
        x = np.zeros(NX)
        x[PHI] = lean
        x[WHEEL_RATE] = -speed / self.r_r
        return x


def lateral_eigenvalues(bike, speed):
    """The eigenvalues of the linearization's lateral block (phi, delta and their rates) at
    upright straight running, from CasADi's Jacobian of the external function."""
    x, u = ca.MX.sym("x", NX), ca.MX.sym("u", NU)
    jac = ca.Function("A", [x, u], [ca.jacobian(bike.f(x, u, bike.p), x)])
    a = np.array(jac(bike.upright(speed), np.zeros(NU)))
    rows = [PHI, DELTA, ROLL_RATE, STEER_RATE]
    return np.linalg.eigvals(a[np.ix_(rows, rows)])


def check_eigenvalues(bike):
    worst = 0.0
    for speed, table in TABLE_2.items():
        ours = lateral_eigenvalues(bike, speed)
        key = lambda z: (round(z.real, 6), z.imag)  # noqa: E731
        ours, theirs = sorted(ours, key=key), sorted(np.array(table, dtype=complex), key=key)
        difference = max(abs(a - b) for a, b in zip(ours, theirs))
        worst = max(worst, difference)
        shown = ", ".join(f"{z.real:.5f}{z.imag:+.5f}i" if z.imag else f"{z.real:.5f}"
                          for z in ours)
        print(f"  v = {speed} m/s: {shown}  (Table 2: within {difference:.1e})")
    unstable = max(z.real for z in lateral_eigenvalues(bike, SPEED))
    return worst, unstable


def plant(bike):
    """One sampling period of the plant: CVODES on the external right-hand side."""
    x, u = ca.MX.sym("x", NX), ca.MX.sym("u", NU)
    ode = {"x": x, "p": u, "ode": bike.f(x, u, bike.p)}
    return ca.integrator("plant", "cvodes", ode, 0.0, DT, {"abstol": 1e-10, "reltol": 1e-10})


def open_loop(bike, period):
    """Torques zero from the initial lean until the bicycle has fallen past FALLEN (or T_END)."""
    x = bike.upright(SPEED, LEAN)
    states = [x]
    while len(states) <= round(T_END / DT) and abs(x[PHI]) <= FALLEN:
        x = np.array(period(x0=x, p=np.zeros(NU))["xf"]).ravel()
        states.append(x)
    return np.array(states)


def controller(f, p):
    """The optimal control problem on the right-hand side `f(x, u, p)` as a function:
    (x0, warm start) -> (torques, states). Minimizes lean, steer and their rates, and the
    steer torque, over the horizon."""
    h = DT
    x, u = ca.MX.sym("x", NX), ca.MX.sym("u", NU)
    k1 = f(x, u, p)
    k2 = f(x + h / 2 * k1, u, p)
    k3 = f(x + h / 2 * k2, u, p)
    k4 = f(x + h * k3, u, p)
    step = ca.Function("rk4", [x, u], [x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)])

    opti = ca.Opti()
    X = opti.variable(NX, N + 1)
    tau = opti.variable(1, N)
    x0 = opti.parameter(NX)
    opti.subject_to(X[:, 0] == x0)
    cost = 0
    for k in range(N):
        # The roll torque stays zero: the steer torque is the only input.
        opti.subject_to(X[:, k + 1] == step(X[:, k], ca.vertcat(0, tau[k])))
        cost += stage(X[:, k + 1], tau[k])
    opti.subject_to(opti.bounded(-TAU_MAX, tau, TAU_MAX))
    opti.minimize(cost)
    opti.solver(
        "ipopt",
        {"print_time": False},
        {"hessian_approximation": "exact", "print_level": 0, "tol": 1e-8,
         "max_iter": 100, "sb": "yes"},
    )
    return opti.to_function("nmpc", [x0, X, tau], [tau, X], ["x0", "X", "tau"],
                            ["tau_opt", "X_opt"])


def stage(x, tau):
    """The stage cost: the lean most, then the steer angle, the rates and the torque."""
    return (100 * x[PHI] ** 2 + 10 * x[DELTA] ** 2 + 1 * x[ROLL_RATE] ** 2
            + 0.1 * x[STEER_RATE] ** 2 + 0.1 * tau ** 2) * DT


class Loop:
    """One closed loop: a controller, the plant's state, and what the run recorded."""

    def __init__(self, bike, nmpc):
        self.nmpc = nmpc
        x = bike.upright(SPEED, LEAN)
        self.X_guess = np.tile(x[:, None], (1, N + 1))
        self.tau_guess = np.zeros((1, N))
        self.states, self.torques, self.seconds, self.iterations = [x], [], [], []

    def step(self, period):
        """Solve from the current state, apply the first torque for one period."""
        x = self.states[-1]
        start = time.perf_counter()
        tau_opt, X_opt = self.nmpc(x, self.X_guess, self.tau_guess)
        self.seconds.append(time.perf_counter() - start)
        stats = self.nmpc.stats()
        if not stats["success"]:
            sys.exit(f"the NMPC solve at t = {DT * len(self.torques):.2f} s failed: "
                     f"{stats['return_status']}")
        self.iterations.append(stats["iter_count"])
        tau_opt, X_opt = np.array(tau_opt), np.array(X_opt)
        self.torques.append(float(tau_opt[0, 0]))
        x = np.array(period(x0=x, p=[0.0, self.torques[-1]])["xf"]).ravel()
        self.states.append(x)
        # Warm start: the solution shifted by one period, its last column repeated.
        self.X_guess = np.hstack([X_opt[:, 1:], X_opt[:, -1:]])
        self.X_guess[:, 0] = x
        self.tau_guess = np.hstack([tau_opt[:, 1:], tau_opt[:, -1:]])


def closed_loop(bike, period, nmpc):
    loop = Loop(bike, nmpc)
    for _ in range(round(T_END / DT)):
        loop.step(period)
    return loop


def first_solves(bike, controllers, repeat):
    """The first period's problem (from the initial lean, the same cold start) solved on
    each model `repeat` times, interleaved: {name: (optimal states, iterations, seconds)}."""
    x = bike.upright(SPEED, LEAN)
    X_guess, tau_guess = np.tile(x[:, None], (1, N + 1)), np.zeros((1, N))
    results = {name: [] for name in controllers}
    for _ in range(repeat):
        for name, nmpc in controllers.items():
            start = time.perf_counter()
            _, X_opt = nmpc(x, X_guess, tau_guess)
            seconds = time.perf_counter() - start
            stats = nmpc.stats()
            if not stats["success"]:
                sys.exit(f"the first solve on {name} failed: {stats['return_status']}")
            results[name].append((np.array(X_opt), stats["iter_count"], seconds))
    return results


def figure(path, open_states, states, torques):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
    t_open = DT * np.arange(len(open_states))
    t = DT * np.arange(len(states))
    a.plot(t_open, open_states[:, PHI], color="tab:red", label="lean, no control (falls)")
    a.plot(t, states[:, PHI], color="tab:blue", label="lean, NMPC")
    a.plot(t, states[:, DELTA], color="tab:green", label="steer angle, NMPC")
    a.set_xlim(0, T_END)
    a.set_xlabel("t (s)")
    a.set_ylabel("angle (rad)")
    a.set_title(f"benchmark bicycle at {SPEED} m/s, leaning {LEAN} rad at t = 0")
    a.legend(loc="lower left", fontsize=8)
    b.step(t[:-1], torques, where="post", color="tab:purple", label="steer torque")
    b.axhline(TAU_MAX, color="gray", linestyle=":")
    b.axhline(-TAU_MAX, color="gray", linestyle=":")
    b.set_xlabel("t (s)")
    b.set_ylabel("torque (N m)")
    b.set_title(f"steer torque, bounded by {TAU_MAX} N m")
    b.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def percentile(values, q):
    return float(np.percentile(values, q))


def linearization_report(bike, failures):
    print("lateral eigenvalues of the external function's linearization (1/s):")
    worst, unstable = check_eigenvalues(bike)
    if worst > 1e-12:
        failures.append(f"eigenvalues differ from Table 2 by {worst:.1e} > 1e-12")
    if unstable <= 0:
        failures.append(f"at {SPEED} m/s the largest real part is {unstable}, not positive")
    return {"eigenvalue_difference": worst}


def open_loop_report(falling, failures):
    fallen_at = DT * (len(falling) - 1)
    if abs(falling[-1, PHI]) > FALLEN:
        print(f"no control: the lean passes {FALLEN} rad at t = {fallen_at:.2f} s")
    else:
        print(f"no control: the lean is {falling[-1, PHI]:.3f} rad at {T_END} s")
        failures.append(f"the uncontrolled bicycle did not fall ({falling[-1, PHI]:.3f} rad)")
    return {"fallen_at_s": fallen_at}


def closed_loop_report(loop, failures):
    states, torques = np.array(loop.states), np.array(loop.torques)
    t = DT * np.arange(len(states))
    last_second = float(np.max(np.abs(states[t >= T_END - 1.0, PHI])))
    largest = float(np.max(np.abs(states[:, PHI])))
    largest_torque = float(np.max(np.abs(torques)))
    ms = [1e3 * s for s in loop.seconds]
    print(f"NMPC ({len(torques)} solves, horizon {N * DT:.2f} s, |steer torque| <= {TAU_MAX} "
          f"N m): largest lean {largest:.4f} rad, |lean| <= {last_second:.1e} rad in the "
          f"last second, largest steer torque {largest_torque:.3f} N m")
    print(f"time per solve: median {statistics.median(ms):.1f} ms (p10-p90 "
          f"{percentile(ms, 10):.1f}-{percentile(ms, 90):.1f} ms), IPOPT iterations median "
          f"{statistics.median(loop.iterations)} (range {min(loop.iterations)}-"
          f"{max(loop.iterations)}); the first solve (cold start) {ms[0]:.1f} ms")
    if last_second > SETTLED:
        failures.append(f"the lean is {last_second:.1e} rad in the last second (> {SETTLED})")
    if largest > BOUNDED:
        failures.append(f"the lean grew to {largest:.4f} rad (> {BOUNDED} rad)")
    if largest_torque > TAU_MAX * (1 + 1e-6):
        failures.append(f"the steer torque reached {largest_torque} N m")
    return {"largest_lean": largest, "last_second_lean": last_second,
            "largest_torque": largest_torque, "solve_ms": ms, "iterations": loop.iterations}


def comparison_report(bike, repeat, failures):
    """The first period's problem on hamel's functions and on CasADi's SX model."""
    start = time.perf_counter()
    sx = controller(whipple_sx.function(), bike.p)
    built = time.perf_counter() - start
    results = first_solves(bike, {"hamel": controller(bike.f, bike.p), "sx": sx}, repeat)
    print(f"the first period's problem (cold start), {repeat} solves each, interleaved "
          f"(the SX problem built in {built:.1f} s):")
    print(f"{'model':6} {'iterations':>10} {'solve (ms)':>11} {'per iteration (ms)':>19} "
          f"{'max |X - X_hamel|':>18}")
    reference = results["hamel"][-1][0]
    report = {}
    for name, runs in results.items():
        states, iterations, _ = runs[-1]
        seconds = statistics.median(r[2] for r in runs)
        difference = float(np.max(np.abs(states - reference)))
        print(f"{name:6} {iterations:>10} {1e3 * seconds:>11.1f} "
              f"{1e3 * seconds / iterations:>19.2f} {difference:>18.1e}")
        report[name] = {"iterations": iterations, "solves_ms": [1e3 * r[2] for r in runs],
                        "max_state_difference": difference}
        if difference > 1e-6:
            failures.append(f"the optimum on {name} differs from hamel's by {difference:.1e}")
    ratios = [b[2] / a[2] for a, b in zip(results["hamel"], results["sx"])]
    print(f"solve time sx / hamel: median {statistics.median(ratios):.1f} "
          f"(range {min(ratios):.1f}-{max(ratios):.1f} over {len(ratios)} rounds)")
    return report


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("outdir", help="where libwhipple_bicycle.so is")
    parser.add_argument("--repeat", type=int, default=1,
                        help="solves of the first period's problem on each model")
    parser.add_argument("--figure")
    parser.add_argument("--json")
    args = parser.parse_args()
    bike = Bicycle(args.outdir)
    failures = []
    report = linearization_report(bike, failures)
    period = plant(bike)
    falling = open_loop(bike, period)
    report.update(open_loop_report(falling, failures))
    loop = closed_loop(bike, period, controller(bike.f, bike.p))
    report["closed_loop"] = closed_loop_report(loop, failures)
    report["first_solve"] = comparison_report(bike, args.repeat, failures)
    if args.figure:
        figure(args.figure, falling, np.array(loop.states), np.array(loop.torques))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(report, indent=1))
    if failures:
        sys.exit("; ".join(failures))


if __name__ == "__main__":
    main()
