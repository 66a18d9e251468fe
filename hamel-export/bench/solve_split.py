"""Where the parking solve's time goes: IPOPT's statistics of the NLP functions (wall time of
the objective, the constraints, their Jacobian and the Hessian of the Lagrangian, and the
number of calls of each) for hamel's functions and CasADi's generated C of the SX robot,
interleaved, median of the solves:

    python solve_split.py OUTDIR [--repeat 7] [--constant-parameters]

With --solves K --only MODEL, solves K times on that model alone, after a first solve, and
prints nothing: what solve_instructions.sh counts under callgrind.
"""

import argparse
import pathlib
import statistics
import sys
import tempfile

import casadi as ca

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "nmpc"))
import robot_parking  # noqa: E402

FUNCTIONS = ["nlp_f", "nlp_g", "nlp_grad_f", "nlp_jac_g", "nlp_hess_l"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("outdir", help="where libmobile_robot.so is")
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--constant-parameters", action="store_true")
    parser.add_argument("--solves", type=int)
    parser.add_argument("--only", choices=["hamel", "sx-c"])
    args = parser.parse_args()
    library = pathlib.Path(args.outdir) / "libmobile_robot.so"
    with tempfile.TemporaryDirectory() as tmp:
        models = {}
        if args.only in (None, "hamel"):
            models["hamel"] = ca.external("mobile_robot_f", str(library))
        if args.only in (None, "sx-c"):
            directions = robot_parking.forward_directions(library)
            models["sx-c"] = robot_parking.casadi_generated_c(tmp, directions)
        if args.solves is not None:
            for f in models.values():
                for _ in range(args.solves + 1):
                    robot_parking.solve(f, args.constant_parameters)
            return
        runs = {name: [] for name in models}
        for _ in range(args.repeat):
            for name, f in models.items():
                stats = {}
                seconds = robot_parking.solve(f, args.constant_parameters, stats)[3]
                runs[name].append((seconds, stats))
    print(f"{args.repeat} interleaved solves each; wall time in ms, median (calls)")
    print(f"{'function':12}" + "".join(f"{name:>18}" for name in runs))
    rows = [("solve", lambda r: r[0])]
    rows += [(k, lambda r, k=k: r[1][f"t_wall_{k}"]) for k in FUNCTIONS]
    rows += [("the rest", lambda r: r[0] - sum(r[1][f"t_wall_{k}"] for k in FUNCTIONS))]
    for label, value in rows:
        cells = []
        for name, solves in runs.items():
            ms = 1e3 * statistics.median(value(r) for r in solves)
            calls = solves[-1][1].get(f"n_call_{label}")
            cells.append(f"{ms:10.1f}" + (f" ({calls:>4})" if calls is not None else " " * 7))
        print(f"{label:12}" + "".join(f"{c:>18}" for c in cells))


if __name__ == "__main__":
    main()
