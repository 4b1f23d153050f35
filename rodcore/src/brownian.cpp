#include "rodcore/brownian.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "rodcore/block_band.hpp"
#include "rodcore/error.hpp"
#include "rodcore/gaussian.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/reconstruction.hpp"

namespace rodcore {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6Block3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// The Philox streams of the Brownian noise (thermal.cpp uses 1..3 for the
// sample and the Langevin bath): a seed's streams never share a counter.
enum Stream : std::uint32_t { kEta1 = 4, kEta2 = 5 };

// Fixed-point iterations of the midpoint compatibility update: the first is the explicit
// (Ito) update, each further one gains a factor ~|dtheta| (~0.1 for DNA at 300 K).
constexpr int kMidpointIterations = 4;

void normals6(std::array<std::uint32_t, 2> key, Stream stream, unsigned long long step, std::size_t i,
              double z[6]) {
  GaussianStream g(key, static_cast<std::uint32_t>(i), stream << 8, static_cast<std::uint32_t>(step),
                   static_cast<std::uint32_t>(step >> 32));
  g.six(z);
}

// The stencil of a translation-invariant d/ds, read from its response to a unit
// impulse at point 0: (offset, weight) with f'_i = sum w f_{i + offset}.
std::vector<std::pair<int, double>> read_stencil(const DerivativeOperator& op) {
  const std::size_t N = op.N();
  std::vector<double> e(N, 0.0), d(N, 0.0);
  e[0] = 1.0;
  op.apply(e.data(), d.data(), 1);
  // d_i = w_{offset} with i + offset = 0 (mod N)
  double big = 0.0;
  for (double v : d) big = std::max(big, std::abs(v));
  std::vector<std::pair<int, double>> st;
  for (std::size_t i = 0; i < N; ++i)
    if (std::abs(d[i]) > 1e-12 * big) {
      long off = -static_cast<long>(i);
      if (off < -static_cast<long>(N) / 2) off += static_cast<long>(N);
      st.emplace_back(static_cast<int>(off), d[i]);
    }
  if (st.size() > 8 || 2 * st.size() + 1 > N)
    throw InputError("solver.time = \"brownian\" needs a banded d/ds (solver.space = \"fd4\"); " + op.name() +
                     " couples " + std::to_string(st.size()) + " points");
  return st;
}

// [v]x: [v]x a = v x a
Mat6Block3 cross3(const double v[3]) {
  Mat6Block3 X;
  X << 0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0;
  return X;
}

}  // namespace

// The implicit matrix Z + dt D^T K D in 6 x 6 blocks (block_band.hpp). Row i of D has the
// blocks E_o = w_o I + [o = 0] C_i at columns i + o, o in `offsets` (the stencil's and 0),
// C_i = [[Omega]x, [Gamma]x; 0, [Omega]x] the local cross products (Eqs 13-14).
struct BrownianStep::Solver {
  std::vector<int> offsets;    // ascending, 0 included
  std::vector<double> weight;  // w_o (0 where the stencil has none)
  std::vector<Mat6> K;         // K per point (or one)
  std::vector<Mat6> C;         // C_i at the step's start
  std::unique_ptr<CyclicBlockBand> band;
};

BrownianStep::~BrownianStep() = default;

BrownianStep::BrownianStep(std::size_t N, double L, const MaterialField& mf, const DerivativeOperator& op,
                           std::function<void(const double*, double*)> rhs,
                           std::array<double, 2> friction_translational,
                           std::array<double, 2> friction_rotational, double kT, double dt,
                           unsigned long long seed, Noise noise)
    : N_(N),
      h_(L / static_cast<double>(N)),
      kT_(kT),
      dt_(dt),
      noise_(noise),
      key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
      rhs_(std::move(rhs)),
      per_point_(mf.kind == MaterialKind::per_point),
      solver_(std::make_unique<Solver>()) {
  for (double z :
       {friction_translational[0], friction_translational[1], friction_rotational[0], friction_rotational[1]})
    if (!(z > 0.0) || !std::isfinite(z))
      throw InputError("solver.time = \"brownian\": every friction (thermal.friction_translational, "
                       "thermal.friction_rotational) must be > 0 (an overdamped rod moves by its friction)");
  if (!(kT >= 0.0) || !(dt > 0.0) || !std::isfinite(dt))
    throw InputError("solver.time = \"brownian\": kT >= 0 and solver.dt > 0 needed");
  stencil_ = read_stencil(op);
  Z_ = {friction_translational[1], friction_translational[1], friction_translational[0],
        friction_rotational[1],    friction_rotational[1],    friction_rotational[0]};
  const std::size_t P = per_point_ ? N : 1;
  K_.resize(36 * P);
  LK_.assign(36 * P, 0.0);
  I_.resize(9 * P);
  rho_.resize(P);
  for (std::size_t p = 0; p < P; ++p) {
    mf.K_at(p, K_.data() + 36 * p);
    mf.I_at(p, I_.data() + 9 * p);
    rho_[p] = mf.rho_at(p);
    const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> K(K_.data() + 36 * p);
    const Eigen::Matrix<double, 6, 6> Lk = K.llt().matrixL();
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(LK_.data() + 36 * p) = Lk;
  }
  Solver& s = *solver_;
  s.offsets.push_back(0);
  for (const auto& [off, w] : stencil_) s.offsets.push_back(off);
  std::sort(s.offsets.begin(), s.offsets.end());
  s.offsets.erase(std::unique(s.offsets.begin(), s.offsets.end()), s.offsets.end());
  s.weight.assign(s.offsets.size(), 0.0);
  for (const auto& [off, w] : stencil_)
    s.weight[static_cast<std::size_t>(std::find(s.offsets.begin(), s.offsets.end(), off) -
                                      s.offsets.begin())] += w;
  s.C.assign(N, Mat6::Zero());
  for (std::size_t p = 0; p < P; ++p)
    s.K.emplace_back(Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(K_.data() + 36 * p));
  // read_stencil keeps 2 (offsets) + 1 <= N, so the band's N >= 2 b + 1 holds for an fd4 stencil
  s.band = std::make_unique<CyclicBlockBand>(N, s.offsets.back() - s.offsets.front());
  y0_.resize(12 * N);
  f_.resize(12 * N);
  dx_.resize(6 * N);
}

void BrownianStep::apply(long step, double* y, double* anchor) {
  Eigen::VectorXd b = force_rhs(y);
  factorise(y);
  if (kT_ > 0.0) add_noise(step, b);
  solver_->band->solve(b.data());
  advance(step, b, y, anchor);
}

Eigen::VectorXd BrownianStep::force_rhs(double* y) {
  // force and torque per length at the step's start: the RHS at zero velocity
  const std::size_t N = N_;
  for (std::size_t k = 0; k < 6 * N; ++k) y[k] = 0.0;
  rhs_(y, f_.data());
  Eigen::VectorXd b(static_cast<long>(6 * N));
  for (std::size_t i = 0; i < N; ++i) {
    const std::size_t p = per_point_ ? i : 0;
    const double* I = I_.data() + 9 * p;
    for (int c = 0; c < 3; ++c) {
      b(6 * i + c) = dt_ * rho_[p] * f_[c * N + i];
      b(6 * i + 3 + c) =
          dt_ * (I[3 * c] * f_[3 * N + i] + I[3 * c + 1] * f_[4 * N + i] + I[3 * c + 2] * f_[5 * N + i]);
    }
  }
  return b;
}

void BrownianStep::factorise(const double* y) {
  // H = D^T K D by blocks: point i adds E_o1^T K_i E_o2 at block (i + o1, i + o2), and with
  // E_o = w_o I + [o = 0] C_i that is a sum of K_i, K_i C_i, C_i^T K_i and C_i^T K_i C_i.
  const std::size_t N = N_;
  Solver& s = *solver_;
  CyclicBlockBand& band = *s.band;
  band.set_zero();
  const long Nl = static_cast<long>(N);
  const std::size_t n_off = s.offsets.size();
  for (std::size_t i = 0; i < N; ++i) {
    const double G[3] = {y[6 * N + i], y[7 * N + i], y[8 * N + i]};
    const double O[3] = {y[9 * N + i], y[10 * N + i], y[11 * N + i]};
    Mat6& C = s.C[i];
    C.setZero();
    C.topLeftCorner<3, 3>() = cross3(O);      // Omega x dgamma
    C.topRightCorner<3, 3>() = cross3(G);     // -dtheta x Gamma = Gamma x dtheta
    C.bottomRightCorner<3, 3>() = cross3(O);  // -dtheta x Omega = Omega x dtheta
    const Mat6& K = s.K[per_point_ ? i : 0];
    const Mat6 KC = K * C;
    const Mat6 CtKC = C.transpose() * KC;
    for (std::size_t a = 0; a < n_off; ++a) {
      const int o1 = s.offsets[a];
      const double w1 = s.weight[a];
      const long row = ((static_cast<long>(i) + o1) % Nl + Nl) % Nl;
      for (std::size_t c = 0; c <= a; ++c) {  // o2 <= o1: the block (i + o1, i + o2) is lower
        const int o2 = s.offsets[c];
        const double w2 = s.weight[c];
        Mat6& blk = band.lower(static_cast<std::size_t>(row), o1 - o2);
        if (w1 * w2 != 0.0) blk.noalias() += (dt_ * w1 * w2) * K;
        if (o2 == 0 && w1 != 0.0) blk.noalias() += (dt_ * w1) * KC;
        if (o1 == 0 && w2 != 0.0) blk.noalias() += (dt_ * w2) * KC.transpose();
        if (o1 == 0 && o2 == 0) blk.noalias() += dt_ * CtKC;
      }
    }
  }
  for (std::size_t i = 0; i < N; ++i)
    for (int c = 0; c < 6; ++c) band.lower(i, 0)(c, c) += Z_[static_cast<std::size_t>(c)];
  if (!band.factorise())
    throw NumericalError("solver.time = \"brownian\": the implicit matrix Z + dt D^T K D is not positive "
                         "definite (non-finite strains?)");
}

void BrownianStep::add_noise(long step, Eigen::VectorXd& b) {
  // (2 kT dt / h)^1/2 Z^1/2 eta1 + dt (kT / h)^1/2 D^T L_K eta2, D^T by the blocks of
  // factorise(): (D^T u)_(i + o) += E_o^T u_i = w_o u_i + [o = 0] C_i^T u_i
  const std::size_t N = N_;
  const Solver& s = *solver_;
  const double a1 = std::sqrt(2.0 * kT_ * dt_ / h_);
  const double a2 = dt_ * std::sqrt(kT_ / h_);
  const bool second = noise_ == Noise::exact;
  const long Nl = static_cast<long>(N);
  for (std::size_t i = 0; i < N; ++i) {
    double z[6];
    normals6(key_, kEta1, static_cast<unsigned long long>(step), i, z);
    for (int c = 0; c < 6; ++c) b(6 * i + c) += a1 * std::sqrt(Z_[c]) * z[c];
  }
  if (!second) return;
  for (std::size_t i = 0; i < N; ++i) {
    double z[6];
    normals6(key_, kEta2, static_cast<unsigned long long>(step), i, z);
    const double* Lk = LK_.data() + 36 * (per_point_ ? i : 0);
    Vec6 u;
    for (int r = 0; r < 6; ++r) {
      double v = 0.0;
      for (int c = 0; c <= r; ++c) v += Lk[6 * r + c] * z[c];
      u(r) = a2 * v;
    }
    for (std::size_t k = 0; k < s.offsets.size(); ++k) {
      const long j = ((static_cast<long>(i) + s.offsets[k]) % Nl + Nl) % Nl;
      if (s.weight[k] != 0.0) b.segment<6>(6 * j) += s.weight[k] * u;
      if (s.offsets[k] == 0) b.segment<6>(6 * j).noalias() += s.C[i].transpose() * u;
    }
  }
}

void BrownianStep::advance(long step, const Eigen::VectorXd& dx, double* y, double* anchor) {
  const std::size_t N = N_;
  // the strains move by the RHS's compatibility rows (Eqs 13-14) with velocity dx
  for (std::size_t i = 0; i < N; ++i)
    for (int c = 0; c < 6; ++c) y[c * N + i] = dx(6 * i + c);
  // Midpoint in q of the compatibility, q_{n+1} = q_n + D((q_n + q_{n+1}) / 2) dx (fixed-point
  // iterations; D is affine in q, and |dtheta| << 1 makes each gain ~|dtheta|): the
  // Stratonovich form, whose mean second-order term is (kT / h) div(D M D^T) dt for small dt
  // (the Ito drift that makes exp(-E / kT) dGamma dOmega stationary) and stays bounded by the
  // step's own covariance of dx at any dt; the local cross products become Cayley rotations,
  // which keep |Gamma| and |Omega| under a rotation of the frame.
  std::copy(y + 6 * N, y + 12 * N, y0_.begin());
  for (int it = 0; it < kMidpointIterations; ++it) {
    if (it > 0)
      for (std::size_t k = 6 * N; k < 12 * N; ++k) y[k] = 0.5 * (y0_[k - 6 * N] + y[k]);
    rhs_(y, f_.data());
    for (std::size_t k = 6 * N; k < 12 * N; ++k) y[k] = y0_[k - 6 * N] + f_[k];
  }
  if (anchor) {
    Quat q{anchor[0], anchor[1], anchor[2], anchor[3]};
    Vec3 r{anchor[4], anchor[5], anchor[6]};
    se3_advance(q, r, Vec3{dx(3), dx(4), dx(5)}, Vec3{dx(0), dx(1), dx(2)});
    for (int k = 0; k < 4; ++k) anchor[k] = q[k];
    for (int k = 0; k < 3; ++k) anchor[4 + k] = r[k];
  }
  for (std::size_t k = 0; k < 6 * N; ++k) y[k] = 0.0;
  for (std::size_t k = 6 * N; k < 12 * N; ++k)
    if (!std::isfinite(y[k]))
      throw NumericalError("solver.time = \"brownian\": a non-finite strain after step " +
                           std::to_string(step));
}

}  // namespace rodcore
