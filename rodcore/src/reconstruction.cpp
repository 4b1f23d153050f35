#include "rodcore/reconstruction.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fftw_lock.hpp"
#include "rodcore/error.hpp"

namespace rodcore {

Quat quat_mul(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

Quat quat_exp(const Vec3& th) {
  const double a = std::sqrt(th[0] * th[0] + th[1] * th[1] + th[2] * th[2]);
  const double half = 0.5 * a;
  // sin(a/2)/a, with its Taylor series near 0
  const double sa = a < 1e-4 ? 0.5 - a * a / 48.0 : std::sin(half) / a;
  return {std::cos(half), sa * th[0], sa * th[1], sa * th[2]};
}

Quat quat_normalized(const Quat& q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

void quat_to_matrix(const Quat& q, double R[3][3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  R[0][0] = 1 - 2 * (y * y + z * z);
  R[0][1] = 2 * (x * y - w * z);
  R[0][2] = 2 * (x * z + w * y);
  R[1][0] = 2 * (x * y + w * z);
  R[1][1] = 1 - 2 * (x * x + z * z);
  R[1][2] = 2 * (y * z - w * x);
  R[2][0] = 2 * (x * z - w * y);
  R[2][1] = 2 * (y * z + w * x);
  R[2][2] = 1 - 2 * (x * x + y * y);
}

Quat matrix_to_quat(const double R[3][3]) {
  // Shepperd's method: pick the largest of w, x, y, z for stability.
  const double tr = R[0][0] + R[1][1] + R[2][2];
  Quat q;
  if (tr >= R[0][0] && tr >= R[1][1] && tr >= R[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + tr);
    q = {0.25 * s, (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s};
  } else if (R[0][0] >= R[1][1] && R[0][0] >= R[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + R[0][0] - R[1][1] - R[2][2]);
    q = {(R[2][1] - R[1][2]) / s, 0.25 * s, (R[0][1] + R[1][0]) / s, (R[0][2] + R[2][0]) / s};
  } else if (R[1][1] >= R[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + R[1][1] - R[0][0] - R[2][2]);
    q = {(R[0][2] - R[2][0]) / s, (R[0][1] + R[1][0]) / s, 0.25 * s, (R[1][2] + R[2][1]) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R[2][2] - R[0][0] - R[1][1]);
    q = {(R[1][0] - R[0][1]) / s, (R[0][2] + R[2][0]) / s, (R[1][2] + R[2][1]) / s, 0.25 * s};
  }
  return quat_normalized(q);
}

Vec3 quat_rotate(const Quat& q, const Vec3& v) {
  double R[3][3];
  quat_to_matrix(q, R);
  return {R[0][0] * v[0] + R[0][1] * v[1] + R[0][2] * v[2], R[1][0] * v[0] + R[1][1] * v[1] + R[1][2] * v[2],
          R[2][0] * v[0] + R[2][1] * v[1] + R[2][2] * v[2]};
}

void anchor_rate(const double* qr, const Vec3& omega0, const Vec3& gamma0, double* rate) {
  const Quat q{qr[0], qr[1], qr[2], qr[3]};
  const Quat dq = quat_mul(q, Quat{0.0, 0.5 * omega0[0], 0.5 * omega0[1], 0.5 * omega0[2]});
  for (int j = 0; j < 4; ++j) rate[j] = dq[j];
  const Vec3 v = quat_rotate(quat_normalized(q), gamma0);
  for (int j = 0; j < 3; ++j) rate[4 + j] = v[j];
}

namespace {
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
constexpr int kRows = 6;  // Omega1..3, Gamma1..3
}  // namespace

Reconstructor::Reconstructor(std::size_t N, double L, double max_turn)
    : N_(N), L_(L), M_(N / 2 + 1), max_turn_(max_turn) {
  if (N < 2 || !(L > 0.0)) throw InputError("reconstruction: need N >= 2 and L > 0");
  real_ = static_cast<double*>(fftw_malloc(sizeof(double) * N * kRows));
  spec_ = fftw_malloc(sizeof(fftw_complex) * M_ * kRows);
  const int n = static_cast<int>(N), m = static_cast<int>(M_);
  {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    forward_ = fftw_plan_many_dft_r2c(1, &n, kRows, real_, nullptr, 1, n, static_cast<fftw_complex*>(spec_),
                                      nullptr, 1, m, FFTW_ESTIMATE);
    backward_ = fftw_plan_many_dft_c2r(1, &n, kRows, static_cast<fftw_complex*>(spec_), nullptr, 1, m, real_,
                                       nullptr, 1, n, FFTW_ESTIMATE);
  }
  coef_.resize(2 * M_ * kRows);
}

Reconstructor::~Reconstructor() {
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  fftw_destroy_plan(static_cast<fftw_plan>(forward_));
  fftw_destroy_plan(static_cast<fftw_plan>(backward_));
  fftw_free(real_);
  fftw_free(spec_);
}

void Reconstructor::interpolate(const double* y) {
  const std::size_t N = N_;
  std::copy(y + 9 * N, y + 12 * N, real_);         // Omega
  std::copy(y + 6 * N, y + 9 * N, real_ + 3 * N);  // Gamma
  // Substeps so that each Magnus step turns the frame by <= ~0.05 rad
  // (the 4th-order error constant grows with (h |Omega|)^4).
  double wmax = 0.0;
  for (std::size_t i = 0; i < N; ++i)
    wmax = std::max(wmax, std::sqrt(real_[i] * real_[i] + real_[N + i] * real_[N + i] +
                                    real_[2 * N + i] * real_[2 * N + i]));
  const double h = L_ / static_cast<double>(N);
  substeps_ = std::clamp(static_cast<int>(std::ceil(std::min(h * wmax / max_turn_, 64.0))), 1, 64);
  fftw_execute(static_cast<fftw_plan>(forward_));
  auto* spec = static_cast<fftw_complex*>(spec_);
  for (std::size_t j = 0; j < M_ * kRows; ++j) {
    coef_[2 * j] = spec[j][0] / static_cast<double>(N);
    coef_[2 * j + 1] = spec[j][1] / static_cast<double>(N);
  }
  const double c[2] = {0.5 - std::sqrt(3.0) / 6.0, 0.5 + std::sqrt(3.0) / 6.0};
  at_.resize(static_cast<std::size_t>(2 * substeps_) * kRows * N);
  // The shifts' phases depend on the number of substeps only: kept until it changes
  // (the same values as computed afresh; a closure projection sweeps several times a step).
  if (shift_substeps_ != substeps_) {
    shift_.resize(static_cast<std::size_t>(2 * substeps_) * 2 * M_);
    for (int sub = 0; sub < substeps_; ++sub)
      for (int a = 0; a < 2; ++a) {
        const double delta = (sub + c[a]) * h / substeps_;
        double* cs_sn = shift_.data() + static_cast<std::size_t>(2 * sub + a) * 2 * M_;
        for (std::size_t j = 0; j < M_; ++j) {
          const double k = 2.0 * std::numbers::pi * static_cast<double>(j) / L_;
          const bool nyquist = N % 2 == 0 && j == N / 2;
          // Nyquist mode as the real cosine mode: shifted by cos(k delta)
          cs_sn[2 * j] = std::cos(k * delta);
          cs_sn[2 * j + 1] = nyquist ? 0.0 : std::sin(k * delta);
        }
      }
    shift_substeps_ = substeps_;
  }
  for (int sub = 0; sub < substeps_; ++sub) {
    for (int a = 0; a < 2; ++a) {
      const double* cs_sn = shift_.data() + static_cast<std::size_t>(2 * sub + a) * 2 * M_;
      for (std::size_t j = 0; j < M_; ++j) {
        const bool nyquist = N % 2 == 0 && j == N / 2;
        const double cs = cs_sn[2 * j], sn = cs_sn[2 * j + 1];
        for (int r = 0; r < kRows; ++r) {
          const double re = coef_[2 * (r * M_ + j)], im = nyquist ? 0.0 : coef_[2 * (r * M_ + j) + 1];
          spec[r * M_ + j][0] = re * cs - im * sn;
          spec[r * M_ + j][1] = re * sn + im * cs;
        }
      }
      fftw_execute(static_cast<fftw_plan>(backward_));
      std::copy(real_, real_ + kRows * N, at_.begin() + (2 * sub + a) * kRows * N);
    }
  }
}

void Reconstructor::magnus_step(std::size_t i, int sub, double h, Quat& q, Vec3& r) const {
  const std::size_t N = N_;
  const double* a1 = at_.data() + (2 * sub) * kRows * N;
  const double* a2 = at_.data() + (2 * sub + 1) * kRows * N;
  const Vec3 W1{a1[0 * N + i], a1[1 * N + i], a1[2 * N + i]};
  const Vec3 V1{a1[3 * N + i], a1[4 * N + i], a1[5 * N + i]};
  const Vec3 W2{a2[0 * N + i], a2[1 * N + i], a2[2 * N + i]};
  const Vec3 V2{a2[3 * N + i], a2[4 * N + i], a2[5 * N + i]};
  const double k3 = std::sqrt(3.0) / 12.0 * h * h;
  const Vec3 WxW = cross(W1, W2);
  const Vec3 c12 = cross(W1, V2), c21 = cross(W2, V1);
  Vec3 phi, u;
  for (int a = 0; a < 3; ++a) {
    phi[a] = 0.5 * h * (W1[a] + W2[a]) + k3 * WxW[a];
    u[a] = 0.5 * h * (V1[a] + V2[a]) + k3 * (c12[a] - c21[a]);
  }
  se3_advance(q, r, phi, u);
}

void se3_advance(Quat& q, Vec3& r, const Vec3& phi, const Vec3& u) {
  // SE(3) exponential: translation V u, V = I + b [phi]x + c [phi]x^2, rotation exp(phi).
  // The sweeps of a closure projection make millions of these, in a chain: one sine and
  // cosine of the half angle serve both (cos a = 1 - 2 sin^2(a/2), sin a = 2 sin(a/2)
  // cos(a/2)), one division, and a unit q times exp(phi) is renormalised by a Newton step
  // for 1 / |q| (exact to round-off when |q|^2 is within 1e-8 of 1) instead of sqrt and divide.
  const double a2n = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
  const double an = std::sqrt(a2n);
  const double sh = std::sin(0.5 * an), ch = std::cos(0.5 * an);
  double b, c, sa;
  if (an < 1e-2) {
    b = 0.5 - a2n / 24.0 + a2n * a2n / 720.0;
    c = 1.0 / 6.0 - a2n / 120.0 + a2n * a2n / 5040.0;
    sa = an < 1e-4 ? 0.5 - a2n / 48.0 : sh / an;  // sin(a/2) / a, its Taylor series near 0
  } else {
    const double inv = 1.0 / an, inv2 = inv * inv;
    b = 2.0 * sh * sh * inv2;
    c = (an - 2.0 * sh * ch) * inv2 * inv;
    sa = sh * inv;
  }
  const Vec3 pu = cross(phi, u);
  const Vec3 ppu = cross(phi, pu);
  Vec3 p;
  for (int a = 0; a < 3; ++a) p[a] = u[a] + b * pu[a] + c * ppu[a];
  const Vec3 dp = quat_rotate(q, p);
  for (int a = 0; a < 3; ++a) r[a] += dp[a];
  const Quat qe = quat_mul(q, Quat{ch, sa * phi[0], sa * phi[1], sa * phi[2]});
  const double n2 = qe[0] * qe[0] + qe[1] * qe[1] + qe[2] * qe[2] + qe[3] * qe[3];
  const double inv_n = std::abs(n2 - 1.0) < 1e-8 ? 1.5 - 0.5 * n2 : 1.0 / std::sqrt(n2);
  q = {qe[0] * inv_n, qe[1] * inv_n, qe[2] * inv_n, qe[3] * inv_n};
}

Reconstructor::End Reconstructor::sweep(const double* y, const Quat& q0, const Vec3& r0, double* centerline,
                                        double* directors) {
  interpolate(y);
  const std::size_t N = N_;
  const double h = L_ / static_cast<double>(N);
  Quat q = quat_normalized(q0);
  Vec3 r = r0;
  norm_error_ = 0.0;
  for (std::size_t i = 0; i <= N; ++i) {
    if (i < N) {
      double R[3][3];
      quat_to_matrix(q, R);
      if (centerline)
        for (int a = 0; a < 3; ++a) centerline[3 * i + a] = r[a];
      if (directors)
        for (int a = 0; a < 3; ++a)
          for (int k = 0; k < 3; ++k) directors[9 * i + 3 * a + k] = R[a][k];
      for (int k = 0; k < 3; ++k) {
        const double n2 = R[0][k] * R[0][k] + R[1][k] * R[1][k] + R[2][k] * R[2][k];
        norm_error_ = std::max(norm_error_, std::abs(std::sqrt(n2) - 1.0));
      }
    }
    if (i == N) break;
    for (int sub = 0; sub < substeps_; ++sub) magnus_step(i, sub, h / substeps_, q, r);
  }
  return {q, r};
}

}  // namespace rodcore
