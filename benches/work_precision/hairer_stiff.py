"""Hairer's own codes on the stiff test set of benches/work_precision.rs: RADAU5 (Hairer &
Wanner's C translation shipped in Assimulo) and RODAS (their Fortran, compiled into
Assimulo's wheel), through Assimulo's Radau5ODE and RodasODE (PyPI `assimulo-testing`, the
only registry package with a prebuilt wheel of them; `pyradau13` wraps RADAU, the
variable-order code, and ships no wheel). The same problems, tolerances, exact Jacobians,
mixed error and batches as scipy_stiff.py (whose problem definitions it imports). Counts:
Assimulo's nfcns, njacs, nsteps, nerrfails; its nlus counts RADAU5's real and complex
factorizations of a step as one, so they are doubled here to count as scipy and hamel do.

    python hairer_stiff.py OUT.csv ROUND PROBLEM
"""
import os
import sys

import numpy as np
from assimulo.problem import Explicit_Problem
from assimulo.solvers import Radau5ODE, RodasODE

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scipy_stiff  # noqa: E402

SOLVERS = [("Hairer RADAU5", Radau5ODE, 2), ("Hairer RODAS", RodasODE, 1)]


def main(out, round_number, problem_name):
    problems = {p[0]: p for p in [scipy_stiff.rober(), scipy_stiff.vdpol(), scipy_stiff.hires(),
                                  scipy_stiff.orego(), scipy_stiff.pollu()]}
    if problem_name not in problems:
        sys.exit(f"hairer_stiff.py: no problem {problem_name!r}: one of {list(problems)}")
    name, f, jac, y0, t_end, ratio, ref = problems[problem_name]
    ref = np.array(ref)

    def run(solver, rtol):
        problem = Explicit_Problem(lambda t, y: np.asarray(f(t, y), dtype=float),
                                   np.array(y0, dtype=float), 0.0)
        problem.jac = lambda t, y: np.asarray(jac(t, y), dtype=float)
        sim = solver(problem)
        sim.verbosity = 50
        sim.report_continuously = False
        sim.rtol = rtol
        sim.atol = ratio * rtol
        sim.usejac = True
        sim.maxsteps = 10**7
        _, y = sim.simulate(t_end, 1)
        return np.asarray(y[-1]), sim.statistics

    rows = []
    for label, solver, lu_per_factorization in SOLVERS:
        run(solver, scipy_stiff.TOLERANCES[1])
        for rtol in scipy_stiff.TOLERANCES:
            try:
                (y, stats), wall = scipy_stiff.batch(lambda: run(solver, rtol))
            except Exception as e:  # a failed run: no point on its curve
                print(f"{name} {label} {rtol:g}: {e}", file=sys.stderr)
                continue
            error = float(np.max(np.abs(y - ref) / (np.abs(ref) + ratio)))
            rows.append(f"{round_number},{name},{label},{rtol:e},{error:e},{int(stats['nsteps'])},"
                        f"{int(stats['nerrfails'])},{int(stats['nfcns'])},{int(stats['njacs'])},"
                        f"{lu_per_factorization * int(stats['nlus'])},{wall:e}")
    header = not os.path.exists(out)
    with open(out, "a") as handle:
        if header:
            handle.write("round,problem,solver,rtol,error,steps,rejected,evaluations,jacobians,"
                         "factorizations,wall\n")
        handle.write("".join(row + "\n" for row in rows))


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3])
