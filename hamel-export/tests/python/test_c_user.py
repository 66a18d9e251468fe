"""A plain C program includes the exported header, links the library and integrates the robot
with a fixed-step RK4 of its own: its trajectory is hamel's RK4 run of the same robot
(`cargo run --release --example mobile_robot -- --integrator rk4`), to rounding."""

import csv
import os
import pathlib
import shutil
import subprocess

import numpy as np

REPOSITORY = pathlib.Path(__file__).resolve().parents[3]
STATE = ["x", "y", "alpha", "phi1", "phi2", "w3", "w4", "w5"]
X0 = [0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 0.5, 0.2]
TAU = [0.1, 0.05]
T_END, STEP = 2.0, 0.01


def test_a_c_program_integrates_the_robot_as_hamel_does(outdir, tmp_path):
    compiler = shutil.which("cc")
    assert compiler, "a C compiler (cc) is needed"
    program = tmp_path / "rk4"
    subprocess.run([compiler, "-O2", "-std=c99", "-Wall", "-Werror", "-I", str(outdir),
                    str(REPOSITORY / "hamel-export/tests/c/rk4.c"), "-L", str(outdir),
                    "-lmobile_robot", f"-Wl,-rpath,{outdir}", "-o", str(program)], check=True)
    run = subprocess.run([str(program), str(T_END), str(STEP), *map(str, TAU), *map(str, X0)],
                         check=True, capture_output=True, text=True)
    # The C program checks that a wrong length is refused, and says so.
    assert "`x` has 7 entries; the model's has 8" in run.stderr, run.stderr
    c = np.array([[float(v) for v in row] for row in csv.reader(run.stdout.splitlines()[1:])])

    rust_csv = tmp_path / "robot.csv"
    options = []
    for name, value in zip(STATE, X0):
        options += [f"--{name}", str(value)]
    command = ["cargo", "run", "--quiet", "--release", "--example", "mobile_robot", "--",
               "--integrator", "rk4", "--step", str(STEP), "--dt-out", str(STEP),
               "--t-end", str(T_END), "--tau1", str(TAU[0]), "--tau2", str(TAU[1]),
               "--out", str(rust_csv), *options]
    subprocess.run(command, check=True, cwd=REPOSITORY, capture_output=True,
                   env=dict(os.environ))
    with open(rust_csv) as f:
        rows = list(csv.DictReader(f))
    rust = np.array([[float(r["t"])] + [float(r[n]) for n in STATE] for r in rows])

    assert c.shape == rust.shape, (c.shape, rust.shape)
    # The same method, step and right-hand side: equal to the rounding of the RK4 sums.
    scale = np.max(np.abs(rust), axis=0) + 1.0
    difference = np.max(np.abs(c - rust) / scale)
    print(f"largest difference, C RK4 against hamel's: {difference:.1e}")
    assert difference < 1e-12, difference
