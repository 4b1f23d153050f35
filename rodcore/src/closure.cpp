#include "rodcore/closure.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "rodcore/error.hpp"

namespace rodcore {
namespace {

using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using V3 = Eigen::Vector3d;

Mat3 cross_matrix(const V3& r) {
  Mat3 X;
  X << 0.0, -r(2), r(1), r(2), 0.0, -r(0), -r(1), r(0), 0.0;
  return X;
}

Mat3 rotation(const Quat& q) {
  double R[3][3];
  quat_to_matrix(quat_normalized(q), R);
  Mat3 M;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) M(a, b) = R[a][b];
  return M;
}

// Rotation vector of a unit quaternion (the short way round).
V3 rotation_vector(const Quat& q) {
  const double w = q[0] < 0.0 ? -q[0] : q[0];
  const double sgn = q[0] < 0.0 ? -1.0 : 1.0;
  const V3 v(sgn * q[1], sgn * q[2], sgn * q[3]);
  const double s = v.norm();
  if (s == 0.0) return V3::Zero();
  return (2.0 * std::atan2(s, w) / s) * v;
}

Quat conjugate(const Quat& q) { return {q[0], -q[1], -q[2], -q[3]}; }

// The defect (w, r) of defect() with its translation replaced by the exact SE(3) logarithm's,
// V(w)^-1 r, V^-1 = I - W / 2 + (1 - (a / 2) cot(a / 2)) / a^2 W^2 (W = [w]x, a = |w|): the
// twist whose exponential is the defect's motion, not only to first order. A Newton step
// that removes it moves the frame at s = L along the screw that closes it; with the
// first-order translation the step leaves |w| |r| / 2 (about a third of a 10.5-kbp ring's
// gap after a 100-ps step, whose w is ~1 rad).
std::array<double, 6> screw(const std::array<double, 6>& d) {
  const V3 w(d[0], d[1], d[2]), r(d[3], d[4], d[5]);
  const double a2 = w.squaredNorm(), a = std::sqrt(a2);
  const double c = a < 1e-3 ? 1.0 / 12.0 + a2 / 720.0 : (1.0 - 0.5 * a / std::tan(0.5 * a)) / a2;
  const V3 wr = w.cross(r);
  const V3 v = r - 0.5 * wr + c * w.cross(wr);
  return {d[0], d[1], d[2], v(0), v(1), v(2)};
}

}  // namespace

RigidMotion compose(const RigidMotion& a, const RigidMotion& b) {
  const Vec3 Rb = quat_rotate(quat_normalized(a.q), b.r);
  return {quat_normalized(quat_mul(a.q, b.q)), {a.r[0] + Rb[0], a.r[1] + Rb[1], a.r[2] + Rb[2]}};
}

RigidMotion inverse(const RigidMotion& a) {
  const Quat qi = conjugate(quat_normalized(a.q));
  const Vec3 r = quat_rotate(qi, a.r);
  return {qi, {-r[0], -r[1], -r[2]}};
}

RigidMotion holonomy_for(const RigidMotion& T, const RigidMotion& g0) {
  return compose(inverse(g0), compose(T, g0));
}

RigidMotion box_motion(const RigidMotion& H, const RigidMotion& g0) {
  return compose(g0, compose(H, inverse(g0)));
}

struct ClosureProjector::Impl {
  std::size_t N;
  double L, h;
  Reconstructor rec;
  std::vector<Mat6> Kinv;  // one (uniform material) or N
  std::vector<double> centerline, directors;
  std::vector<Mat6> B;  // h Ad_g(s_i) at the frames of the last sweep
  Eigen::LDLT<Mat6> S;
  Impl(std::size_t n, double length, const MaterialField& mf, double max_turn)
      : N(n),
        L(length),
        h(length / static_cast<double>(n)),
        rec(n, length, max_turn),
        centerline(3 * n),
        directors(9 * n),
        B(n) {
    const bool per_point = mf.kind == MaterialKind::per_point;
    Kinv.resize(per_point ? N : 1);
    for (std::size_t p = 0; p < Kinv.size(); ++p) {
      Eigen::Matrix<double, 6, 6, Eigen::RowMajor> K;
      mf.K_at(p, K.data());
      Kinv[p] = Mat6(K).llt().solve(Mat6::Identity());
    }
  }
  const Mat6& Kinv_at(std::size_t i) const { return Kinv[Kinv.size() == 1 ? 0 : i]; }
};

ClosureProjector::ClosureProjector(std::size_t N, double L, const MaterialField& mf, double max_turn)
    : impl_(std::make_unique<Impl>(N, L, mf, max_turn)) {
  if (mf.N != N) throw Error("ClosureProjector: the material has " + std::to_string(mf.N) + " points, not N");
}

ClosureProjector::~ClosureProjector() = default;

RigidMotion ClosureProjector::holonomy(const double* y) {
  Impl& d = *impl_;
  const auto end =
      d.rec.sweep(y, Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, d.centerline.data(), d.directors.data());
  return {quat_normalized(end.q), end.r};
}

void ClosureProjector::linearise() {
  Impl& d = *impl_;
  Mat6 S;
  Mat3 S_rr = Mat3::Zero(), S_rt = Mat3::Zero(), S_tt = Mat3::Zero();
  for (std::size_t i = 0; i < d.N; ++i) {
    Mat3 R;
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) R(a, k) = d.directors[9 * i + 3 * a + k];
    const V3 r(d.centerline[3 * i], d.centerline[3 * i + 1], d.centerline[3 * i + 2]);
    // d(g(L)) g(L)^-1 = int Ad_g(s) d(Omega, Gamma) ds, Ad_(R, r) (w, v) = (R w, R v + r x R w);
    // columns in the strain order (Gamma, Omega).
    const Mat3 X = cross_matrix(r);
    Mat6& Bi = d.B[i];
    Bi.block<3, 3>(0, 0).setZero();
    Bi.block<3, 3>(0, 3) = d.h * R;
    Bi.block<3, 3>(3, 0) = d.h * R;
    Bi.block<3, 3>(3, 3) = d.h * X * R;
    // B_i K_i^-1 B_i^T by 3 x 3 blocks (B_i's zero block and the symmetry spared), with
    // M_ab = R (K_i^-1)_ab R^T (a, b = G, O): rot-rot M_OO, rot-trans M_OG - M_OO X,
    // trans-trans M_GG + X M_OG - M_GO X - X M_OO X (X = [r]x, X^T = -X); times h^2.
    const Mat6& Ki = d.Kinv_at(i);
    const Mat3 M_OO = R * Ki.block<3, 3>(3, 3) * R.transpose();
    const Mat3 M_OG = R * Ki.block<3, 3>(3, 0) * R.transpose();
    const Mat3 M_GG = R * Ki.block<3, 3>(0, 0) * R.transpose();
    const Mat3 M_OO_X = M_OO * X;
    const Mat3 XM_OG = X * M_OG;
    S_rr += M_OO;
    S_rt += M_OG - M_OO_X;
    S_tt += M_GG + XM_OG + XM_OG.transpose() - X * M_OO_X;
  }
  const double h2 = d.h * d.h;
  S.block<3, 3>(0, 0) = h2 * S_rr;
  S.block<3, 3>(0, 3) = h2 * S_rt;
  S.block<3, 3>(3, 0) = h2 * S_rt.transpose();
  S.block<3, 3>(3, 3) = h2 * S_tt;
  d.S.compute(S);
}

std::array<double, 6> ClosureProjector::linear_change(const double* e) const {
  const Impl& d = *impl_;
  Vec6 sum = Vec6::Zero();
  for (std::size_t i = 0; i < d.N; ++i) {
    Vec6 ei;
    for (int r = 0; r < 6; ++r) ei(r) = e[r * d.N + i];
    sum += d.B[i] * ei;
  }
  return {sum(0), sum(1), sum(2), sum(3), sum(4), sum(5)};
}

void ClosureProjector::remove(const std::array<double, 6>& defect, double* e) const {
  const Impl& d = *impl_;
  const Vec6 lambda = d.S.solve(Eigen::Map<const Vec6>(defect.data()));
  for (std::size_t i = 0; i < d.N; ++i) {
    const Vec6 de = d.Kinv_at(i) * (d.B[i].transpose() * lambda);
    for (int r = 0; r < 6; ++r) e[r * d.N + i] -= de(r);
  }
}

std::array<double, 6> ClosureProjector::defect(const RigidMotion& now, const RigidMotion& target) {
  const Quat dq = quat_mul(quat_normalized(now.q), conjugate(quat_normalized(target.q)));
  const V3 w = rotation_vector(dq);
  const V3 v = V3(now.r[0], now.r[1], now.r[2]) - rotation(dq) * V3(target.r[0], target.r[1], target.r[2]);
  return {w(0), w(1), w(2), v(0), v(1), v(2)};
}

double ClosureProjector::size(const std::array<double, 6>& d) const {
  const double rot = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double tr = std::sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
  return std::max(rot, tr / std::max(1.0, impl_->L));
}

ClosureProjector::Result ClosureProjector::project(double* y, const RigidMotion& target, int steps,
                                                   double tolerance, bool relinearise) {
  Impl& d = *impl_;
  Result res;
  std::array<double, 6> gap = defect(holonomy(y), target);
  res.gap_before = size(gap);
  if (res.gap_before <= tolerance) return res;
  linearise();
  double* strains = y + 6 * d.N;  // rows Gamma1..3, Omega1..3 of the state
  for (int k = 0; k < steps; ++k) {
    remove(relinearise ? screw(gap) : gap, strains);
    ++res.steps;
    if (k + 1 < steps) {
      gap = defect(holonomy(y), target);
      if (relinearise) {
        if (size(gap) <= tolerance) break;
        linearise();  // at the frames of the sweep just made: Newton, not chord
      }
    }
  }
  return res;
}

}  // namespace rodcore
