#include "rodcore/rhs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/state.hpp"

namespace rodcore {
namespace {

std::vector<double> expand(const Vec3& uniform, const std::vector<double>& varying, int N, const char* name) {
  const std::size_t n = static_cast<std::size_t>(N);
  std::vector<double> out(3 * n);
  if (varying.empty()) {
    for (int c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < n; ++i) out[c * n + i] = uniform[c];
  } else {
    if (varying.size() != 3 * n)
      throw InputError(std::string("rod.") + name + "_s: expected 3 N = " + std::to_string(3 * n) +
                       " values (N = rod.points), got " + std::to_string(varying.size()));
    out = varying;
  }
  for (std::size_t j = 0; j < out.size(); ++j)
    if (!std::isfinite(out[j]))
      throw InputError(std::string("rod.") + name + ": non-finite value at component " +
                       std::to_string(j / n) + ", point " + std::to_string(j % n));
  return out;
}

}  // namespace

std::vector<double> intrinsic_Gamma0(const Rod& rod) {
  return expand(rod.Gamma0, rod.Gamma0_s, rod.points, "Gamma0");
}
std::vector<double> intrinsic_Omega0(const Rod& rod) {
  return expand(rod.Omega0, rod.Omega0_s, rod.points, "Omega0");
}

RodRHS::RodRHS(const Rod& rod, const Material& material, const DerivativeOperator& op)
    : N_(op.N()), material_(material), op_(op) {
  if (static_cast<std::size_t>(rod.points) != N_)
    throw InputError("RodRHS: rod.points (" + std::to_string(rod.points) +
                     ") differs from the operator's N (" + std::to_string(N_) + ")");
  mf_ = resolve_material(material, N_);
  Gamma0_ = intrinsic_Gamma0(rod);
  Omega0_ = intrinsic_Omega0(rod);
  dGamma0_ds_.assign(3 * N_, 0.0);
  dOmega0_ds_.assign(3 * N_, 0.0);
  // Uniform shapes have zero derivative exactly; only differentiate varying ones.
  if (!rod.Gamma0_s.empty()) op.apply(Gamma0_.data(), dGamma0_ds_.data(), 3);
  if (!rod.Omega0_s.empty()) op.apply(Omega0_.data(), dOmega0_ds_.data(), 3);
  // Row stride of the derivative scratch: N, padded by 8 doubles when N is a
  // multiple of 512, where rows N apart map to the same L1 cache sets and
  // evict each other (docs/performance.md, "FD4 throughput at N = 1024").
  stride_ = (N_ % 512 == 0) ? N_ + 8 : N_;
  dy_ds_.assign(12 * stride_, 0.0);
  dy6_.assign(6 * N_, 0.0);
  if (mf_.kind != MaterialKind::diagonal) nm_.assign(6 * N_, 0.0);
  uniform_ = rod.Gamma0_s.empty() && rod.Omega0_s.empty();
}

void RodRHS::set_nonzero_rows(std::vector<int> rows) {
  for (int r : rows)
    if (r < 0 || r >= 12)
      throw InputError("RodRHS::set_nonzero_rows: row " + std::to_string(r) + " not in 0..11");
  nonzero_rows_ = std::move(rows);
  std::fill(dy_ds_.begin(), dy_ds_.end(), 0.0);  // the skipped rows' derivative is zero
}

namespace {

// Rows of the state that a kernel instance treats as identically zero:
// kPlanar = 0 none (full system), 1 the omega2 polarisation, 2 the omega1
// polarisation (reduced_planar.hpp). Known at compile time, so the zero
// loads fold into the arithmetic and the zero rows' outputs are not formed.
constexpr bool zero_row(int planar, int r) {
  if (planar == 1) return r == 1 || r == 3 || r == 5 || r == 7 || r == 9 || r == 11;
  if (planar == 2) return r == 0 || r == 4 || r == 5 || r == 6 || r == 10 || r == 11;
  return false;
}

struct KernelArgs {
  std::size_t N;
  const double* y[12];      // state rows (unused for zero rows)
  const double* dy[12];     // their s-derivatives (kStress, kPerPoint: rows 6..11 hold dn/ds, dm/ds)
  double* f[12];            // d/dt of the rows (unused for zero rows)
  const double* Gamma0[3];  // per-point intrinsic shape and its derivative
  const double* Omega0[3];  // (kUniform: only element [0] of each row is read)
  const double* dGamma0[3];
  const double* dOmega0[3];
  const double* nm[6];  // kStress, kPerPoint: n, m at every point (stress_kernel)
  const MaterialField* mf;
};

// The grid-point loops are compiled twice, for SSE2 (the x86-64 baseline) and
// for AVX2, and the CPU picks one when the program loads (GCC function
// multiversioning). AVX2 without FMA: the same IEEE operations in the same
// order, 4 points per instruction instead of 2, so both clones give
// bit-identical results (docs/performance.md, "General material").
// GCC only: clang (the fuzz build) does not multiversion function templates.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define ROD_KERNEL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ROD_KERNEL_CLONES
#endif

// How the kernel obtains n, m and dn/ds, dm/ds (fixed at compile time):
// kDiagonal  K = diag(C, D), diagonal I, rho = 1, applied in the kernel;
// kCoupled   a uniform full K applied in the kernel to e and de/ds (the
//            reduced planar system, whose zero rows have no stress row);
// kStress    a uniform K, I, rho; n, m formed by stress_kernel, their
//            derivatives by the operator (one 6 x 6 product per point
//            instead of two, and fewer live values in the kernel:
//            docs/performance.md);
// kPerPoint  the same with K, I, rho at every point.
enum : int { kDiagonal = 0, kCoupled = 1, kStress = 2, kPerPoint = 3 };

// The constitutive law (n, m) = K e for a symmetric K given by its 21 unique
// entries (sym6): written once, used by the uniform kernel and the per-point
// stress pass.
// Written without loops: GCC vectorises the grid-point loop only if no inner
// loop is left in its body.
template <int r, class KFn>
[[gnu::always_inline]] inline double stress_row(const KFn& K, const double e[6]) {
  return K(sym6(r, 0)) * e[0] + K(sym6(r, 1)) * e[1] + K(sym6(r, 2)) * e[2] + K(sym6(r, 3)) * e[3] +
         K(sym6(r, 4)) * e[4] + K(sym6(r, 5)) * e[5];
}
template <class KFn>
[[gnu::always_inline]] inline void stress(const KFn& K, const double e[6], double out[6]) {
  out[0] = stress_row<0>(K, e);
  out[1] = stress_row<1>(K, e);
  out[2] = stress_row<2>(K, e);
  out[3] = stress_row<3>(K, e);
  out[4] = stress_row<4>(K, e);
  out[5] = stress_row<5>(K, e);
}

// Pass 1 of kStress and kPerPoint: n and m at every point, which the
// derivative operator then differentiates (the derivative acts on the stress,
// not the strain: that keeps the semi-discrete energy exact for a per-point
// K; docs/numerics.md). kUniformK: the 21 entries of a uniform K as locals.
template <bool kUniform, bool kUniformK>
ROD_KERNEL_CLONES void stress_kernel(const KernelArgs& a, double* nm) {
  const std::size_t N = a.N;
  const double* Kp = a.mf->K_s.data();
  double Ku[21];
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) Ku[sym6(r, c)] = a.mf->K[r * 6 + c];
  const double* y = a.y[0];
  const double *G01 = a.Gamma0[0], *G02 = a.Gamma0[1], *G03 = a.Gamma0[2];
  const double *O01 = a.Omega0[0], *O02 = a.Omega0[1], *O03 = a.Omega0[2];
#pragma GCC ivdep
  for (std::size_t i = 0; i < N; ++i) {
    const double e[6] = {
        y[6 * N + i] - (kUniform ? G01[0] : G01[i]),  y[7 * N + i] - (kUniform ? G02[0] : G02[i]),
        y[8 * N + i] - (kUniform ? G03[0] : G03[i]),  y[9 * N + i] - (kUniform ? O01[0] : O01[i]),
        y[10 * N + i] - (kUniform ? O02[0] : O02[i]), y[11 * N + i] - (kUniform ? O03[0] : O03[i])};
    double out[6];
    stress([&](int k) { return kUniformK ? Ku[k] : Kp[k * N + i]; }, e, out);
    for (int r = 0; r < 6; ++r) nm[r * N + i] = out[r];
  }
}

// The rod equations at every grid point: the ONE place the physics is written.
// kMat: kDiagonal (K = diag(C, D), diagonal I, rho = 1: exactly the paper's
// Eqs 11-14, the fast path), kCoupled, kStress, kPerPoint (above). kUniform: the intrinsic
// shape is the same at every point (read once, zero derivative), which
// removes 12 of the 48 streamed arrays.
template <int kMat, bool kUniform, int kPlanar>
ROD_KERNEL_CLONES void rod_kernel(const KernelArgs& a) {
  const std::size_t N = a.N;
  const MaterialField& mf = *a.mf;
  const double C1 = mf.K[0], C2 = mf.K[7], C3 = mf.K[14];
  const double D1 = mf.K[21], D2 = mf.K[28], D3 = mf.K[35];
  const double I1 = mf.I[0], I2 = mf.I[4], I3 = mf.I[8];
  const double iI1 = 1.0 / I1, iI2 = 1.0 / I2, iI3 = 1.0 / I3;
  const double irho_u = 1.0 / mf.rho;
  // Uniform coupled material: the 21 unique entries of K and the 6 of I, I^-1
  // as locals (kept in registers).
  double Ku[21], Iu[6], Iiu[6];
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) Ku[sym6(r, c)] = mf.K[r * 6 + c];
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      Iu[sym3(r, c)] = mf.I[r * 3 + c];
      Iiu[sym3(r, c)] = mf.Iinv[r * 3 + c];
    }
  const double* Ip = mf.I_s.data();
  const double* Iip = mf.Iinv_s.data();
  const double* irp = mf.irho_s.data();
  // Local copies of the row pointers (constant indices below: kept in
  // registers, and the loop sees no pointer loads through `a`).
  const double* y[12];
  const double* dy[12];
  double* f[12];
  for (int r = 0; r < 12; ++r) {
    y[r] = a.y[r];
    dy[r] = a.dy[r];
    f[r] = a.f[r];
  }
  const double* nm[6];
  for (int r = 0; r < 6; ++r) nm[r] = a.nm[r];
  const double *G01 = a.Gamma0[0], *G02 = a.Gamma0[1], *G03 = a.Gamma0[2];
  const double *O01 = a.Omega0[0], *O02 = a.Omega0[1], *O03 = a.Omega0[2];
  const double *dG01 = a.dGamma0[0], *dG02 = a.dGamma0[1], *dG03 = a.dGamma0[2];
  const double *dO01 = a.dOmega0[0], *dO02 = a.dOmega0[1], *dO03 = a.dOmega0[2];
  const double uG01 = G01[0], uG02 = G02[0], uG03 = G03[0];
  const double uO01 = O01[0], uO02 = O02[0], uO03 = O03[0];
#define ROD_Y(r) (zero_row(kPlanar, r) ? 0.0 : y[r][i])
#define ROD_DY(r) (zero_row(kPlanar, r) ? 0.0 : dy[r][i])
#define ROD_F(r, value) \
  if constexpr (!zero_row(kPlanar, r)) f[r][i] = (value)
#define ROD_SHAPE(u, p) (kUniform ? (u) : (p)[i])
#define ROD_DSHAPE(p) (kUniform ? 0.0 : (p)[i])

  // The row pointers never overlap (y, dy_ds_, the intrinsic shape and dydt
  // are distinct arrays); saying so lets GCC vectorise the loop
  // (measured: bench/, docs/performance.md).
#pragma GCC ivdep
  for (std::size_t i = 0; i < N; ++i) {
    const double b1 = ROD_Y(0), b2 = ROD_Y(1), b3 = ROD_Y(2);    // gamma
    const double a1 = ROD_Y(3), a2 = ROD_Y(4), a3 = ROD_Y(5);    // omega
    const double Q1 = ROD_Y(6), Q2 = ROD_Y(7), Q3 = ROD_Y(8);    // Gamma
    const double P1 = ROD_Y(9), P2 = ROD_Y(10), P3 = ROD_Y(11);  // Omega
    // Internal forces n = dW/dGamma and moments m = dW/dOmega, and their
    // s-derivatives dn, dm.
    double n1, n2, n3, m1, m2, m3, dn1, dn2, dn3, dm1, dm2, dm3;
    if constexpr (kMat == kDiagonal) {
      n1 = C1 * (Q1 - ROD_SHAPE(uG01, G01)), n2 = C2 * (Q2 - ROD_SHAPE(uG02, G02)),
      n3 = C3 * (Q3 - ROD_SHAPE(uG03, G03));
      m1 = D1 * (P1 - ROD_SHAPE(uO01, O01)), m2 = D2 * (P2 - ROD_SHAPE(uO02, O02)),
      m3 = D3 * (P3 - ROD_SHAPE(uO03, O03));
      dn1 = C1 * (ROD_DY(6) - ROD_DSHAPE(dG01)), dn2 = C2 * (ROD_DY(7) - ROD_DSHAPE(dG02)),
      dn3 = C3 * (ROD_DY(8) - ROD_DSHAPE(dG03));
      dm1 = D1 * (ROD_DY(9) - ROD_DSHAPE(dO01)), dm2 = D2 * (ROD_DY(10) - ROD_DSHAPE(dO02)),
      dm3 = D3 * (ROD_DY(11) - ROD_DSHAPE(dO03));
    } else if constexpr (kMat == kCoupled) {
      // Uniform K: d(K e)/ds = K de/ds.
      const double e[6] = {Q1 - ROD_SHAPE(uG01, G01), Q2 - ROD_SHAPE(uG02, G02), Q3 - ROD_SHAPE(uG03, G03),
                           P1 - ROD_SHAPE(uO01, O01), P2 - ROD_SHAPE(uO02, O02), P3 - ROD_SHAPE(uO03, O03)};
      const double de[6] = {ROD_DY(6) - ROD_DSHAPE(dG01),  ROD_DY(7) - ROD_DSHAPE(dG02),
                            ROD_DY(8) - ROD_DSHAPE(dG03),  ROD_DY(9) - ROD_DSHAPE(dO01),
                            ROD_DY(10) - ROD_DSHAPE(dO02), ROD_DY(11) - ROD_DSHAPE(dO03)};
      double s[6], ds[6];
      auto K = [&](int k) { return Ku[k]; };
      stress(K, e, s);
      stress(K, de, ds);
      n1 = s[0], n2 = s[1], n3 = s[2], m1 = s[3], m2 = s[4], m3 = s[5];
      dn1 = ds[0], dn2 = ds[1], dn3 = ds[2], dm1 = ds[3], dm2 = ds[4], dm3 = ds[5];
    } else {  // kStress, kPerPoint
      n1 = nm[0][i], n2 = nm[1][i], n3 = nm[2][i], m1 = nm[3][i], m2 = nm[4][i], m3 = nm[5][i];
      dn1 = dy[6][i], dn2 = dy[7][i], dn3 = dy[8][i], dm1 = dy[9][i], dm2 = dy[10][i], dm3 = dy[11][i];
    }

    // Balance of force (Eq 11; the diagonal kind has rho = 1).
    if constexpr (kMat == kDiagonal) {
      ROD_F(0, dn1 + (P2 * n3 - P3 * n2) - (a2 * b3 - a3 * b2));
      ROD_F(1, dn2 + (P3 * n1 - P1 * n3) - (a3 * b1 - a1 * b3));
      ROD_F(2, dn3 + (P1 * n2 - P2 * n1) - (a1 * b2 - a2 * b1));
    } else {
      const double irho = kMat == kPerPoint ? irp[i] : irho_u;
      ROD_F(0, irho * (dn1 + (P2 * n3 - P3 * n2)) - (a2 * b3 - a3 * b2));
      ROD_F(1, irho * (dn2 + (P3 * n1 - P1 * n3)) - (a3 * b1 - a1 * b3));
      ROD_F(2, irho * (dn3 + (P1 * n2 - P2 * n1)) - (a1 * b2 - a2 * b1));
    }

    // Balance of torque (Eq 12), solved for d omega/dt.
    if constexpr (kMat == kDiagonal) {
      const double Iw1 = I1 * a1, Iw2 = I2 * a2, Iw3 = I3 * a3;
      ROD_F(3, iI1 * (dm1 + (P2 * m3 - P3 * m2) + (Q2 * n3 - Q3 * n2) - (a2 * Iw3 - a3 * Iw2)));
      ROD_F(4, iI2 * (dm2 + (P3 * m1 - P1 * m3) + (Q3 * n1 - Q1 * n3) - (a3 * Iw1 - a1 * Iw3)));
      ROD_F(5, iI3 * (dm3 + (P1 * m2 - P2 * m1) + (Q1 * n2 - Q2 * n1) - (a1 * Iw2 - a2 * Iw1)));
    } else {
      auto In = [&](int k) { return kMat == kPerPoint ? Ip[k * N + i] : Iu[k]; };
      auto Ii = [&](int k) { return kMat == kPerPoint ? Iip[k * N + i] : Iiu[k]; };
      const double Iw1 = In(0) * a1 + In(1) * a2 + In(2) * a3;
      const double Iw2 = In(1) * a1 + In(3) * a2 + In(4) * a3;
      const double Iw3 = In(2) * a1 + In(4) * a2 + In(5) * a3;
      const double t1 = dm1 + (P2 * m3 - P3 * m2) + (Q2 * n3 - Q3 * n2) - (a2 * Iw3 - a3 * Iw2);
      const double t2 = dm2 + (P3 * m1 - P1 * m3) + (Q3 * n1 - Q1 * n3) - (a3 * Iw1 - a1 * Iw3);
      const double t3 = dm3 + (P1 * m2 - P2 * m1) + (Q1 * n2 - Q2 * n1) - (a1 * Iw2 - a2 * Iw1);
      ROD_F(3, Ii(0) * t1 + Ii(1) * t2 + Ii(2) * t3);
      ROD_F(4, Ii(1) * t1 + Ii(3) * t2 + Ii(4) * t3);
      ROD_F(5, Ii(2) * t1 + Ii(4) * t2 + Ii(5) * t3);
    }

    // Eq 13: compatibility of velocity and strain.
    ROD_F(6, ROD_DY(0) + (P2 * b3 - P3 * b2) - (a2 * Q3 - a3 * Q2));
    ROD_F(7, ROD_DY(1) + (P3 * b1 - P1 * b3) - (a3 * Q1 - a1 * Q3));
    ROD_F(8, ROD_DY(2) + (P1 * b2 - P2 * b1) - (a1 * Q2 - a2 * Q1));

    // Eq 14: compatibility of angular velocity and curvature.
    ROD_F(9, ROD_DY(3) - (a2 * P3 - a3 * P2));
    ROD_F(10, ROD_DY(4) - (a3 * P1 - a1 * P3));
    ROD_F(11, ROD_DY(5) - (a1 * P2 - a2 * P1));
  }
#undef ROD_Y
#undef ROD_DY
#undef ROD_F
#undef ROD_SHAPE
#undef ROD_DSHAPE
}

}  // namespace

void RodRHS::operator()(const double* y, double* dydt) const {
  const std::size_t N = N_;
  const std::size_t S = stride_;
  KernelArgs a;
  a.N = N;
  for (int r = 0; r < 12; ++r) {
    a.y[r] = y + r * N;
    a.dy[r] = dy_ds_.data() + r * S;
    a.f[r] = dydt + r * N;
  }
  for (int c = 0; c < 3; ++c) {
    a.Gamma0[c] = Gamma0_.data() + c * N;
    a.Omega0[c] = Omega0_.data() + c * N;
    a.dGamma0[c] = dGamma0_ds_.data() + c * N;
    a.dOmega0[c] = dOmega0_ds_.data() + c * N;
  }
  a.mf = &mf_;
  for (int r = 0; r < 6; ++r) a.nm[r] = nm_.empty() ? nullptr : nm_.data() + r * N;
  if (mf_.kind != MaterialKind::diagonal) {
    // d/ds of gamma, omega (rows 0..5) and of n, m (into rows 6..11): all
    // of them (nonzero_rows_ would only save work).
    const bool pp = mf_.kind == MaterialKind::per_point;
    if (uniform_) pp ? stress_kernel<true, false>(a, nm_.data()) : stress_kernel<true, true>(a, nm_.data());
    else pp ? stress_kernel<false, false>(a, nm_.data()) : stress_kernel<false, true>(a, nm_.data());
    if (S == N) {
      op_.apply(y, dy_ds_.data(), 6);
      op_.apply(nm_.data(), dy_ds_.data() + 6 * S, 6);
    } else {
      for (std::size_t r = 0; r < 6; ++r) op_.apply(y + r * N, dy_ds_.data() + r * S, 1);
      for (std::size_t r = 0; r < 6; ++r) op_.apply(nm_.data() + r * N, dy_ds_.data() + (6 + r) * S, 1);
    }
    // The shape entered through n, m only.
    pp ? rod_kernel<kPerPoint, true, 0>(a) : rod_kernel<kStress, true, 0>(a);
    return;
  }
  if (nonzero_rows_.empty() && S == N) {
    op_.apply(y, dy_ds_.data(), 12);
  } else if (nonzero_rows_.empty()) {
    for (std::size_t r = 0; r < 12; ++r) op_.apply(y + r * N, dy_ds_.data() + r * S, 1);
  } else {
    for (int r : nonzero_rows_) op_.apply(y + r * N, dy_ds_.data() + r * S, 1);
  }
  // The zero rows of a planar polarisation are still written (as zeros) so
  // that dydt is the complete 12-row derivative the caller expects.
  if (uniform_) rod_kernel<kDiagonal, true, 0>(a);
  else rod_kernel<kDiagonal, false, 0>(a);
}

void RodRHS::reduced(int planar, const std::array<int, 6>& rows, const double* y6, double* f6) const {
  if (!uniform_ || mf_.kind == MaterialKind::per_point || (planar != 1 && planar != 2))
    throw Error(
        "RodRHS::reduced: needs a uniform intrinsic shape, a uniform material and polarisation 1 or 2");
  const std::size_t N = N_;
  op_.apply(y6, dy6_.data(), 6);  // the six kept rows, one batch
  KernelArgs a;
  a.N = N;
  for (int r = 0; r < 12; ++r) a.y[r] = a.dy[r] = a.f[r] = nullptr;
  for (std::size_t k = 0; k < 6; ++k) {
    const int r = rows[k];
    if (zero_row(planar, r)) throw Error("RodRHS::reduced: row " + std::to_string(r) + " is not kept");
    a.y[r] = y6 + k * N;
    a.dy[r] = dy6_.data() + k * N;
    a.f[r] = f6 + k * N;
  }
  for (int c = 0; c < 3; ++c) {
    a.Gamma0[c] = Gamma0_.data() + c * N;
    a.Omega0[c] = Omega0_.data() + c * N;
    a.dGamma0[c] = dGamma0_ds_.data() + c * N;
    a.dOmega0[c] = dOmega0_ds_.data() + c * N;
  }
  a.mf = &mf_;
  for (int r = 0; r < 6; ++r) a.nm[r] = nullptr;
  const bool diag = mf_.kind == MaterialKind::diagonal;
  if (planar == 1) diag ? rod_kernel<kDiagonal, true, 1>(a) : rod_kernel<kCoupled, true, 1>(a);
  else diag ? rod_kernel<kDiagonal, true, 2>(a) : rod_kernel<kCoupled, true, 2>(a);
}

}  // namespace rodcore
