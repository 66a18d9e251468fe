#!/usr/bin/env python3
"""scipy's solution of continuous algebraic Riccati equations, the reference of
tests/validation/tests/riccati.rs.

Reads cases from stdin, each a line `case NAME N M` followed by the rows of A (N × N), B
(N × M), Q (N × N) and R (M × M), numbers separated by blanks. Writes for each case a line
`case NAME N M` followed by the rows of the gain K = R⁻¹ B' P (M × N) and of P (N × N), each
number as `repr` prints it (the shortest string that reads back to the same double).

    python3 tests/validation/scripts/care_reference.py < cases.txt
"""

import sys

import numpy as np
from scipy.linalg import solve_continuous_are


def read_cases(text):
    tokens = text.split()
    at = 0
    while at < len(tokens):
        if tokens[at] != "case":
            raise ValueError(f"expected `case`, found {tokens[at]!r}")
        name, n, m = tokens[at + 1], int(tokens[at + 2]), int(tokens[at + 3])
        at += 4
        def matrix(rows, cols):
            nonlocal at
            values = [float(v) for v in tokens[at:at + rows * cols]]
            at += rows * cols
            return np.array(values).reshape(rows, cols)
        a, b, q, r = matrix(n, n), matrix(n, m), matrix(n, n), matrix(m, m)
        yield name, a, b, q, r


def main():
    out = []
    for name, a, b, q, r in read_cases(sys.stdin.read()):
        p = solve_continuous_are(a, b, q, r)
        k = np.linalg.solve(r, b.T @ p)
        n, m = a.shape[0], b.shape[1]
        out.append(f"case {name} {n} {m}")
        for row in list(k) + list(p):
            out.append(" ".join(repr(float(v)) for v in row))
    print("\n".join(out))


if __name__ == "__main__":
    main()
