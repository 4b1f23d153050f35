#include "rodcore/contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/state.hpp"

namespace rodcore {
namespace {

// Hash of a cell of the cell list: the table has a power-of-two size; cells that share
// a bucket are told apart by their coordinates.
std::size_t cell_hash(long x, long y, long z, std::size_t mask) {
  const auto u = static_cast<unsigned long long>(x) * 73856093ULL ^
                 static_cast<unsigned long long>(y) * 19349663ULL ^
                 static_cast<unsigned long long>(z) * 83492791ULL;
  return static_cast<std::size_t>(u) & mask;
}

}  // namespace

double contact_diameter_ratio(double B) {
  // Midpoint rule in the angle g and Simpson in x; the x integrand falls from 1 to 0
  // within (sin g / 16 B)^1/4 of x = 1, resolved by the 4000 intervals for B <= 1e6.
  const int ng = 400, nx = 4000;
  double outer = 0.0;
  for (int a = 0; a < ng; ++a) {
    const double g = (a + 0.5) * (std::numbers::pi / 2) / ng;
    const double sg = std::sin(g);
    double inner = 0.0;
    for (int k = 0; k <= nx; ++k) {
      const double x = static_cast<double>(k) / nx;
      const double q = 1.0 - x * x;
      const double v = 1.0 - std::exp(-B * q * q * q * q / sg);
      inner += (k == 0 || k == nx ? 1.0 : (k % 2 ? 4.0 : 2.0)) * v;
    }
    outer += sg * sg * inner / (3.0 * nx);
  }
  return outer * (std::numbers::pi / 2) / ng * 4.0 / std::numbers::pi;
}

ContactPotential contact_potential(const Contact& c) {
  if (!(c.diameter > 0.0) || !std::isfinite(c.diameter))
    throw InputError("contact.diameter must be > 0 and finite, got " + message_number(c.diameter));
  if (!(c.barrier_kT > 0.0) || !std::isfinite(c.barrier_kT))
    throw InputError("contact.barrier_kT must be > 0 and finite, got " + message_number(c.barrier_kT));
  if (!(c.kT > 0.0) || !std::isfinite(c.kT))
    throw InputError("contact: the calibration kT must be > 0, got " + message_number(c.kT));
  if (c.stride < 1) throw InputError("contact.stride must be >= 1, got " + std::to_string(c.stride));
  ContactPotential p;
  p.cutoff = c.diameter / contact_diameter_ratio(c.barrier_kT);
  p.psi0 = 4.0 * c.barrier_kT * c.kT / (std::numbers::pi * p.cutoff * p.cutoff);
  p.exclude = 0.5 * std::numbers::pi * p.cutoff;
  p.stride = c.stride;
  return p;
}

SelfContact::SelfContact(std::size_t N, double L, const ContactPotential& potential, bool closed)
    : N_(N), h_(L / static_cast<double>(N)), p_(potential), closed_(closed) {
  const std::size_t k = static_cast<std::size_t>(p_.stride);
  if (N % k != 0)
    throw InputError("contact.stride = " + std::to_string(k) + " does not divide rod.points = " +
                     std::to_string(N) + ": the beads must sit at every stride-th grid point");
  const double w = static_cast<double>(k) * h_;
  if (w > 0.25 * p_.cutoff)
    throw InputError("contact: beads " + message_number(w) + " apart (contact.stride = " + std::to_string(k) +
                     " grid spacings of " + message_number(h_) + ") exceed a quarter of the cut-off " +
                     message_number(p_.cutoff) +
                     ": the rods could slip between the beads; use a smaller contact.stride or more "
                     "rod.points");
  if (closed_ && L <= 2.0 * p_.exclude)
    throw InputError("contact: the ring's length " + message_number(L) + " is not longer than twice the " +
                     "excluded contour pi d_c / 2 = " + message_number(p_.exclude) +
                     ": no pair of its points can touch; drop [contact] or use a smaller diameter");
  M_ = N / k;
  exclude_pts_ = static_cast<long>(std::ceil(p_.exclude / h_ - 1e-12));
  r_.assign(3 * (N + 1), 0.0);
  D_.assign(9 * N, 0.0);
  rec_ = std::make_unique<Reconstructor>(N, L);
  F_.assign(3 * N, 0.0);
  cell_.resize(3 * M_);
  std::size_t T = 1;
  while (T < 2 * M_) T <<= 1;
  head_.resize(T);
  next_.resize(M_);
}

void SelfContact::sweep(const double* y, bool frames) {
  // The centreline of the output, the closure and the topology (reconstruction.hpp), so that the
  // curve the contact keeps apart is the curve whose Lk is kept: a local (Hermite-Magnus) sweep of
  // the same strains differs from it by the grid-scale roughness of a thermal state, integrated
  // along the rod (about 10 nm, twice the DNA's diameter, on a 1-kbp ring at 300 K).
  const auto end =
      rec_->sweep(y, Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, r_.data(), frames ? D_.data() : nullptr);
  for (int c = 0; c < 3; ++c) r_[3 * N_ + c] = end.r[c];
}

double SelfContact::forces(const double* r, double* F) {
  const std::size_t N = N_, M = M_;
  const long k = p_.stride;
  const double dc = p_.cutoff, dc2 = dc * dc;
  const double w = static_cast<double>(k) * h_;
  const double e0 = w * w * p_.psi0, f0 = 6.0 * w * w * p_.psi0 / dc2;
  std::fill(F, F + 3 * N, 0.0);
  auto bead = [&](std::size_t b) { return r + 3 * (b * static_cast<std::size_t>(k)); };
  // The period (a box-periodic rod meets its images r_b + m P) and how many images can
  // reach: the beads' extent along P plus the cut-off.
  Vec3 P{0.0, 0.0, 0.0};
  long m_max = 0;
  if (!closed_) {
    for (int c = 0; c < 3; ++c) P[c] = r[3 * N + c] - r[c];
    const double lP = std::sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
    if (!(lP > 0.0)) throw NumericalError("contact: a box-periodic rod with period 0");
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t b = 0; b < M; ++b) {
      const double* p = bead(b);
      const double z = (p[0] * P[0] + p[1] * P[1] + p[2] * P[2]) / lP;
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
    m_max = static_cast<long>(std::floor((hi - lo + dc) / lP));
  }
  // The cell list: cells of size d_c, hashed into a table of >= 2 M buckets.
  const std::size_t mask = head_.size() - 1;
  std::fill(head_.begin(), head_.end(), -1);
  for (std::size_t b = 0; b < M; ++b) {
    const double* p = bead(b);
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(p[c]))
        throw NumericalError("contact: non-finite centreline at bead " + std::to_string(b));
      cell_[3 * b + c] = static_cast<long>(std::floor(p[c] / dc));
    }
    const std::size_t hb = cell_hash(cell_[3 * b], cell_[3 * b + 1], cell_[3 * b + 2], mask);
    next_[b] = head_[hb];
    head_[hb] = static_cast<int>(b);
  }
  double U = 0.0, min_r2 = std::numeric_limits<double>::infinity();
  const double excl = p_.exclude / h_;
  const long Nl = static_cast<long>(N);
  for (long m = 0; m <= m_max; ++m) {
    for (std::size_t a = 0; a < M; ++a) {
      const double* pa = bead(a);
      // bead b's image b + m N is near a when b is near pa - m P
      const double t[3] = {pa[0] - m * P[0], pa[1] - m * P[1], pa[2] - m * P[2]};
      long ct[3];
      for (int c = 0; c < 3; ++c)
        ct[c] = m == 0 ? cell_[3 * a + c] : static_cast<long>(std::floor(t[c] / dc));
      for (long dx = -1; dx <= 1; ++dx)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dz = -1; dz <= 1; ++dz) {
            const long cx = ct[0] + dx, cy = ct[1] + dy, cz = ct[2] + dz;
            for (int b = head_[cell_hash(cx, cy, cz, mask)]; b >= 0; b = next_[b]) {
              const auto ub = static_cast<std::size_t>(b);
              if (m == 0 && ub <= a) break;  // each pair once (a bucket lists its beads in descending order)
              if (cell_[3 * ub] != cx || cell_[3 * ub + 1] != cy || cell_[3 * ub + 2] != cz) continue;
              long gap = static_cast<long>(ub) * k + m * Nl - static_cast<long>(a) * k;
              if (gap < 0) gap = -gap;
              if (closed_) gap = std::min(gap, Nl - gap);
              if (static_cast<double>(gap) < excl) continue;  // neighbours along the rod
              const double* pb = bead(ub);
              const double d[3] = {t[0] - pb[0], t[1] - pb[1], t[2] - pb[2]};
              const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
              if (r2 >= dc2) continue;
              min_r2 = std::min(min_r2, r2);
              const double x = 1.0 - r2 / dc2;
              U += e0 * x * x * x;
              const double f = f0 * x * x;
              double* Fa = F + 3 * (a * static_cast<std::size_t>(k));
              double* Fb = F + 3 * (ub * static_cast<std::size_t>(k));
              for (int c = 0; c < 3; ++c) {
                Fa[c] += f * d[c];
                Fb[c] -= f * d[c];
              }
            }
          }
    }
  }
  min_distance_ = std::sqrt(min_r2);
  return U;
}

double SelfContact::energy(const double* y) {
  sweep(y, false);
  return forces(r_.data(), F_.data());
}

double SelfContact::add_to_rhs(const double* y, const MaterialField& mf, double* dydt) {
  sweep(y, true);
  const double U = forces(r_.data(), F_.data());
  const std::size_t N = N_;
  const bool per_point = mf.kind == MaterialKind::per_point;
  for (std::size_t i = 0; i < N; i += static_cast<std::size_t>(p_.stride)) {
    const double* F = F_.data() + 3 * i;
    if (F[0] == 0.0 && F[1] == 0.0 && F[2] == 0.0) continue;
    const double* R = D_.data() + 9 * i;  // R[3 a + k]: component a of director d_k
    double body[3];                       // R^T F
    for (int k = 0; k < 3; ++k) body[k] = R[k] * F[0] + R[3 + k] * F[1] + R[6 + k] * F[2];
    const double s = (per_point ? mf.irho_s[i] : 1.0 / mf.rho) / h_;
    for (int c = 0; c < 3; ++c) dydt[row(gamma, c) * N + i] += s * body[c];
  }
  return U;
}

}  // namespace rodcore
