#include "rodcore/thermal.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "rodcore/closure.hpp"
#include "rodcore/error.hpp"
#include "rodcore/gaussian.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/reconstruction.hpp"

namespace rodcore {
namespace {

using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using V3 = Eigen::Vector3d;

// What a Philox counter is used for (its second word, with the block number):
// the streams of one seed never share a counter.
enum Stream : std::uint32_t { kStrainSample = 1, kVelocitySample = 2, kBath = 3 };

std::array<std::uint32_t, 2> key_of(unsigned long long seed) {
  return {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)};
}

// Six standard normal numbers for grid point i of a stream at a step.
void normals6(std::array<std::uint32_t, 2> key, Stream stream, unsigned long long step, std::size_t i,
              double z[6]) {
  GaussianStream g(key, static_cast<std::uint32_t>(i), stream << 8, static_cast<std::uint32_t>(step),
                   static_cast<std::uint32_t>(step >> 32));
  g.six(z);
}

// K (6 x 6) or I (3 x 3) of point i as an Eigen matrix.
Mat6 K_matrix(const MaterialField& mf, std::size_t i) {
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> M;
  mf.K_at(i, M.data());
  return M;
}
Mat3 I_matrix(const MaterialField& mf, std::size_t i) {
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> M;
  mf.I_at(i, M.data());
  return M;
}

// Frames of a state: directors R_i (columns d_k) and centerline r_i, from
// the frame (identity, 0) at s = 0.
struct Frames {
  std::vector<Mat3> R;
  std::vector<V3> r;
};

Frames frames_of(Reconstructor& rec, const std::vector<double>& y, std::size_t N) {
  std::vector<double> cl(3 * N), dir(9 * N);
  rec.sweep(y.data(), Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, cl.data(), dir.data());
  Frames f;
  f.R.resize(N);
  f.r.resize(N);
  for (std::size_t i = 0; i < N; ++i) {
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) f.R[i](a, k) = dir[9 * i + 3 * a + k];
    f.r[i] = V3(cl[3 * i], cl[3 * i + 1], cl[3 * i + 2]);
  }
  return f;
}

std::string num(double x) { return message_number(x, 3); }

// Closing a sample the chord steps cannot close (a ring many persistence lengths long,
// whose sample is a random coil far from the linearisation's circle): continuation in the
// sample's amplitude. The strains y + a e_lin + c are kept closed while a goes from 0 (y
// itself, closed) to 1, the correction c by Newton steps re-linearised at every trial
// state (the sampler's six directions K_i^-1 B_i^T of that state); a stage that does not
// converge is halved. Each Newton step is the least change in the energy metric at its own
// linearisation, so c stays a sum of smooth, long-wave corrections and the sample's local
// statistics are the linear sample's. On exit e = e_lin + c (a = 1) when `gap` <= tol.
// A phantom ring (the sampler knows no contact) may pass through itself on the way: the
// closed sample's Lk can differ from the initial state's by an even number.
struct Continuation {
  int stages = 0, sweeps = 0;
  double gap = std::numeric_limits<double>::infinity();
};

Continuation close_by_continuation(ClosureProjector& closure, const std::vector<double>& y,
                                   std::vector<double>& e, const RigidMotion& target, double tol) {
  const std::size_t n6 = e.size();
  const std::vector<double> e_lin = e;
  std::vector<double> c(n6, 0.0), c_try(n6), trial(y.size());
  Continuation out;
  constexpr int kMaxSweeps = 2000, kNewton = 12;
  constexpr double kStageTol = 1e-8;  // intermediate stages: close enough to start the next
  double a = 0.0, da = 1.0;
  while (a < 1.0 && out.sweeps < kMaxSweeps && da > 1e-6) {
    const double a_try = std::min(1.0, a + da);
    const double want = a_try < 1.0 ? kStageTol : tol;
    c_try = c;
    double prev = std::numeric_limits<double>::infinity(), gap = prev;
    bool ok = false;
    for (int k = 0; k < kNewton && out.sweeps < kMaxSweeps; ++k) {
      trial = y;
      for (std::size_t m = 0; m < n6; ++m) trial[y.size() - n6 + m] += a_try * e_lin[m] + c_try[m];
      const auto d = ClosureProjector::defect(closure.holonomy(trial.data()), target);
      ++out.sweeps;
      gap = closure.size(d);
      if (!std::isfinite(gap) || (k > 0 && gap > 0.5 * prev && gap > want)) break;
      if (gap <= want) {
        ok = true;
        break;
      }
      prev = gap;
      closure.linearise();  // at the trial state just swept
      closure.remove(d, c_try.data());
    }
    if (ok) {
      a = a_try;
      c.swap(c_try);
      ++out.stages;
      out.gap = gap;
      da = std::min(1.0, 2.0 * da);
    } else {
      da *= 0.5;
    }
  }
  if (a < 1.0) {
    out.gap = std::numeric_limits<double>::infinity();
    return out;
  }
  for (std::size_t m = 0; m < n6; ++m) e[m] = e_lin[m] + c[m];
  return out;
}

}  // namespace

double kinetic_kT(const double* y, std::size_t N, double h, const MaterialField& mf) {
  double twice_ke = 0.0;
  double I[9];
  mf.I_at(0, I);
  const bool per_point = mf.kind == MaterialKind::per_point;
  for (std::size_t i = 0; i < N; ++i) {
    if (per_point) mf.I_at(i, I);
    const double g[3] = {y[i], y[N + i], y[2 * N + i]};
    const double w[3] = {y[3 * N + i], y[4 * N + i], y[5 * N + i]};
    double kr = 0.0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) kr += I[r * 3 + c] * (w[r] * w[c]);
    twice_ke += mf.rho_at(i) * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) + kr;
  }
  return h * twice_ke / (6.0 * static_cast<double>(N));
}

ThermalSampleReport add_thermal_sample(std::vector<double>& y, double L, const MaterialField& mf, double kT,
                                       unsigned long long seed) {
  const std::size_t N = mf.N;
  if (y.size() != 12 * N) throw Error("add_thermal_sample: the state must hold 12 N values");
  ThermalSampleReport rep;
  if (!(kT > 0.0)) {
    rep.note = "no thermal sample (kT = 0)";
    return rep;
  }
  const double h = L / static_cast<double>(N);
  const auto key = key_of(seed);
  Reconstructor rec(N, L);

  // ---- strains: e_i = (kT / h)^1/2 U_i^-1 xi, K_i = U_i^T U_i
  const bool per_point = mf.kind == MaterialKind::per_point;
  std::vector<Eigen::LLT<Mat6>> chol(per_point ? N : 1);
  for (std::size_t p = 0; p < chol.size(); ++p) chol[p].compute(K_matrix(mf, p));
  std::vector<double> e(6 * N);  // (dGamma, dOmega): 6 rows of N, as the state's strain rows
  const double sd = std::sqrt(kT / h);
  for (std::size_t i = 0; i < N; ++i) {
    double z[6];
    normals6(key, kStrainSample, 0, i, z);
    const Vec6 ei = sd * chol[per_point ? i : 0].matrixU().solve(Eigen::Map<const Vec6>(z));
    for (int r = 0; r < 6; ++r) e[r * N + i] = ei(r);
  }

  // ---- closure: condition on the holonomy (projection in the metric K / h,
  // along the six directions of the reference state: closure.hpp)
  ClosureProjector closure(N, L, mf);
  const RigidMotion ref_holonomy = closure.holonomy(y.data());
  closure.linearise();
  closure.remove(closure.linear_change(e.data()), e.data());
  std::vector<double> trial = y;
  auto apply = [&](std::vector<double>& out) {
    out = y;
    for (std::size_t k = 0; k < 6 * N; ++k) out[6 * N + k] += e[k];
  };
  // Chord-Newton on the holonomy of the reconstruction (the same six
  // directions): exact closure where the linearisation is good enough to
  // converge; else continuation (close_by_continuation); else the linear-order
  // sample is kept and the gap reported.
  const std::vector<double> e_linear = e;
  apply(trial);
  auto err = ClosureProjector::defect(closure.holonomy(trial.data()), ref_holonomy);
  const double linear_gap = closure.size(err);
  double gap = linear_gap;
  int it = 0;
  const double tol = 1e-12;
  while (gap > tol && it < 50) {
    closure.remove(err, e.data());
    apply(trial);
    err = ClosureProjector::defect(closure.holonomy(trial.data()), ref_holonomy);
    const double next = closure.size(err);
    ++it;
    // Stagnated (round-off), diverged, or converging too slowly to reach
    // round-off (the chord steps of a good linearisation gain ~10x each).
    const bool slow = next > 0.5 * gap;
    gap = next;
    if (slow) break;
  }
  // Continuation for a ring only: a ring left open loses its topology (Lk, Tw, Wr) and its
  // contact geometry; a box-held rod closed at linear order is brought onto its box by the
  // run's projections (docs/thermal.md, "Closure in a run").
  const auto ref_twist = ClosureProjector::defect(ref_holonomy, RigidMotion{});
  const bool ring = V3(ref_twist[0], ref_twist[1], ref_twist[2]).norm() < 1e-6 &&
                    V3(ref_twist[3], ref_twist[4], ref_twist[5]).norm() < 1e-6 * std::max(1.0, L);
  if (gap > 1e-9 && ring) {
    e = e_linear;
    const Continuation c = close_by_continuation(closure, y, e, ref_holonomy, tol);
    rep.closure_stages = c.stages;
    it += c.sweeps;
    gap = c.gap;
    apply(trial);
  }
  if (gap <= 1e-9) {
    rep.closure_exact = true;
    rep.closure_iterations = it;
    rep.closure_residual = gap;
  } else {
    e = e_linear;
    apply(trial);
    rep.closure_residual = linear_gap;
  }
  y = trial;
  const Frames now = frames_of(rec, y, N);

  // ---- velocities, then zero momenta (frames of the sampled configuration)
  std::vector<V3> gam(N), om(N);
  std::vector<Mat3> Im(per_point ? N : 1);
  std::vector<Eigen::LLT<Mat3>> Ichol(per_point ? N : 1);
  for (std::size_t p = 0; p < Im.size(); ++p) {
    Im[p] = I_matrix(mf, p);
    Ichol[p].compute(Im[p]);
  }
  for (std::size_t i = 0; i < N; ++i) {
    double z[6];
    normals6(key, kVelocitySample, 0, i, z);
    gam[i] = std::sqrt(kT / (mf.rho_at(i) * h)) * V3(z[0], z[1], z[2]);
    om[i] = sd * Ichol[per_point ? i : 0].matrixU().solve(V3(z[3], z[4], z[5]));
  }
  const V3 hol_rot(ref_twist[0], ref_twist[1], ref_twist[2]),
      hol_tr(ref_twist[3], ref_twist[4], ref_twist[5]);
  const bool closed = ring;
  std::vector<V3> axes;
  if (closed) {
    axes = {V3::UnitX(), V3::UnitY(), V3::UnitZ()};
  } else {
    axes = {hol_rot.norm() > 1e-6 ? hol_rot.normalized() : hol_tr.normalized()};
  }
  V3 centre = V3::Zero();
  double mass = 0.0;
  for (std::size_t i = 0; i < N; ++i) {
    centre += mf.rho_at(i) * now.r[i];
    mass += mf.rho_at(i);
  }
  centre /= mass;
  // The rigid motions whose momenta the dynamics conserves: translations
  // gamma_i = R_i^T e_a, and rotations about u, gamma_i = R_i^T (u x r_i),
  // omega_i = R_i^T u.
  const int m = 3 + static_cast<int>(axes.size());
  std::vector<std::vector<V3>> fg(m, std::vector<V3>(N)), fw(m, std::vector<V3>(N, V3::Zero()));
  for (int a = 0; a < 3; ++a)
    for (std::size_t i = 0; i < N; ++i) fg[a][i] = now.R[i].transpose() * V3::Unit(a);
  for (std::size_t k = 0; k < axes.size(); ++k)
    for (std::size_t i = 0; i < N; ++i) {
      fg[3 + k][i] = now.R[i].transpose() * axes[k].cross(now.r[i] - centre);
      fw[3 + k][i] = now.R[i].transpose() * axes[k];
    }
  auto mass_dot = [&](const std::vector<V3>& ag, const std::vector<V3>& aw, const std::vector<V3>& bg,
                      const std::vector<V3>& bw) {
    double s = 0.0;
    for (std::size_t i = 0; i < N; ++i)
      s += mf.rho_at(i) * ag[i].dot(bg[i]) + aw[i].dot(Im[per_point ? i : 0] * bw[i]);
    return h * s;
  };
  Eigen::MatrixXd G(m, m);
  Eigen::VectorXd a(m);
  for (int k = 0; k < m; ++k) {
    a(k) = mass_dot(fg[k], fw[k], gam, om);
    for (int l = 0; l < m; ++l) G(k, l) = mass_dot(fg[k], fw[k], fg[l], fw[l]);
  }
  const Eigen::VectorXd c = G.ldlt().solve(a);
  for (int k = 0; k < m; ++k)
    for (std::size_t i = 0; i < N; ++i) {
      gam[i] -= c(k) * fg[k][i];
      om[i] -= c(k) * fw[k][i];
    }
  for (std::size_t i = 0; i < N; ++i)
    for (int r = 0; r < 3; ++r) {
      y[r * N + i] += gam[i](r);
      y[(3 + r) * N + i] += om[i](r);
    }
  rep.momentum_constraints = m;
  rep.note = "Boltzmann sample at kT = " + num(kT) + " (seed " + std::to_string(seed) + "): closure " +
             (rep.closure_exact
                  ? "exact to " + num(rep.closure_residual) + " after " +
                        std::to_string(rep.closure_iterations) + " Newton steps" +
                        (rep.closure_stages > 0 ? " (continuation in the sample's amplitude, stages: " +
                                                      std::to_string(rep.closure_stages) + ")"
                                                : std::string())
                  : "at linear order only (nonlinear gap " + num(rep.closure_residual) +
                        ": kT too large for the linearisation)") +
             "; zero linear momentum and angular momentum " +
             (closed ? "(closed ring: all three components)" : "about the axis");
  return rep;
}

LangevinBath::LangevinBath(const MaterialField& mf, double h, double kT,
                           std::array<double, 2> friction_translational,
                           std::array<double, 2> friction_rotational, double tau, unsigned long long seed)
    : N_(mf.N), per_point_(mf.kind == MaterialKind::per_point), noise_(kT > 0.0), key_(key_of(seed)) {
  for (double z : {friction_translational[0], friction_translational[1], friction_rotational[0],
                   friction_rotational[1], kT, tau})
    if (!(z >= 0.0) || !std::isfinite(z))
      throw InputError("Langevin bath: frictions, kT and the step must be finite and >= 0");
  const std::size_t points = per_point_ ? N_ : 1;
  coef_.assign(24 * points, 0.0);
  const double zt[3] = {friction_translational[1], friction_translational[1], friction_translational[0]};
  const Mat3 Zr = V3(friction_rotational[1], friction_rotational[1], friction_rotational[0]).asDiagonal();
  for (std::size_t p = 0; p < points; ++p) {
    double* k = coef_.data() + 24 * p;
    const double rho = mf.rho_at(p);
    for (int a = 0; a < 3; ++a) {
      const double c = std::exp(-zt[a] * tau / rho);
      k[a] = c;
      k[3 + a] = std::sqrt(kT * (1.0 - c * c) / (rho * h));
    }
    // I = V diag(l) V^T; M = I^-1/2 Z I^-1/2 = Q diag(mu) Q^T.
    const Eigen::SelfAdjointEigenSolver<Mat3> ei(I_matrix(mf, p));
    const Mat3 Ih =
        ei.eigenvectors() * ei.eigenvalues().cwiseSqrt().asDiagonal() * ei.eigenvectors().transpose();
    const Mat3 Imh = ei.eigenvectors() * ei.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal() *
                     ei.eigenvectors().transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> em(Imh * Zr * Imh);
    const V3 c = (-tau * em.eigenvalues().array()).exp().matrix();
    const V3 s = (1.0 - c.array().square()).sqrt().matrix();
    const Mat3& Q = em.eigenvectors();
    // No rotational friction: omega untouched, exactly (a frictionless
    // Langevin step is then the RK4 step bit for bit).
    const bool still = friction_rotational[0] == 0.0 && friction_rotational[1] == 0.0;
    const Mat3 Bm = still ? Mat3::Identity() : Mat3(Imh * Q * c.asDiagonal() * Q.transpose() * Ih);
    const Mat3 Sm = std::sqrt(kT / h) * Imh * Q * s.asDiagonal();
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) {
        k[6 + 3 * r + col] = Bm(r, col);
        k[15 + 3 * r + col] = Sm(r, col);
      }
  }
}

void LangevinBath::apply(long step, double* y) const {
  const std::size_t N = N_;
  const Stream stream = kBath;
  for (std::size_t i = 0; i < N; ++i) {
    const double* k = coef_.data() + (per_point_ ? 24 * i : 0);
    double z[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    if (noise_) normals6(key_, stream, static_cast<unsigned long long>(step), i, z);
    for (int a = 0; a < 3; ++a) y[a * N + i] = k[a] * y[a * N + i] + k[3 + a] * z[a];
    const double w[3] = {y[3 * N + i], y[4 * N + i], y[5 * N + i]};
    for (int r = 0; r < 3; ++r) {
      const double* Br = k + 6 + 3 * r;
      const double* Sr = k + 15 + 3 * r;
      y[(3 + r) * N + i] =
          Br[0] * w[0] + Br[1] * w[1] + Br[2] * w[2] + (Sr[0] * z[3] + Sr[1] * z[4] + Sr[2] * z[5]);
    }
  }
}

}  // namespace rodcore
