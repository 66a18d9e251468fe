"""Optimal control on hamel's exact derivatives: the paper's robot parked by its wheel torques.

The robot (hamel's `mobile_robot`, a body balancing on its axle like an inverted pendulum)
starts at rest, upright, at the origin heading along x, and must come to rest upright at
(1 m, 1 m) heading along y, with each wheel torque bounded by TAU_MAX, in T seconds:
minimum sum of squared torques, by multiple shooting (N intervals, RK4 steps within each) in
CasADi's Opti with IPOPT and its exact Hessian (`hessian_approximation = exact`).

The same problem is solved three times, on three implementations of the same right-hand side:

- `hamel`: hamel's CasADi external functions (libmobile_robot.so from
  `cargo run --release --example export -- casadi mobile_robot OUTDIR`), whose Jacobian and
  second derivatives are straight-line code `#[hamel_system]` emits (hamel-export's feature
  `compiled`, which the example turns on);
- `sx`: the robot written in CasADi's SX from the paper's equations (tests/python/robot_sx.py),
  evaluated by CasADi's virtual machine;
- `sx-c`: the same SX model through CasADi's own C code generation (the function and the
  derivative functions CasADi asks for, `jac_`, `fwd1_`, `adj1_`, `jac_adj1_`, and the
  `fwd<N>_` of as many directions as hamel's library exports), compiled by `cc -O3` and
  loaded as an external, as CasADi users deploy models.

    python robot_parking.py OUTDIR [--repeat 5] [--figure robot_parking.svg] [--json timings.json]
                                   [--baseline OTHER_OUTDIR] [--constant-parameters]

prints, for each, the solve's iterations, the wall time per solve and per IPOPT iteration
(median of --repeat solves, interleaved), and the largest difference of the optimal states
from hamel's; writes the figure of the path and torques.
"""

import argparse
import ctypes
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import casadi as ca
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tests" / "python"))
import robot_sx  # noqa: E402

N = 40  # shooting intervals
T = 4.0  # s
SUBSTEPS = 2  # RK4 steps per interval
TAU_MAX = 0.4  # N m, each wheel
TARGET = (1.0, 1.0, np.pi / 2)  # x, y (m), heading (rad)
R, B = robot_sx.DEFAULTS[5], robot_sx.DEFAULTS[6]


def step_function(f, parameters=None):
    """One shooting interval of RK4 steps over the right-hand side `f(x, u, p)`: a function of
    (x, u, p), or of (x, u) with `parameters` its constants."""
    x, u = ca.MX.sym("x", 8), ca.MX.sym("u", 2)
    p = ca.MX.sym("p", 9) if parameters is None else ca.DM(parameters)
    h = T / N / SUBSTEPS
    y = x
    for _ in range(SUBSTEPS):
        k1 = f(y, u, p)
        k2 = f(y + h / 2 * k1, u, p)
        k3 = f(y + h / 2 * k2, u, p)
        k4 = f(y + h * k3, u, p)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    if parameters is not None:
        return ca.Function("interval", [x, u], [y])
    return ca.Function("interval", [x, u, p], [y])


def problem(f, constant_parameters=False):
    """The parking problem over the right-hand side `f`; returns the Opti and its variables.

    The parameters are an input of the shooting interval's function, given as constants
    (CasADi then asks the model for every derivative by them too, `jac_adj1_`'s blocks by p
    among them, which the NLP does not use), or with `constant_parameters` constants inside
    it (CasADi asks for none)."""
    p = ca.DM(robot_sx.DEFAULTS)
    opti = ca.Opti()
    X = opti.variable(8, N + 1)
    U = opti.variable(2, N)
    opti.subject_to(X[:, 0] == 0)
    if constant_parameters:
        interval = step_function(f, robot_sx.DEFAULTS)

        def step(x, u, _):
            return interval(x, u)
    else:
        step = step_function(f)
    for k in range(N):
        opti.subject_to(X[:, k + 1] == step(X[:, k], U[:, k], p))
    heading = R / B * (X[3, N] - X[4, N])
    opti.subject_to(X[0, N] == TARGET[0])
    opti.subject_to(X[1, N] == TARGET[1])
    opti.subject_to(heading == TARGET[2])
    opti.subject_to(X[2, N] == 0)  # upright
    opti.subject_to(X[5:8, N] == 0)  # at rest
    opti.subject_to(opti.bounded(-TAU_MAX, ca.vec(U), TAU_MAX))
    opti.subject_to(opti.bounded(-0.6, X[2, :], 0.6))  # the body's pitch stays moderate
    opti.minimize(T / N * ca.sumsqr(U))
    # A start that moves along the straight line, so that IPOPT starts from the same point
    # for every model.
    s = np.linspace(0.0, 1.0, N + 1)
    opti.set_initial(X[0, :], TARGET[0] * s)
    opti.set_initial(X[1, :], TARGET[1] * s)
    opti.solver(
        "ipopt",
        {"print_time": False},
        {"hessian_approximation": "exact", "print_level": 0, "tol": 1e-10, "max_iter": 500},
    )
    return opti, X, U


def solve(f, constant_parameters=False, stats=None):
    """Solve once: (states, torques, iterations, seconds); IPOPT's statistics into `stats`
    (a dict) if given."""
    opti, X, U = problem(f, constant_parameters)
    start = time.perf_counter()
    sol = opti.solve()
    seconds = time.perf_counter() - start
    iterations = sol.stats()["iter_count"]
    if stats is not None:
        stats.update(sol.stats())
    return np.array(sol.value(X)), np.array(sol.value(U)), iterations, seconds


def forward_directions(library):
    """The N > 1 of the `fwd<N>_mobile_robot_f` that hamel's library exports: CasADi calls
    them for a batch of exactly N forward directions through a call of the model."""
    exported = ctypes.CDLL(str(library))
    return [n for n in (2, 4, 8, 16, 32, 64) if hasattr(exported, f"fwd{n}_mobile_robot_f")]


def casadi_generated_c(directory, directions=(2, 4, 8)):
    """The SX model with the derivative functions CasADi loads, generated as C by CasADi and
    compiled by cc -O3: an external function like hamel's, of CasADi's own making, with the
    same multi-direction forward functions `fwd<N>_` as hamel's library (`directions`), so
    that CasADi makes the same calls of both."""
    f = robot_sx.function("robot_sx")
    cg = ca.CodeGenerator("robot_sx.c", {"with_header": False})
    derivatives = [f.jacobian(), f.forward(1), f.reverse(1), f.reverse(1).jacobian()]
    for g in [f] + derivatives + [f.forward(n) for n in directions]:
        cg.add(g)
    source = pathlib.Path(directory) / "robot_sx.c"
    cg.generate(str(directory) + "/")
    library = pathlib.Path(directory) / "librobot_sx.so"
    subprocess.run(["cc", "-O3", "-fPIC", "-shared", str(source), "-o", str(library), "-lm"],
                   check=True)
    return ca.external("robot_sx", str(library))


def figure(path, states, torques):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.linspace(0.0, T, N + 1)
    heading = R / B * (states[3] - states[4])
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
    a.plot(states[0], states[1], color="tab:blue", label="axle centre")
    # The axle, drawn every fourth interval: the heading is perpendicular to it.
    for k in range(0, N + 1, 4):
        dx, dy = -np.sin(heading[k]) * B / 2, np.cos(heading[k]) * B / 2
        a.plot([states[0][k] - dx, states[0][k] + dx], [states[1][k] - dy, states[1][k] + dy],
               color="tab:gray", linewidth=1)
    a.plot([0, TARGET[0]], [0, TARGET[1]], "o", color="black")
    a.set_xlabel("x (m)")
    a.set_ylabel("y (m)")
    a.set_aspect("equal")
    a.set_title("path of the axle (gray: the axle), (0, 0) to (1, 1)")
    a.legend(loc="upper left")
    b.step(t[:-1], torques[0], where="post", label="tau1 (right wheel)")
    b.step(t[:-1], torques[1], where="post", label="tau2 (left wheel)")
    b.plot(t, states[2], color="tab:green", label="pitch alpha (rad)")
    b.axhline(TAU_MAX, color="gray", linestyle=":")
    b.axhline(-TAU_MAX, color="gray", linestyle=":")
    b.set_xlabel("t (s)")
    b.set_ylabel("torque (N m), pitch (rad)")
    b.set_title(f"wheel torques, bounded by {TAU_MAX} N m")
    b.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("outdir", help="where libmobile_robot.so is")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--figure")
    parser.add_argument("--json")
    parser.add_argument("--constant-parameters", action="store_true",
                        help="the parameters constants inside the shooting interval's function "
                        "(CasADi then asks for no derivative by them), not an input of it")
    parser.add_argument("--baseline", help="the OUTDIR of another build of hamel's library: "
                        "solved too (`hamel-b`), with CasADi's C given its fwd<N>_ (`sx-c-b`)")
    args = parser.parse_args()
    library = pathlib.Path(args.outdir) / "libmobile_robot.so"
    with tempfile.TemporaryDirectory() as tmp:
        models = {
            "hamel": ca.external("mobile_robot_f", str(library)),
            "sx": robot_sx.function(),
            "sx-c": casadi_generated_c(tmp, forward_directions(library)),
        }
        if args.baseline:
            baseline = pathlib.Path(args.baseline) / "libmobile_robot.so"
            other = pathlib.Path(tmp) / "baseline"
            other.mkdir()
            models["hamel-b"] = ca.external("mobile_robot_f", str(baseline))
            models["sx-c-b"] = casadi_generated_c(other, forward_directions(baseline))
        runs = {name: [] for name in models}
        results = {}
        # Interleaved: one solve of each model per round.
        for _ in range(args.repeat):
            for name, f in models.items():
                states, torques, iterations, seconds = solve(f, args.constant_parameters)
                runs[name].append(seconds)
                results[name] = (states, torques, iterations)
    reference = results["hamel"][0]
    report = {}
    print(f"robot parking: N = {N} intervals, {SUBSTEPS} RK4 steps each, T = {T} s, "
          f"|tau| <= {TAU_MAX} N m, IPOPT with the exact Hessian; {args.repeat} solves each")
    print(f"{'model':7} {'iterations':>10} {'solve (ms)':>11} {'per iteration (ms)':>19} "
          f"{'max |x - x_hamel|':>18}")
    for name in models:
        states, torques, iterations = results[name]
        seconds = statistics.median(runs[name])
        difference = float(np.max(np.abs(states - reference)))
        report[name] = {
            "iterations": iterations,
            "solve_ms": 1e3 * seconds,
            "per_iteration_ms": 1e3 * seconds / max(iterations, 1),
            "solves_ms": [1e3 * s for s in runs[name]],
            "max_state_difference": difference,
        }
        print(f"{name:7} {iterations:>10} {1e3 * seconds:>11.1f} "
              f"{1e3 * seconds / max(iterations, 1):>19.2f} {difference:>18.1e}")
    pairs = [("sx", "hamel"), ("sx-c", "hamel")]
    if args.baseline:
        pairs += [("sx-c-b", "hamel-b"), ("hamel-b", "hamel"), ("sx-c-b", "sx-c")]
    for other, base in pairs:
        ratios = sorted(a / b for a, b in zip(runs[other], runs[base]))
        p10, p90 = ratios[len(ratios) // 10], ratios[(9 * len(ratios)) // 10]
        print(f"solve time {other} / {base}: median {statistics.median(ratios):.2f} "
              f"(p10-p90 {p10:.2f}-{p90:.2f}, range {ratios[0]:.2f}-{ratios[-1]:.2f} "
              f"over {len(ratios)} rounds)")
    if args.figure:
        figure(args.figure, reference, results["hamel"][1])
    worst = max(report[name]["max_state_difference"] for name in models)
    if worst > 1e-6:
        sys.exit(f"the optima differ: largest state difference {worst:.1e} > 1e-6")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
