#include "rodcore/passage_guard.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Dense>

#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/reconstruction.hpp"
#include "rodcore/topology.hpp"

namespace rodcore {
namespace {

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Distance between the segments p0 -> p1 and q0 -> q1 (the clamped closest points of the two
// lines, each parameter clamped and the other re-solved: exact for segments).
double segment_distance(const double* p0, const double* p1, const double* q0, const double* q1) {
  double d1[3], d2[3], r[3];
  for (int k = 0; k < 3; ++k) {
    d1[k] = p1[k] - p0[k];
    d2[k] = q1[k] - q0[k];
    r[k] = p0[k] - q0[k];
  }
  const double a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r), c = dot3(d1, r), b = dot3(d1, d2);
  const double den = a * e - b * b;
  double s = den > 1e-14 * a * e ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
  double t = e > 0.0 ? (b * s + f) / e : 0.0;
  if (t < 0.0 || t > 1.0) {
    t = std::clamp(t, 0.0, 1.0);
    s = a > 0.0 ? std::clamp((b * t - c) / a, 0.0, 1.0) : 0.0;
  }
  double d = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double v = r[k] + s * d1[k] - t * d2[k];
    d += v * v;
  }
  return std::sqrt(d);
}

// y <- the rigid motion of y that best superposes it on x (Kabsch): whether strands cross does not
// depend on a rigid motion of the whole, and without it the turn of the frame at s = 0, from
// which both are reconstructed, would swing the far side of a ring by its lever arm.
void superpose(const std::vector<double>& x, std::vector<double>& y) {
  const std::size_t n = x.size() / 3;
  Eigen::Vector3d cx = Eigen::Vector3d::Zero(), cy = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    cx += Eigen::Vector3d(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    cy += Eigen::Vector3d(y[3 * i], y[3 * i + 1], y[3 * i + 2]);
  }
  cx /= static_cast<double>(n);
  cy /= static_cast<double>(n);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i)
    A += (Eigen::Vector3d(y[3 * i], y[3 * i + 1], y[3 * i + 2]) - cy) *
         (Eigen::Vector3d(x[3 * i], x[3 * i + 1], x[3 * i + 2]) - cx).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  const Eigen::Matrix3d R = svd.matrixV() * S * svd.matrixU().transpose();  // R (y - cy) ~ x - cx
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = R * (Eigen::Vector3d(y[3 * i], y[3 * i + 1], y[3 * i + 2]) - cy) + cx;
    for (int k = 0; k < 3; ++k) y[3 * i + k] = v[k];
  }
}

// Edges e and e + 2 of a polygon cannot meet while both turn by less than 90 deg from the edge
// between them: projected on it, e lies behind its end and e + 2 ahead of its start. Along the
// straight path x -> y the projections a(t) . m(t) are quadratic in t with coefficients from the
// four products of the old and new edge vectors, so all four > 0 keeps them apart throughout.
bool unfolded(const double* x, const double* y, std::size_t e, std::size_t n) {
  const std::size_t p[4] = {e, (e + 1) % n, (e + 2) % n, (e + 3) % n};
  auto edge = [&](const double* z, int k, int c) { return z[3 * p[k + 1] + c] - z[3 * p[k] + c]; };
  for (const double* u : {x, y})
    for (const double* v : {x, y})
      for (int side : {0, 2}) {
        double d = 0.0;
        for (int c = 0; c < 3; ++c) d += edge(u, side, c) * edge(v, 1, c);
        if (!(d > 0.0)) return false;
      }
  return true;
}

}  // namespace

std::size_t uncertified_edge_pairs(const double* x, const double* y, std::size_t n) {
  // Along the straight path x -> y, the gap p(s) - q(t) between points of edges e and f moves by
  // a bilinear blend of the four end-point differences dx_a - dx_b, so by at most their largest
  // norm, m_ef. A pair is certified when its distance at x exceeds m_ef (<= 2 max |dx|): only
  // pairs closer than that are looked at, from a cell list of the edge midpoints.
  double longest = 0.0, moved = 0.0;
  std::vector<double> mid(3 * n);
  for (std::size_t e = 0; e < n; ++e) {
    const double* a = x + 3 * e;
    const double* b = x + 3 * ((e + 1) % n);
    double l2 = 0.0, d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      mid[3 * e + k] = 0.5 * (a[k] + b[k]);
      l2 += (b[k] - a[k]) * (b[k] - a[k]);
      d2 += (y[3 * e + k] - a[k]) * (y[3 * e + k] - a[k]);
    }
    longest = std::max(longest, std::sqrt(l2));
    moved = std::max(moved, std::sqrt(d2));
  }
  const double cell = longest + 2.0 * moved;
  auto key = [](long i, long j, long k) {
    return (static_cast<unsigned long long>(i & 0x1fffff) << 42) |
           (static_cast<unsigned long long>(j & 0x1fffff) << 21) |
           static_cast<unsigned long long>(k & 0x1fffff);
  };
  std::unordered_map<unsigned long long, std::vector<std::size_t>> cells;
  std::vector<std::array<long, 3>> at(n);
  for (std::size_t e = 0; e < n; ++e) {
    for (int k = 0; k < 3; ++k) at[e][k] = static_cast<long>(std::floor(mid[3 * e + k] / cell));
    cells[key(at[e][0], at[e][1], at[e][2])].push_back(e);
  }
  auto relative = [&](std::size_t i, std::size_t j) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double v = (y[3 * i + k] - x[3 * i + k]) - (y[3 * j + k] - x[3 * j + k]);
      d2 += v * v;
    }
    return std::sqrt(d2);
  };
  std::size_t open = 0;
  for (std::size_t e = 0; e < n; ++e)
    for (long di = -1; di <= 1; ++di)
      for (long dj = -1; dj <= 1; ++dj)
        for (long dk = -1; dk <= 1; ++dk) {
          const auto it = cells.find(key(at[e][0] + di, at[e][1] + dj, at[e][2] + dk));
          if (it == cells.end()) continue;
          for (std::size_t f : it->second) {
            const std::size_t gap = (f + n - e) % n;
            if (f <= e || gap < 2 || gap > n - 2) continue;  // each pair once; no shared point
            const std::size_t e1 = (e + 1) % n, f1 = (f + 1) % n;
            const double m = std::max(std::max(relative(e, f), relative(e, f1)),
                                      std::max(relative(e1, f), relative(e1, f1)));
            if (segment_distance(x + 3 * e, x + 3 * e1, x + 3 * f, x + 3 * f1) > m) continue;
            if (gap == 2 && unfolded(x, y, e, n)) continue;
            if (gap == n - 2 && unfolded(x, y, f, n)) continue;
            ++open;
          }
        }
  return open;
}

StrandPassageGuard::StrandPassageGuard(std::size_t N, double L, const double* y12)
    : N_(N), rec_(std::make_unique<Reconstructor>(N, L)), x_old_(3 * N), x_new_(3 * N), directors_(9 * N) {
  Lk0_ = linking(y12);
  std::swap(x_old_, x_new_);
}

StrandPassageGuard::~StrandPassageGuard() = default;

long StrandPassageGuard::linking(const double* y12) {
  rec_->sweep(y12, Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, x_new_.data(), directors_.data());
  std::vector<double> d1(3 * N_);
  for (std::size_t i = 0; i < N_; ++i)
    for (int a = 0; a < 3; ++a) d1[3 * i + a] = directors_[9 * i + 3 * a];
  return topology::ribbon_topology(x_new_.data(), d1.data(), N_, nullptr, topology::writhe_stride(N_), false)
      .Lk;
}

std::string StrandPassageGuard::note() const {
  return "strand-passage guard: Lk = " + std::to_string(Lk0_) + " kept over " + std::to_string(steps_) +
         " steps (" + std::to_string(uncertified_) + " not certified by distance, then checked by Lk)";
}

bool StrandPassageGuard::after_step(double, double t, double* y, double*) {
  const std::size_t N = N_;
  ++steps_;
  rec_->sweep(y, Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, x_new_.data(), nullptr);
  superpose(x_old_, x_new_);
  if (uncertified_edge_pairs(x_old_.data(), x_new_.data(), N) > 0) {
    ++uncertified_;
    pending_ = true;
  }
  // Lk is a ring's only where it is closed: between the closure holds of an inertial run (every
  // closure_interval) the gap edge may sweep across strands, so the check waits for a closed state
  if (pending_ && topology::is_closed(x_new_.data(), N)) {
    pending_ = false;
    const long Lk = linking(y);
    if (Lk != Lk0_)
      throw NumericalError("strand passage at t = " + message_number(t) +
                           ": the closed rod's linking number " + "went from " + std::to_string(Lk0_) +
                           " to " + std::to_string(Lk) +
                           " although [contact] forbids it: the contact did not hold (in a \"brownian\" run "
                           "the closure projection moves a ring's far side by nm per step, docs/thermal.md)");
  }
  std::swap(x_old_, x_new_);
  return false;
}

}  // namespace rodcore
