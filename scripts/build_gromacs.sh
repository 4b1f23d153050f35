#!/usr/bin/env bash
# Opt-in: build GROMACS 2022.5 for THIS machine's CPU from Debian's own source
# package, into a prefix of the checkout. `dnarod run-md` and the workflow use it
# when it exists (mdbridge/gromacs/gmx.py); --gmx and DNAROD_GMX still override.
#
# Why: Debian's binary package is compiled for SSE4.1 so that it runs on every
# x86-64 CPU; mdrun's kernels then use 128-bit SIMD only. The same source built
# with AVX2_256 (or AVX_512) runs the 158-bp system faster (bench/gromacs_simd.py
# measures by how much; docs/md.md "GROMACS built for the machine").
#
# Why Debian's source package and not a tarball from gromacs.org: it is the exact
# source, patches included, of the `gmx` that setup.sh installs, it is signed by
# the Debian archive, and its build dependencies come from the same archive
# (`apt-get build-dep`), so nothing outside Debian is downloaded.
#
# Why a prefix inside the checkout (.local/gromacs by default): no root is
# needed for the install, it lives and dies with the checkout (`git clean -X`),
# and it never shadows a system GROMACS. Several checkouts can share one build by
# setting DNAROD_GROMACS_PREFIX to one directory in each.
#
# Idempotent: if PREFIX/bin/gmx exists and reports the same version, it exits at once.
#
# Environment:
#   DNAROD_GROMACS_PREFIX  install prefix (default: <checkout>/.local/gromacs)
#   DNAROD_GMX_SIMD        GROMACS SIMD level (default: what GROMACS's own CPU
#                          detection suggests: AVX_512 on CPUs with two AVX-512 FMA
#                          units, else AVX2_256 where AVX2 exists)
#   DNAROD_GMX_GPU=CUDA    build the CUDA GPU code (needs nvcc and an NVIDIA GPU).
#                          UNTESTED: no GPU was available where this script was written.
#   DNAROD_GMX_DOUBLE=1    also build the double-precision gmx_d (doubles the build time)
#   DNAROD_GMX_JOBS        parallel compile jobs (default: number of CPUs)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PREFIX="${DNAROD_GROMACS_PREFIX:-$ROOT/.local/gromacs}"
VERSION=2022.5
JOBS="${DNAROD_GMX_JOBS:-$(nproc)}"
WORK="$ROOT/.local/gromacs-build"

if [ -x "$PREFIX/bin/gmx" ] && "$PREFIX/bin/gmx" --version 2>/dev/null | grep -q "GROMACS version:.*$VERSION"; then
  echo "build_gromacs: $PREFIX/bin/gmx ($VERSION) already built; nothing to do"
  "$PREFIX/bin/gmx" --version 2>/dev/null | grep -E "SIMD instructions|GPU support" || true
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
t0=$(date +%s)

# 1. deb-src for the archive the binary came from (same URIs and suites as the
#    enabled deb entries of /etc/apt/sources.list.d/debian.sources).
if ! apt-get source --print-uris gromacs >/dev/null 2>&1; then
  src=/etc/apt/sources.list.d/dnarod-gromacs-src.sources
  codename="$(. /etc/os-release && echo "${VERSION_CODENAME:?cannot read VERSION_CODENAME from /etc/os-release}")"
  echo "build_gromacs: enabling deb-src for Debian $codename in $src"
  $SUDO tee "$src" >/dev/null <<EOF
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: $codename
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
  $SUDO apt-get update -q
fi

# 2. Build dependencies of the binary packages (not of the documentation).
echo "build_gromacs: installing Debian's build dependencies of gromacs"
$SUDO apt-get build-dep -y -q --arch-only gromacs

# 3. Debian's source (upstream tarball + Debian patches applied by dpkg-source).
mkdir -p "$WORK"
cd "$WORK"
srcdir="$(ls -d gromacs-$VERSION*/ 2>/dev/null | head -1 || true)"
if [ -z "$srcdir" ]; then
  apt-get source -q gromacs
  srcdir="$(ls -d gromacs-$VERSION*/ | head -1)"
fi
srcdir="$WORK/${srcdir%/}"
grep -q "$VERSION" "$srcdir/debian/changelog" || {
  echo "build_gromacs: $srcdir is not GROMACS $VERSION (see its debian/changelog)" >&2; exit 1; }

# 4. SIMD level: GROMACS's own hardware detection (the same code that makes
#    mdrun's log say "SIMD instructions most likely to fit this hardware").
SIMD="${DNAROD_GMX_SIMD:-AUTO}"
GPU="${DNAROD_GMX_GPU:-OFF}"
case "$GPU" in
  OFF|CUDA) ;;
  *) echo "build_gromacs: DNAROD_GMX_GPU=$GPU; allowed: OFF or CUDA" >&2; exit 2 ;;
esac

build_one() {  # $1 = ON for double precision
  local dbl="$1" bdir="$WORK/build-$([ "$1" = ON ] && echo double || echo mixed)"
  mkdir -p "$bdir"
  cmake -S "$srcdir" -B "$bdir" \
    -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_INSTALL_PREFIX="$PREFIX" \
    -DGMX_SIMD="$SIMD" \
    -DGMX_DOUBLE="$dbl" \
    -DGMX_GPU="$GPU" \
    -DGMX_MPI=OFF -DGMX_OPENMP=ON -DGMX_THREAD_MPI=ON \
    -DGMX_FFT_LIBRARY=fftw3 -DGMX_BUILD_OWN_FFTW=OFF \
    -DGMX_HWLOC=ON -DGMX_USE_RDTSCP=ON \
    -DGMX_EXTERNAL_BLAS=ON -DGMX_EXTERNAL_LAPACK=ON \
    -DGMX_BUILD_HELP=OFF -DGMX_BUILD_MANUAL=OFF -DBUILD_TESTING=OFF \
    -DGMX_INSTALL_LEGACY_API=OFF -DGMXAPI=OFF -DGMX_PYTHON_PACKAGE=OFF \
    -DCMAKE_C_FLAGS="-march=native" -DCMAKE_CXX_FLAGS="-march=native"
  cmake --build "$bdir" -j "$JOBS"
  cmake --install "$bdir"
}

build_one OFF
if [ "${DNAROD_GMX_DOUBLE:-0}" = 1 ]; then build_one ON; fi

t1=$(date +%s)
echo "build_gromacs: installed $PREFIX/bin/gmx in $(( (t1 - t0) / 60 )) min $(( (t1 - t0) % 60 )) s"
"$PREFIX/bin/gmx" --version 2>/dev/null | grep -E "GROMACS version|SIMD instructions|GPU support|C compiler flags"
