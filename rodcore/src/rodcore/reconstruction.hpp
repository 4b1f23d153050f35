// Centerline and directors from the internal fields (paper Eqs 1-2).
//
// Directors are unit quaternions q (body -> lab rotation R(q), columns d_k),
// so |d_k| = 1 to round-off by construction:
//   along s:  dq/ds = 1/2 q * (0, Omega),  dr/ds = R(q) Gamma,
//   in time (at s = 0 only): dq/dt = 1/2 q * (0, omega), dr/dt = R(q) gamma.
// The sweep along s integrates the frame g = (R, r) in SE(3) with the
// 4th-order Magnus method (2-point Gauss):
//   xi_a = (Omega, Gamma)(s_i + c_a h), c_{1,2} = 1/2 -+ sqrt(3)/6,
//   theta = h/2 (xi_1 + xi_2) + sqrt(3)/12 h^2 [xi_1, xi_2],
//   [(W1,V1),(W2,V2)] = (W1 x W2, W1 x V2 - W2 x V1),
//   g_{i+1} = g_i exp(theta)  (exact SE(3) exponential),
// with the fields at the Gauss points from the Fourier interpolant (exact
// shift in Fourier space), so a uniform state (helix, ring) is reproduced
// exactly and smooth states to O(h^4). Each grid interval is split into m
// substeps with h |Omega|_max / m <= 0.05 (m <= 64), because the error
// constant grows like (h |Omega|)^4 (DNA: h Omega3 ~ 0.6 rad per base pair).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "rodcore/state.hpp"

namespace rodcore {

using Quat = std::array<double, 4>;  // (w, x, y, z)

Quat quat_mul(const Quat& a, const Quat& b);
// exp of a rotation vector theta: (cos |theta|/2, sin(|theta|/2) theta/|theta|)
Quat quat_exp(const Vec3& theta);
Quat quat_normalized(const Quat& q);
// R[a][k] = component a (x, y, z) of director d_k
void quat_to_matrix(const Quat& q, double R[3][3]);
Quat matrix_to_quat(const double R[3][3]);
Vec3 quat_rotate(const Quat& q, const Vec3& v);

// d/dt of the s = 0 anchor (q, r) given omega(0,t), gamma(0,t): 7 values
// (dq/dt, dr/dt); q need not be exactly normalised.
void anchor_rate(const double* q_r, const Vec3& omega0, const Vec3& gamma0, double* rate);

// g <- g exp(theta) for the frame g = (R(q), r) and theta = (phi, u) in se(3) (rotation
// phi, translation u, body frame): the exact SE(3) exponential, q renormalised.
void se3_advance(Quat& q, Vec3& r, const Vec3& phi, const Vec3& u);

class Reconstructor {
 public:
  // max_turn: largest frame rotation h |Omega| per Magnus substep (radians);
  // infinity disables substepping.
  explicit Reconstructor(std::size_t N, double L, double max_turn = 0.05);
  ~Reconstructor();
  Reconstructor(const Reconstructor&) = delete;
  Reconstructor& operator=(const Reconstructor&) = delete;

  // Sweep along s from the frame (q0, r0) at s = 0, using Omega and Gamma
  // of the state y (12 N). centerline: N x 3 (may be null), directors:
  // N x 3 x 3 [i][xyz][k] (may be null). Returns the frame at s = L.
  struct End {
    Quat q;
    Vec3 r;
  };
  End sweep(const double* y, const Quat& q0, const Vec3& r0, double* centerline, double* directors);

  // Largest | |d_k| - 1 | of the last sweep.
  double max_director_norm_error() const { return norm_error_; }

 private:
  void interpolate(const double* y);  // fills at_ (6 rows: Omega, Gamma per Gauss point)
  void magnus_step(std::size_t i, int sub, double h, Quat& q, Vec3& r) const;
  std::size_t N_;
  double L_;
  std::size_t M_;
  double* real_ = nullptr;
  void* spec_ = nullptr;  // fftw_complex
  void* forward_ = nullptr;
  void* backward_ = nullptr;
  std::vector<double> coef_;   // 6 x M spectrum (re, im interleaved)
  std::vector<double> at_;     // [substep][gauss point][6 rows][N]
  std::vector<double> shift_;  // [substep][gauss point][mode] (cos, sin) of the shift, for shift_substeps_
  int shift_substeps_ = 0;
  int substeps_ = 1;
  double max_turn_ = 0.05;
  double norm_error_ = 0.0;
};

}  // namespace rodcore
