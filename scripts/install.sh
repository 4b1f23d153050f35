#!/usr/bin/env bash
# Install this checkout for every shell on the machine (after scripts/build.sh):
#   1. pip, editable: mdbridge, dna_models and dnarod (the folder workflows/)
#      import from this checkout, and `dnarod` goes to /usr/local/bin;
#   2. cmake --install: the compiled module rodcore into Debian Python's
#      /usr/local/lib/python3.X/dist-packages and rodsim into /usr/local/bin
#      (cmake/python_install.cmake).
# One install serves the whole machine, so the last checkout installed wins:
# scripts/test.sh reinstalls the checkout it tests, and
# tests/python/test_install.py checks that what imports is this checkout.
# Debian's pip refuses system installs without --break-system-packages; it only
# adds files under /usr/local and never touches what apt installed. No network:
# --no-index, --no-build-isolation (Debian's setuptools), --no-deps (Debian packages).
set -euo pipefail
source "$(dirname "$0")/env.sh"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO "$PYTHON" -m pip install --quiet --break-system-packages --no-build-isolation --no-deps \
      --no-index --root-user-action=ignore --disable-pip-version-check -e "$DNAROD_ROOT"
$SUDO cmake --install "$DNAROD_BUILD" > "$DNAROD_BUILD.install.log" \
  || { cat "$DNAROD_BUILD.install.log"; exit 1; }
echo "install: $DNAROD_ROOT (Python packages, editable) and $DNAROD_BUILD (rodcore, rodsim)"
