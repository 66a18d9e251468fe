"""How long Ctrl-C takes to stop a long run and an ensemble.

    python python/benches/interrupt.py [repeats]      (after `pip install ./python`)

In a child process, a run that would take minutes (and an ensemble of 10⁴ runs on 2
threads) is interrupted by SIGINT after 0.5 s of computing; the child notes when
KeyboardInterrupt reached it (the system's monotonic clock, shared by both processes).
Printed: the latency from the signal to the exception, median and largest. The issue's bound
is 0.1 s.
"""

import signal
import statistics
import subprocess
import sys
import time

CHILD = """
import time, hamel
robot = hamel.models.MobileRobot()
x0 = robot.state(alpha=0.3, w4=0.5, w5=0.4)
print("ready", flush=True)
try:
    {call}
except KeyboardInterrupt:
    print(time.monotonic(), flush=True)
"""

CALLS = {
    "run": "robot.simulate(x0, t_end=1e6, dt=1e4)",
    "ensemble": "robot.ensemble(parameters={'m0': [10.0] * 10000}, states=x0, t_end=100.0, dt=10.0, threads=2)",
}


def latency(call):
    child = subprocess.Popen([sys.executable, "-c", CHILD.format(call=call)],
                             stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "ready"
    time.sleep(0.5)
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=60)
    return float(out) - sent


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    for name, call in CALLS.items():
        times = [latency(call) for _ in range(repeats)]
        print(f"Ctrl-C on a {name}: median {statistics.median(times) * 1e3:.1f} ms, "
              f"largest {max(times) * 1e3:.1f} ms ({repeats} times)")


if __name__ == "__main__":
    main()
