"""A 10 s robot run called from Python against the same run in Rust, interleaved.

    python python/benches/speed.py [rounds]      (after `pip install ./python`)

Builds `cargo run --release --example robot_run` (python/benches/robot_run.rs: the README's
run with `Simulation`, as `cargo run --release --example mobile_robot` makes it) and keeps it
running; each round times a batch of runs in Rust (its own clock, in its process) and a
batch of `robot.simulate(x0, t_end=10.0, dt=0.01, method="dopri5", rtol=1e-9, atol=1e-12)`
in Python (the whole call: arguments, the run, the `Run` object), alternating which goes
first. Per round the ratio of the batches' medians; printed: the median ratio and p10–p90 over
the rounds, and the medians of the run times, on two clocks: the wall clock, and the thread's
CPU clock (`time.thread_time`, `CLOCK_THREAD_CPUTIME_ID` in Rust), which leaves out the time
spent waiting for a core and so shows the cost on a machine loaded by other processes. A third
side, the Rust run with a progress callback that does nothing (`robot_run --progress`), shows
how much of the difference is the runtime's cost of watching a run (the Python package gives
each run a callback, to look for Ctrl-C). The issue's bound is a ratio ≤ 1.05.
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
    program = str(PYTHON_DIR / "target" / "release" / "examples" / "robot_run")
    rust = subprocess.Popen([program], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    watched = subprocess.Popen([program, "--progress"], stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, text=True)
    robot = hamel.models.MobileRobot()
    x0 = robot.state(alpha=0.3, w4=0.5, w5=0.4)

    def python_batch():
        times, cpu_times = [], []
        for _ in range(batch):
            cpu_start, start = time.thread_time(), time.perf_counter()
            robot.simulate(x0, t_end=10.0, dt=0.01, method="dopri5", rtol=1e-9, atol=1e-12)
            times.append(time.perf_counter() - start)
            cpu_times.append(time.thread_time() - cpu_start)
        return statistics.median(times), statistics.median(cpu_times)

    def rust_batch(process):
        process.stdin.write(f"{batch}\n")
        process.stdin.flush()
        wall = statistics.median(float(t) for t in process.stdout.readline().split())
        cpu = statistics.median(float(t) for t in process.stdout.readline().split())
        return wall, cpu

    python_batch(), rust_batch(rust), rust_batch(watched)  # warm them
    wall, cpu = Sides("Python"), Sides("Python")
    watch_wall, watch_cpu = Sides("Rust with a progress callback"), Sides("Rust with a progress callback")
    for r in range(rounds):
        # The three sides in an order that turns each round.
        sides = [lambda: ("p", python_batch()), lambda: ("s", rust_batch(rust)),
                 lambda: ("w", rust_batch(watched))]
        got = dict(side() for side in sides[r % 3:] + sides[:r % 3])
        wall.add(got["p"][0], got["s"][0])
        cpu.add(got["p"][1], got["s"][1])
        watch_wall.add(got["w"][0], got["s"][0])
        watch_cpu.add(got["w"][1], got["s"][1])
    for process in (rust, watched):
        process.stdin.close()
        process.wait()
    print(f"robot, 10 s run (1001 samples, dopri5 rtol 1e-9 atol 1e-12), {rounds} rounds of {batch} runs each side")
    wall.show("wall clock")
    cpu.show("thread CPU clock")
    watch_wall.show("wall clock")
    watch_cpu.show("thread CPU clock")


class Sides:
    """Per round the two batches' medians, and their ratio."""

    def __init__(self, name):
        self.name = name
        self.ratios, self.python, self.rust = [], [], []

    def add(self, python, rust):
        self.ratios.append(python / rust)
        self.python.append(python)
        self.rust.append(rust)

    def show(self, clock):
        r = self.ratios
        print(f"{self.name} / Rust, {clock}: median {statistics.median(r):.3f} "
              f"(p10-p90 {quantile(r, 0.1):.3f}-{quantile(r, 0.9):.3f}); median run: "
              f"{statistics.median(self.python) * 1e3:.3f} ms against "
              f"{statistics.median(self.rust) * 1e3:.3f} ms")

if __name__ == "__main__":
    main()
