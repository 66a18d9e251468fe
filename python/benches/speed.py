"""A 10 s robot run called from Python against the same run in Rust, interleaved.

    python python/benches/speed.py [rounds]      (after `pip install ./python`)

Builds `cargo run --release --example robot_run` (python/benches/robot_run.rs: the README's
run with `Simulation`, as `cargo run --release --example mobile_robot` makes it) and keeps it
running; each round times a batch of runs in Rust (its own clock, in its process) and a
batch of `robot.simulate(x0, t_end=10.0, dt=0.01, method="dopri5", rtol=1e-9, atol=1e-12)`
in Python (the whole call: arguments, the run, the `Run` object), alternating which goes
first. Per round the ratio of the batches' medians; printed: the median ratio and p10–p90 over
the rounds, and the medians of the run times. The issue's bound is a ratio ≤ 1.05.
"""

import statistics
import subprocess
import sys
import time
from pathlib import Path

import hamel

HERE = Path(__file__).resolve().parent
PYTHON_DIR = HERE.parent


def quantile(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, max(0, round(q * (len(values) - 1))))]


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 41
    batch = 25
    subprocess.run(["cargo", "build", "--release", "--quiet", "--example", "robot_run"],
                   cwd=PYTHON_DIR, check=True)
    rust = subprocess.Popen([str(PYTHON_DIR / "target" / "release" / "examples" / "robot_run")],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    robot = hamel.models.MobileRobot()
    x0 = robot.state(alpha=0.3, w4=0.5, w5=0.4)

    def python_batch():
        times = []
        for _ in range(batch):
            start = time.perf_counter()
            robot.simulate(x0, t_end=10.0, dt=0.01, method="dopri5", rtol=1e-9, atol=1e-12)
            times.append(time.perf_counter() - start)
        return statistics.median(times)

    def rust_batch():
        rust.stdin.write(f"{batch}\n")
        rust.stdin.flush()
        return statistics.median(float(t) for t in rust.stdout.readline().split())

    python_batch(), rust_batch()  # warm both
    ratios, py_times, rs_times = [], [], []
    for r in range(rounds):
        if r % 2 == 0:
            p, s = python_batch(), rust_batch()
        else:
            s, p = rust_batch(), python_batch()
        ratios.append(p / s)
        py_times.append(p)
        rs_times.append(s)
    rust.stdin.close()
    rust.wait()
    print(f"robot, 10 s run (1001 samples, dopri5 rtol 1e-9 atol 1e-12), {rounds} rounds of {batch} runs each side")
    print(f"Python / Rust: median {statistics.median(ratios):.3f} (p10-p90 {quantile(ratios, 0.1):.3f}-{quantile(ratios, 0.9):.3f})")
    print(f"median run: Python {statistics.median(py_times) * 1e3:.3f} ms, Rust {statistics.median(rs_times) * 1e3:.3f} ms")


if __name__ == "__main__":
    main()
