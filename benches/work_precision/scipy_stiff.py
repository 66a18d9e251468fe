"""scipy's Radau, BDF and LSODA on the stiff test set of benches/work_precision.rs: the same
problems, spans, tolerances (atol = ATOL_RATIO * rtol), exact Jacobians and mixed error against
the Bari Test Set's references (tests/validation/tests/common/stiff_problems.rs has the
definitions and the sources); and Radau without the Jacobian ("scipy Radau (differences)"),
scipy's num_jac differencing it. One round of run.sh on one problem: each method at each
tolerance, a batch of runs of at least BATCH_SECONDS (after an untimed warm-up run; see
benches/work_precision.rs), one CSV row per batch appended to OUT.csv, the wall time the
batch's mean. The counts are scipy's nfev (right-hand sides; with the Jacobian given, as hamel
counts them then), njev and nlu (Radau's real and complex factorizations counted as two, as
hamel counts them too). Without the Jacobian scipy's nfev leaves out the evaluations num_jac
makes; the evaluations here are every call of the right-hand side, as hamel counts them.

    python scipy_stiff.py OUT.csv ROUND PROBLEM
"""
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

TOLERANCES = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
BATCH_SECONDS = 0.1


def batch(f):
    """f's last result and its mean wall time over a batch of at least BATCH_SECONDS."""
    runs, start = 0, time.perf_counter()
    while True:
        result = f()
        runs += 1
        elapsed = time.perf_counter() - start
        if elapsed >= BATCH_SECONDS:
            return result, elapsed / runs


def rober():
    def f(t, y):
        return [-0.04 * y[0] + 1e4 * y[1] * y[2],
                0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] ** 2,
                3e7 * y[1] ** 2]

    def jac(t, y):
        return [[-0.04, 1e4 * y[2], 1e4 * y[1]],
                [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
                [0.0, 6e7 * y[1], 0.0]]
    return ("ROBER", f, jac, [1.0, 0.0, 0.0], 1e11, 1e-6,
            [0.2083340149701255e-7, 0.8333360770334713e-13, 0.9999999791665050])


def vdpol():
    eps = 1e-6

    def f(t, y):
        return [y[1], ((1 - y[0] ** 2) * y[1] - y[0]) / eps]

    def jac(t, y):
        return [[0.0, 1.0], [(-2 * y[0] * y[1] - 1) / eps, (1 - y[0] ** 2) / eps]]
    return ("VDPOL", f, jac, [2.0, 0.0], 2.0, 1.0,
            [0.1706167732170483e1, -0.8928097010247975])


def hires():
    def f(t, y):
        f7 = 280 * y[5] * y[7] - 1.81 * y[6]
        return [-1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007,
                1.71 * y[0] - 8.75 * y[1],
                -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4],
                8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3],
                -1.745 * y[4] + 0.43 * (y[5] + y[6]),
                -280 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6],
                f7, -f7]

    def jac(t, y):
        j = np.zeros((8, 8))
        j[0, 0:3] = [-1.71, 0.43, 8.32]
        j[1, 0:2] = [1.71, -8.75]
        j[2, 2:5] = [-10.03, 0.43, 0.035]
        j[3, 1:4] = [8.32, 1.71, -1.12]
        j[4, 4:7] = [-1.745, 0.43, 0.43]
        j[5, 3:8] = [0.69, 1.71, -280 * y[7] - 0.43, 0.69, -280 * y[5]]
        j[6, 5:8] = [280 * y[7], -1.81, 280 * y[5]]
        j[7, 5:8] = [-280 * y[7], 1.81, -280 * y[5]]
        return j
    return ("HIRES", f, jac, [1, 0, 0, 0, 0, 0, 0, 0.0057], 321.8122, 1e-4,
            [0.7371312573325668e-3, 0.1442485726316185e-3, 0.5888729740967575e-4,
             0.1175651343283149e-2, 0.2386356198831331e-2, 0.6238968252742796e-2,
             0.2849998395185769e-2, 0.2850001604814231e-2])


def orego():
    def f(t, y):
        return [77.27 * (y[1] + y[0] * (1 - 8.375e-6 * y[0] - y[1])),
                (y[2] - (1 + y[0]) * y[1]) / 77.27,
                0.161 * (y[0] - y[2])]

    def jac(t, y):
        return [[77.27 * (1 - 2 * 8.375e-6 * y[0] - y[1]), 77.27 * (1 - y[0]), 0.0],
                [-y[1] / 77.27, -(1 + y[0]) / 77.27, 1 / 77.27],
                [0.161, 0.0, -0.161]]
    return ("OREGO", f, jac, [1.0, 2.0, 3.0], 360.0, 1.0,
            [0.1000814870318523e1, 0.1228178521549917e4, 0.1320554942846706e3])


# POLLU: rate constants, reactions (species indices, 1-based; 0 for none), stoichiometry,
# as in stiff_problems.rs (pollu.F).
K = [0.35, 0.266e2, 0.123e5, 0.86e-3, 0.82e-3, 0.15e5, 0.13e-3, 0.24e5, 0.165e5, 0.9e4,
     0.22e-1, 0.12e5, 0.188e1, 0.163e5, 0.48e7, 0.35e-3, 0.175e-1, 0.1e9, 0.444e12, 0.124e4,
     0.21e1, 0.578e1, 0.474e-1, 0.178e4, 0.312e1]
REACTIONS = [(1, 0), (2, 4), (5, 2), (7, 0), (7, 0), (7, 6), (9, 0), (9, 6), (11, 2), (11, 1),
             (13, 0), (10, 2), (14, 0), (1, 6), (3, 0), (4, 0), (4, 0), (16, 0), (16, 0),
             (17, 6), (19, 0), (19, 0), (1, 4), (19, 1), (20, 0)]
CONSUMED = [[1, 10, 14, 23, 24], [2, 3, 9, 12], [15], [2, 16, 17, 23], [3], [6, 8, 14, 20],
            [4, 5, 6], [], [7, 8], [12], [9, 10], [], [11], [13], [], [18, 19], [20], [],
            [21, 22, 24], [25]]
PRODUCED = [[2, 3, 9, 11, 12, 22, 25], [1, 21], [1, 17, 19, 22], [15], [4, 4, 6, 7, 13, 20],
            [3, 18, 18], [13], [4, 5, 6, 7], [], [7, 9], [8, 11], [9], [10], [12], [14], [16],
            [], [20], [23, 25], [24]]
STOICH = np.zeros((20, 25))
for s in range(20):
    for k in PRODUCED[s]:
        STOICH[s, k - 1] += 1
    for k in CONSUMED[s]:
        STOICH[s, k - 1] -= 1
A_IDX = np.array([a - 1 for a, _ in REACTIONS])
B_IDX = np.array([b - 1 for _, b in REACTIONS])
HAS_B = np.array([b != 0 for _, b in REACTIONS])
KV = np.array(K)


def pollu():
    def rates(y):
        second = np.where(HAS_B, y[B_IDX], 1.0)
        return KV * y[A_IDX] * second

    def f(t, y):
        return STOICH @ rates(np.asarray(y))

    def jac(t, y):
        y = np.asarray(y)
        dr = np.zeros((25, 20))
        for i in range(25):
            a, b = A_IDX[i], B_IDX[i]
            if HAS_B[i]:
                dr[i, a] += KV[i] * y[b]
                dr[i, b] += KV[i] * y[a]
            else:
                dr[i, a] += KV[i]
        return STOICH @ dr
    y0 = np.zeros(20)
    y0[[1, 3, 6, 7, 8, 16]] = [0.2, 0.04, 0.1, 0.3, 0.01, 0.007]
    ref = [0.5646255480022769e-1, 0.1342484130422339, 0.4139734331099427e-8,
           0.5523140207484359e-2, 0.2018977262302196e-6, 0.1464541863493966e-6,
           0.7784249118997964e-1, 0.3245075353396018, 0.7494013383880406e-2,
           0.1622293157301561e-7, 0.1135863833257075e-7, 0.2230505975721359e-2,
           0.2087162882798630e-3, 0.1396921016840158e-4, 0.8964884856898295e-2,
           0.4352846369330103e-17, 0.6899219696263405e-2, 0.1007803037365946e-3,
           0.1772146513969984e-5, 0.5682943292316392e-4]
    return ("POLLU", f, jac, y0, 60.0, 1e-4, ref)


def main(out, round_number, problem_name):
    problems = {p[0]: p for p in [rober(), vdpol(), hires(), orego(), pollu()]}
    if problem_name not in problems:
        sys.exit(f"scipy_stiff.py: no problem {problem_name!r}: one of {list(problems)}")
    name, f, jac, y0, t_end, ratio, ref = problems[problem_name]
    ref = np.array(ref)

    calls = [0]

    def counted(t, y):
        calls[0] += 1
        return f(t, y)

    def run(method, rtol):
        calls[0] = 0
        if method == "Radau (differences)":
            return solve_ivp(counted, (0.0, t_end), y0, method="Radau", rtol=rtol,
                             atol=ratio * rtol, t_eval=[t_end])
        return solve_ivp(f, (0.0, t_end), y0, method=method, rtol=rtol, atol=ratio * rtol,
                         jac=jac, t_eval=[t_end])

    run("Radau", TOLERANCES[1])
    rows = []
    for method in ["Radau", "BDF", "LSODA", "Radau (differences)"]:
        for rtol in TOLERANCES:
            sol, wall = batch(lambda: run(method, rtol))
            evaluations = calls[0] if method == "Radau (differences)" else sol.nfev
            if not sol.success:
                print(f"{name} {method} {rtol:g}: {sol.message}", file=sys.stderr)
                continue
            y = sol.y[:, -1]
            error = float(np.max(np.abs(y - ref) / (np.abs(ref) + ratio)))
            # solve_ivp reports no step counts.
            rows.append(f"{round_number},{name},scipy {method},{rtol:e},{error:e},,,{evaluations},"
                        f"{sol.njev},{sol.nlu},{wall:e}")
    header = not os.path.exists(out)
    with open(out, "a") as handle:
        if header:
            handle.write("round,problem,solver,rtol,error,steps,rejected,evaluations,jacobians,"
                         "factorizations,wall\n")
        handle.write("".join(row + "\n" for row in rows))


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3])
