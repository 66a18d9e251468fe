#!/usr/bin/env bash
# hamel against PyDy + scipy's solve_ivp on the Chaplygin sleigh and the rolling disk
# (pydy_vs_hamel.py says how). Makes its own virtual environment with pydy, sympy, scipy,
# cython and numpy from PyPI and the package built from ./python, once, in
# target/pydy-venv under python/; the Cython extensions PyDy generates need a C compiler.
#
#     bash python/benches/pydy.sh [rounds]
set -euo pipefail
cd "$(dirname "$0")/../.."
venv="$PWD/python/target/pydy-venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q --disable-pip-version-check pydy sympy scipy cython numpy setuptools maturin
fi
PATH="$venv/bin:$PATH" "$venv/bin/pip" install -q --disable-pip-version-check --no-build-isolation ./python
"$venv/bin/pip" list --disable-pip-version-check 2>/dev/null | grep -iE '^(pydy|sympy|scipy|cython|numpy) '
"$venv/bin/python" python/benches/pydy_vs_hamel.py "$@"
