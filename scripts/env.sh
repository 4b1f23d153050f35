# Sourced by the scripts: where things are, and Debian's Python. The toolkit
# itself is found through its install (scripts/install.sh), not through paths.
DNAROD_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DNAROD_BUILD="${DNAROD_BUILD:-$DNAROD_ROOT/build}"
PYTHON=/usr/bin/python3
export DNAROD_ROOT DNAROD_BUILD PYTHON
# Matplotlib without a display.
export MPLBACKEND=Agg
