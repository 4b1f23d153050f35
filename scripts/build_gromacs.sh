#!/usr/bin/env bash
# Opt-in: build GROMACS 2022.5 for THIS machine's CPU from Debian's own source
# package, into a prefix of the checkout. `dnarod run-md` and the workflow use it
# when it exists (mdbridge/md/gromacs/gmx.py); --gmx PATH and DNAROD_GMX=PATH still
# override.
#
#   bash scripts/build_gromacs.sh                   # gmx   (mixed precision)
#   bash scripts/build_gromacs.sh --double          # gmx and gmx_d (double precision)
#   bash scripts/build_gromacs.sh --configure-only  # fetch, configure, stop (no compile)
#   bash scripts/build_gromacs.sh --print-prefix    # where it installs, then exit
#   bash scripts/build_gromacs.sh --if-needed       # only where Debian's gmx cannot run (setup.sh)
#
# Why: Debian's binary package is compiled for SSE4.1 so that it runs on every
# x86-64 CPU; mdrun's kernels then use 128-bit SIMD only. The same source built
# with AVX2_256 or AVX_512 runs the 158-bp system faster (bench/gromacs_simd.py
# measures by how much; docs/md.md "GROMACS built for the machine").
#
# Why Debian's source package and not a tarball from gromacs.org: it is the exact
# source, patches included, of the `gmx` that setup.sh installs, it is signed by
# the Debian archive, and its build dependencies come from the same archive, so
# nothing outside Debian is downloaded.
#
# Why a prefix inside the checkout (.local/gromacs by default): no root is
# needed for the install, it lives and dies with the checkout (`git clean -X`),
# and it never shadows a system GROMACS. Several checkouts can share one build by
# setting DNAROD_GROMACS_PREFIX to one directory in each.
#
# Each binary is built once: a gmx (gmx_d) in PREFIX/bin that reports version
# 2022.5 is kept, so a second run exits at once, and `--double` after a mixed
# build compiles only gmx_d. To rebuild with other options, delete PREFIX.
#
# Environment:
#   DNAROD_GROMACS_PREFIX  install prefix (default: <checkout>/.local/gromacs)
#   DNAROD_GMX_SIMD        GROMACS SIMD level (default AUTO: GROMACS's own CPU
#                          detection, AVX_512 on CPUs with two AVX-512 FMA units,
#                          AVX2_256 on AVX2 CPUs and AVX-512 CPUs with one)
#   DNAROD_GMX_GPU=CUDA    build the CUDA GPU code into gmx (needs nvcc and an
#                          NVIDIA GPU). UNTESTED: no GPU was available where this
#                          script was written. gmx_d never has GPU code (GROMACS
#                          has none in double precision).
#   DNAROD_GMX_DOUBLE=1    same as --double
#   DNAROD_GMX_JOBS        parallel compile jobs (default: number of CPUs)
#   DNAROD_CPUINFO         the CPU's flags (default /proc/cpuinfo; tests give others)
#
# --check prints, for each binary, whether it would be kept or built, and exits.
#
# --if-needed (scripts/setup.sh runs it): build only when the `gmx` on PATH (Debian's)
# cannot run mdrun on this CPU, i.e. it uses rdtscp and the CPU lacks it. There every
# MD of the toolkit and its tests would fail, so the build (~15-20 min on 2 cores) is
# then part of the install; elsewhere this exits at once.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PREFIX="${DNAROD_GROMACS_PREFIX:-$ROOT/.local/gromacs}"
VERSION=2022.5
JOBS="${DNAROD_GMX_JOBS:-$(nproc)}"
WORK="$ROOT/.local/gromacs-build"
DOUBLE="${DNAROD_GMX_DOUBLE:-0}"
CONFIGURE_ONLY=0
CHECK=0
IF_NEEDED=0
for arg in "$@"; do
  case "$arg" in
    --double) DOUBLE=1 ;;
    --configure-only) CONFIGURE_ONLY=1 ;;
    --check) CHECK=1 ;;
    --if-needed) IF_NEEDED=1 ;;
    --print-prefix) echo "$PREFIX"; exit 0 ;;
    -h|--help) sed -n '2,50p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "build_gromacs: unknown argument '$arg'; allowed: --double, --configure-only, --check, --if-needed, --print-prefix" >&2
       exit 2 ;;
  esac
done
SIMD="${DNAROD_GMX_SIMD:-AUTO}"
GPU="${DNAROD_GMX_GPU:-OFF}"
case "$GPU" in
  OFF|CUDA) ;;
  *) echo "build_gromacs: DNAROD_GMX_GPU=$GPU; allowed: OFF or CUDA" >&2; exit 2 ;;
esac

# rdtscp: mdrun built to use it refuses to start on a CPU without it (some virtual
# machines hide it: "Please rebuild GROMACS with the GMX_USE_RDTSCP=OFF"), so it is
# used only where /proc/cpuinfo lists it, and a build that uses it on a CPU without it
# is rebuilt.
if grep -qw rdtscp "${DNAROD_CPUINFO:-/proc/cpuinfo}" 2>/dev/null; then RDTSCP=ON; else RDTSCP=OFF; fi
runs_here() {  # $1 = a gmx, $2 = its `--version` text: false if it uses rdtscp and the CPU lacks it
  if [ "$RDTSCP" = OFF ] && grep -q "RDTSCP usage:.*enabled" <<<"$2"; then
    echo "build_gromacs: $1 uses rdtscp, which this CPU lacks (its mdrun refuses to start here)"
    return 1
  fi
}
have() {  # $1 = gmx or gmx_d: installed, of this version, runnable on this CPU
  [ -x "$PREFIX/bin/$1" ] || return 1
  local v
  v="$("$PREFIX/bin/$1" --version 2>/dev/null)" || return 1
  grep -q "GROMACS version:.*$VERSION" <<<"$v" || return 1
  runs_here "$PREFIX/bin/$1" "$v" || { echo "build_gromacs: rebuilding $1"; return 1; }
}
if [ "$IF_NEEDED" = 1 ]; then
  system_gmx="$(command -v gmx || true)"
  if [ -z "$system_gmx" ]; then
    echo "build_gromacs: no gmx on PATH (scripts/setup.sh installs Debian's)" >&2; exit 1
  fi
  if runs_here "$system_gmx" "$("$system_gmx" --version 2>/dev/null)"; then
    echo "build_gromacs: $system_gmx runs on this CPU; no build needed"
    exit 0
  fi
  echo "build_gromacs: so GROMACS is built for this CPU into $PREFIX (dnarod uses it first)"
fi
wanted=(gmx)
if [ "$DOUBLE" = 1 ]; then wanted+=(gmx_d); fi
todo=()
for exe in "${wanted[@]}"; do
  if have "$exe"; then
    echo "build_gromacs: $PREFIX/bin/$exe ($VERSION) already built; kept"
    "$PREFIX/bin/$exe" --version 2>/dev/null | grep -E "SIMD instructions|GPU support" || true
  else
    todo+=("$exe")
    if [ "$CHECK" = 1 ]; then echo "build_gromacs: $exe would be built (rdtscp $RDTSCP)"; fi
  fi
done
if [ ${#todo[@]} -eq 0 ] || [ "$CHECK" = 1 ]; then exit 0; fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

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

# 2. Debian's source (upstream tarball + Debian patches applied by dpkg-source;
#    no root needed).
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
debver="$(cd "$srcdir" && dpkg-parsechangelog -S version)"

# 3. The build dependencies of Debian's gromacs that this configuration uses (not
#    MPI, X11 or the documentation's); scripts/setup.sh installs them, so root is
#    needed here only if one is missing.
deps=(build-essential cmake dpkg-dev libfftw3-dev libhwloc-dev libmuparser-dev
      libblas-dev liblapack-dev zlib1g-dev)
missing=()
for p in "${deps[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "build_gromacs: installing ${missing[*]}"
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# 4. Configure and build. The options, and why (docs/md.md "GROMACS built for the
#    machine"):
#    - Release (-O3), GMX_SIMD (AUTO: GROMACS's CPU detection) plus -march=native
#      for the code outside the SIMD kernels;
#    - static libgromacs (BUILD_SHARED_LIBS=OFF): no position-independent code, and
#      the built gmx can never load Debian's SSE4.1 libgromacs.so.7 from /usr/lib;
#    - Debian's FFTW (fftw3), hwloc, muparser, BLAS/LAPACK, as Debian builds it;
#    - thread-MPI + OpenMP (mdrun -nt), no MPI, no X11, no tests, docs or APIs.
configure_one() {  # $1 = mixed | double
  local prec="$1" bdir="$WORK/build-$1" dbl=OFF gpu="$GPU"
  if [ "$prec" = double ]; then dbl=ON; gpu=OFF; fi
  mkdir -p "$bdir"
  cmake -S "$srcdir" -B "$bdir" \
    -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_INSTALL_PREFIX="$PREFIX" \
    -DGMX_SIMD="$SIMD" \
    -DGMX_DOUBLE="$dbl" \
    -DGMX_GPU="$gpu" \
    -DGMX_MPI=OFF -DGMX_THREAD_MPI=ON -DGMX_OPENMP=ON \
    -DGMX_FFT_LIBRARY=fftw3 -DGMX_BUILD_OWN_FFTW=OFF \
    -DGMX_HWLOC=ON -DGMX_USE_RDTSCP="$RDTSCP" \
    -DGMX_USE_MUPARSER=EXTERNAL \
    -DGMX_EXTERNAL_BLAS=ON -DGMX_EXTERNAL_LAPACK=ON \
    -DBUILD_SHARED_LIBS=OFF -DGMX_INSTALL_NBLIB_API=OFF -DGMXAPI=OFF \
    -DGMX_X11=OFF -DGMX_BUILD_HELP=OFF -DGMX_BUILD_MANUAL=OFF -DBUILD_TESTING=OFF \
    -DGMX_INSTALL_LEGACY_API=OFF -DGMX_PYTHON_PACKAGE=OFF -DGMX_GIT_VERSION_INFO=OFF \
    -DGMX_VERSION_STRING_OF_FORK="Debian-$debver-dnarod" \
    -DCMAKE_C_FLAGS="-march=native" -DCMAKE_CXX_FLAGS="-march=native"
  echo "build_gromacs: $prec configured: SIMD $(grep -m1 '^GMX_SIMD_ACTIVE_PREVIOUS_VALUE:' "$bdir/CMakeCache.txt" | cut -d= -f2)," \
       "FFT $(grep -m1 '^GMX_FFT_LIBRARY:' "$bdir/CMakeCache.txt" | cut -d= -f2)," \
       "hwloc $(grep -m1 '^GMX_HWLOC:' "$bdir/CMakeCache.txt" | cut -d= -f2), GPU $gpu"
}

build_one() {  # $1 = mixed | double
  local t0 t1 bdir="$WORK/build-$1"
  t0=$(date +%s)
  cmake --build "$bdir" -j "$JOBS"
  cmake --install "$bdir"
  t1=$(date +%s)
  echo "build_gromacs: $1 precision compiled and installed in $(( (t1 - t0) / 60 )) min $(( (t1 - t0) % 60 )) s ($JOBS jobs)"
}

for exe in "${todo[@]}"; do
  prec=$([ "$exe" = gmx_d ] && echo double || echo mixed)
  configure_one "$prec"
  if [ "$CONFIGURE_ONLY" = 1 ]; then continue; fi
  build_one "$prec"
  "$PREFIX/bin/$exe" --version 2>/dev/null | grep -E "GROMACS version|Precision|SIMD instructions|GPU support|FFT library"
done
