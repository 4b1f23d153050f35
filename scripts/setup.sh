#!/usr/bin/env bash
# Install every Debian package dnarod needs, and GROMACS built for this CPU where
# Debian's cannot run (below). Idempotent and non-interactive: packages and builds
# already present are not touched, so a second run costs ~1 s.
set -euo pipefail

PACKAGES=(
  # build
  build-essential cmake pkg-config git
  # C++ libraries of rodcore (see README "Dependencies" for why each)
  libeigen3-dev libfftw3-dev libhdf5-dev libtomlplusplus-dev libcli11-dev
  pybind11-dev libgtest-dev libgmock-dev libbenchmark-dev
  # sanitizer/fuzzer toolchain (scripts/test_sanitize.sh)
  clang libclang-rt-14-dev
  # molecular dynamics
  gromacs
  # what scripts/build_gromacs.sh (opt-in: GROMACS built for this CPU from Debian's
  # source) links besides FFTW, so that it needs no root after this script
  libhwloc-dev libmuparser-dev libblas-dev liblapack-dev zlib1g-dev
  # Python side, all on Debian's /usr/bin/python3
  python3 python3-dev python3-numpy python3-scipy python3-matplotlib
  python3-h5py python3-mdanalysis python3-pytest python3-hypothesis
  python3-yaml python3-toml python3-jsonschema snakemake
  # real components the tests drive: the report in headless Chromium through
  # chromedriver, a local SLURM cluster, PyMOL for the viewing files
  chromium chromium-driver python3-selenium slurm-wlm munge pymol python3-pymol
  # installing the toolkit (scripts/install.sh: pip install -e . with Debian's setuptools)
  python3-pip python3-setuptools python3-wheel
  # checks run by scripts/test.sh (scripts/check.sh): format, lint, types
  clang-format python3-flake8 mypy
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} Debian packages present"
else
  echo "setup: installing ${#missing[@]} package(s): ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Debian's gmx is compiled to use the rdtscp instruction, and its mdrun refuses to start
# on a CPU without it (some virtual machines hide it). There, and only there, GROMACS
# is built for this CPU from Debian's own source (~15-20 min on 2 cores; docs/md.md
# "GROMACS built for the machine"); elsewhere this returns at once.
bash "$(dirname "${BASH_SOURCE[0]}")/build_gromacs.sh" --if-needed
