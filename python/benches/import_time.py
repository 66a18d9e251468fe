"""`import hamel` in a fresh interpreter, and the wheel's size.

    python python/benches/import_time.py [repeats] [wheel]      (after `pip install ./python`)

Times `import hamel` (NumPy's import included) in fresh processes; printed: the median and the
largest. With the path of a wheel (`maturin build --release` writes it to
python/target/wheels/), prints its size too. The issue's bounds: 0.5 s, 10 MB.
"""

import os
import statistics
import subprocess
import sys

CHILD = "import time; s = time.perf_counter(); import hamel; print(time.perf_counter() - s)"


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 11
    times = [float(subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True,
                                  check=True).stdout) for _ in range(repeats)]
    print(f"import hamel: median {statistics.median(times):.3f} s, largest {max(times):.3f} s ({repeats} fresh processes)")
    if len(sys.argv) > 2:
        size = os.path.getsize(sys.argv[2])
        print(f"wheel {os.path.basename(sys.argv[2])}: {size / 1e6:.2f} MB")


if __name__ == "__main__":
    main()
