"""Whether one solver needs more evaluations than another at equal achieved error because of its
method or because of where its points fall: hamel's Radau5 (or another of hamel's solvers, by
the `at` mode of benches/work_precision.rs) and scipy's Radau (scipy_stiff.py's problems, the
exact Jacobian; without it for hamel's "(differences)" runs) on one problem at PER tolerances
per decade, not the eight of run.sh. The achieved error of either is not a smooth function of
rtol (HIRES: scipy's falls 83 times from rtol 1e-4 to 1e-5), so a ratio at one point of run.sh's
eight compares one solver's scatter with the other's. Here each curve's trend is fitted,
log10(evaluations) = a + b log10(error) by least squares, and printed: the ratio of the two
trends at errors both curves reach, and each curve's scatter about its trend (the residuals'
standard deviation, as a factor). hamel's rtol runs to 1e-13 (its local tolerance is
0.1 rtol^(2/3): `Radau5`), scipy's to 1e-10, as in run.sh. Untimed.

    target/work_precision/venv/bin/python benches/work_precision/trend.py PROBLEM [SOLVER] [PER]

with SOLVER one of hamel's labels ("hamel Radau5" by default) and PER 8 by default; the venv
is run.sh's (numpy and scipy).
"""
import json
import os
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scipy_stiff  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def hamel_binary():
    """The work_precision bench's executable, built if it is not."""
    out = subprocess.run(
        ["cargo", "bench", "-q", "-p", "hamel-benches", "--bench", "work_precision", "--no-run",
         "--message-format=json"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        m = json.loads(line)
        if m.get("target", {}).get("name") == "work_precision" and m.get("executable"):
            return m["executable"]
    sys.exit("trend.py: no work_precision executable")


def grid(tightest, per):
    """rtol from 1e-3 down to `tightest`, `per` to a decade."""
    n = int(round(np.log10(1e-3 / tightest) * per))
    return [1e-3 * 10 ** (-k / per) for k in range(n + 1)]


def hamel_points(problem, solver, per):
    tightest = 1e-13 if "Radau5" in solver else 1e-10
    args = [hamel_binary(), "at", problem, solver] + [f"{t:e}" for t in grid(tightest, per)]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    rows = [line.split(",") for line in out.splitlines()[1:]]
    # round,problem,solver,rtol,error,steps,rejected,evaluations,...
    return [(float(r[4]), float(r[7])) for r in rows]


def scipy_points(problem, differenced, per):
    problems = {p[0]: p for p in [scipy_stiff.rober(), scipy_stiff.vdpol(), scipy_stiff.hires(),
                                  scipy_stiff.orego(), scipy_stiff.pollu()]}
    _, f, jac, y0, t_end, ratio, ref = problems[problem]
    ref = np.array(ref)
    calls = [0]

    def counted(t, y):
        calls[0] += 1
        return f(t, y)
    points = []
    for rtol in grid(1e-10, per):
        calls[0] = 0
        sol = solve_ivp(counted, (0.0, t_end), y0, method="Radau", rtol=rtol, atol=ratio * rtol,
                        jac=None if differenced else jac, t_eval=[t_end])
        if sol.success:
            error = float(np.max(np.abs(sol.y[:, -1] - ref) / (np.abs(ref) + ratio)))
            # Every call of the right-hand side (num_jac's too), as hamel counts them.
            points.append((error, calls[0]))
    return points


def trend(points):
    """(a, b, scatter): log10 evaluations = a + b log10 error, and the residuals' deviation."""
    e = np.log10([p[0] for p in points])
    n = np.log10([p[1] for p in points])
    b, a = np.polyfit(e, n, 1)
    return a, b, float(np.std(n - (a + b * e))), (e.min(), e.max())


def main():
    problem = sys.argv[1] if len(sys.argv) > 1 else "HIRES"
    solver = sys.argv[2] if len(sys.argv) > 2 else "hamel Radau5"
    per = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    ours = trend(hamel_points(problem, solver, per))
    theirs = trend(scipy_points(problem, "(differences)" in solver, per))
    lo, hi = max(ours[3][0], theirs[3][0]), min(ours[3][1], theirs[3][1])
    scipy_label = "scipy Radau" + (" (differences)" if "(differences)" in solver else "")
    print(f"{problem}, {per} tolerances per decade: {solver} / {scipy_label}")
    print(f"  scatter about the trend: {solver} x{10 ** ours[2]:.2f}, "
          f"{scipy_label} x{10 ** theirs[2]:.2f} (one standard deviation)")
    print(f"  slopes (log evaluations per log error): {ours[1]:.3f}, {theirs[1]:.3f}")
    for k in range(int(np.ceil(-hi)), int(np.floor(-lo)) + 1):
        ratio = 10 ** ((ours[0] - ours[1] * k) - (theirs[0] - theirs[1] * k))
        print(f"  evaluations at error 1e-{k}, trend over trend: {ratio:.3f}")


if __name__ == "__main__":
    main()
