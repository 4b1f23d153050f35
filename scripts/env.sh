# Sourced by the scripts: where things are, and Debian's Python.
DNAROD_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DNAROD_BUILD="${DNAROD_BUILD:-$DNAROD_ROOT/build}"
PYTHON=/usr/bin/python3
export DNAROD_ROOT DNAROD_BUILD PYTHON
export PYTHONPATH="$DNAROD_ROOT:$DNAROD_BUILD/python${PYTHONPATH:+:$PYTHONPATH}"
# Matplotlib without a display.
export MPLBACKEND=Agg
