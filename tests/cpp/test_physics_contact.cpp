// Self-contact (rodcore/src/rodcore/contact.hpp) against things true independently of
// the code: the closed-form energy of two straight rods crossing at right angles and its
// convergence in the bead spacing, the forces as minus the gradient of the
// energy (finite differences), the cell list against every pair summed by brute force
// (closed and box-periodic, images included), and the effective-diameter ratio f(B)
// against its large-barrier asymptote. The dynamics (a collision that must not pass, an
// NVE run, Lk of a 300-K ring) are in tests/python/test_contact.py.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "rodcore/contact.hpp"
#include "rodcore/error.hpp"

using namespace rodcore;

namespace {

constexpr double kPi = std::numbers::pi;

// A closed polygon with points about h apart: a straight piece along x through the
// origin (z = 0), a straight piece along y through (0, 0, rho), both of half-length X,
// joined by detours at height H far from the crossing. Returns N + 1 points (the last
// equals the first) and sets N.
std::vector<double> crossing_ring(double rho, double X, double H, double h, std::size_t& N) {
  std::vector<double> r;
  auto line = [&](double x0, double y0, double z0, double x1, double y1, double z1) {
    const double len = std::sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0) + (z1 - z0) * (z1 - z0));
    const int n = std::max(1, static_cast<int>(std::lround(len / h)));
    for (int k = 0; k < n; ++k) {
      const double s = static_cast<double>(k) / n;
      r.insert(r.end(), {x0 + s * (x1 - x0), y0 + s * (y1 - y0), z0 + s * (z1 - z0)});
    }
  };
  line(-X, 0, 0, X, 0, 0);      // piece A
  line(X, 0, 0, X, 0, H);       // up
  line(X, 0, H, 0, -X, H);      // across, high
  line(0, -X, H, 0, -X, rho);   // down
  line(0, -X, rho, 0, X, rho);  // piece B
  line(0, X, rho, 0, X, H);     // up
  line(0, X, H, -X, 0, H);      // across, high
  line(-X, 0, H, -X, 0, 0);     // down to the start of A
  N = r.size() / 3;
  r.insert(r.end(), r.begin(), r.begin() + 3);
  return r;
}

ContactPotential unit_potential(int stride = 1) {
  ContactPotential p;
  p.cutoff = 1.0;
  p.psi0 = 1.0;
  p.exclude = 0.5 * kPi;
  p.stride = stride;
  return p;
}

// U_perp(rho) = (pi / 4) psi0 d_c^2 (1 - rho^2 / d_c^2)^4 (contact.hpp), d_c = psi0 = 1.
double crossing_energy(double rho) {
  const double q = 1.0 - rho * rho;
  return rho >= 1.0 ? 0.0 : 0.25 * kPi * q * q * q * q;
}

// Every pair, no cell list: the energy and forces of contact.hpp's definition.
double brute_force(const std::vector<double>& r, std::size_t N, double h, const ContactPotential& p,
                   bool closed, std::vector<double>& F) {
  F.assign(3 * N, 0.0);
  const std::size_t k = static_cast<std::size_t>(p.stride);
  const double w = static_cast<double>(k) * h, dc2 = p.cutoff * p.cutoff;
  double P[3] = {0, 0, 0};
  if (!closed)
    for (int c = 0; c < 3; ++c) P[c] = r[3 * N + c] - r[c];
  const int m_lo = closed ? 0 : -8, m_hi = closed ? 0 : 8;
  double U = 0.0;
  for (std::size_t a = 0; a < N; a += k)
    for (std::size_t b = 0; b < N; b += k)
      for (int m = m_lo; m <= m_hi; ++m) {
        long gap = std::labs(static_cast<long>(b) + m * static_cast<long>(N) - static_cast<long>(a));
        if (closed) gap = std::min(gap, static_cast<long>(N) - gap);
        if (gap * h < p.exclude) continue;
        double d[3], r2 = 0.0;
        for (int c = 0; c < 3; ++c) {
          d[c] = r[3 * a + c] - r[3 * b + c] - m * P[c];
          r2 += d[c] * d[c];
        }
        if (r2 >= dc2) continue;
        const double x = 1.0 - r2 / dc2;
        U += 0.5 * w * w * p.psi0 * x * x * x;  // every ordered pair: half
        for (int c = 0; c < 3; ++c) F[3 * a + c] += 6.0 * w * w * p.psi0 / dc2 * x * x * d[c];
      }
  return U;
}

}  // namespace

TEST(PhysicsContact, CrossingEnergyConvergesToTheClosedForm) {
  // Two straight rods crossing at right angles: the bead sum is the midpoint rule of the
  // continuum double integral, at least second order in the spacing h.
  for (double rho : {0.0, 0.3, 0.7}) {
    double err[2];
    for (int level = 0; level < 2; ++level) {
      const double h = level == 0 ? 0.1 : 0.05;
      std::size_t N = 0;
      auto r = crossing_ring(rho, 5.0, 6.0, h, N);
      SelfContact sc(N, N * h, unit_potential(), true);
      std::vector<double> F(3 * N);
      err[level] = sc.forces(r.data(), F.data()) - crossing_energy(rho);
    }
    const double rel = std::abs(err[1]) / crossing_energy(rho);
    EXPECT_LT(rel, 1e-4) << "rho " << rho;
    // at least second order (measured 4-5: the potential and its first two derivatives
    // vanish at the cut-off)
    const double order = std::log2(std::abs(err[0] / err[1]));
    EXPECT_GT(order, 1.8) << "rho " << rho << " errors " << err[0] << " " << err[1];
  }
  // Control: the energy is that of the crossing, not of the detours (rho beyond d_c).
  std::size_t N = 0;
  auto r = crossing_ring(1.2, 5.0, 6.0, 0.1, N);
  SelfContact sc(N, N * 0.1, unit_potential(), true);
  std::vector<double> F(3 * N);
  EXPECT_EQ(sc.forces(r.data(), F.data()), 0.0);
}

TEST(PhysicsContact, ForcesAreMinusTheGradient) {
  std::size_t N = 0;
  const double h = 0.1;
  auto r = crossing_ring(0.35, 3.0, 4.0, h, N);
  std::mt19937 gen(7);
  std::normal_distribution<double> g(0.0, 0.02);
  for (double& v : r) v += g(gen);
  for (int c = 0; c < 3; ++c) r[3 * N + c] = r[c];
  SelfContact sc(N, N * h, unit_potential(), true);
  std::vector<double> F(3 * N), Fd(3 * N);
  const double U = sc.forces(r.data(), F.data());
  ASSERT_GT(U, 0.0);
  double worst = 0.0, worst_control = 0.0, scale = 0.0;
  for (std::size_t j = 0; j < 3 * N; j += 7) {
    const double e = 1e-6, keep = r[j];
    r[j] = keep + e;
    const double up = sc.forces(r.data(), Fd.data());
    r[j] = keep - e;
    const double down = sc.forces(r.data(), Fd.data());
    r[j] = keep;
    const double minus_grad = -(up - down) / (2 * e);
    worst = std::max(worst, std::abs(minus_grad - F[j]));
    worst_control = std::max(worst_control, std::abs(minus_grad - 1.01 * F[j]));
    scale = std::max(scale, std::abs(F[j]));
  }
  ASSERT_GT(scale, 1e-3);
  EXPECT_LT(worst, 1e-7 * scale);
  // Control: a force 1 % off is seen.
  EXPECT_GT(worst_control, 1e-3 * scale);
}

TEST(PhysicsContact, CellListFindsEveryPair) {
  std::mt19937 gen(11);
  std::normal_distribution<double> g(0.0, 1.0);
  const double h = 0.1;
  // A closed random walk folded into a small box (many contacts), and a box-periodic
  // one along z whose period is short enough that images meet.
  for (bool closed : {true, false}) {
    for (int stride : {1, 2}) {
      const std::size_t N = 400;
      std::vector<double> r(3 * (N + 1));
      double t[3] = {1, 0, 0};
      for (std::size_t i = 1; i <= N; ++i) {
        for (double& v : t) v += 0.3 * g(gen);
        const double n = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        for (int c = 0; c < 3; ++c) r[3 * i + c] = r[3 * (i - 1) + c] + h * t[c] / n;
      }
      if (closed) {  // close it: remove the end gap linearly
        for (std::size_t i = 0; i <= N; ++i)
          for (int c = 0; c < 3; ++c) r[3 * i + c] -= static_cast<double>(i) / N * r[3 * N + c];
      } else {  // period 8 along z
        for (std::size_t i = 0; i <= N; ++i) {
          const double gap[3] = {r[3 * N] - 0.0, r[3 * N + 1], r[3 * N + 2] - 8.0};
          for (int c = 0; c < 3; ++c) r[3 * i + c] -= static_cast<double>(i) / N * gap[c];
        }
      }
      const ContactPotential p = unit_potential(stride);
      SelfContact sc(N, N * h, p, closed);
      std::vector<double> F(3 * N), Fb;
      const double U = sc.forces(r.data(), F.data());
      const double Ub = brute_force(r, N, h, p, closed, Fb);
      ASSERT_GT(Ub, 0.0) << "the test curve has no contact";
      EXPECT_NEAR(U, Ub, 1e-12 * Ub) << (closed ? "closed" : "periodic") << " stride " << stride;
      double worst = 0.0;
      for (std::size_t j = 0; j < 3 * N; ++j) worst = std::max(worst, std::abs(F[j] - Fb[j]));
      EXPECT_LT(worst, 1e-10) << (closed ? "closed" : "periodic") << " stride " << stride;
    }
  }
}

TEST(PhysicsContact, DiameterRatioApproachesItsLargeBarrierAsymptote) {
  // f(B) = 1 - c B^-1/4 + O(B^-1/2) with c = Gamma(5/4) 16^-1/4 (4/pi) int_0^pi/2 sin^9/4,
  // int_0^pi/2 sin^a = (sqrt(pi)/2) Gamma((a+1)/2) / Gamma(a/2 + 1): the remainder times
  // B^1/2 must stay bounded and settle (-0.12 at B = 100, -0.103 at 1e6).
  const double a = 9.0 / 4.0;
  const double c = std::tgamma(1.25) * std::pow(16.0, -0.25) * (4.0 / kPi) * 0.5 * std::sqrt(kPi) *
                   std::tgamma((a + 1) / 2) / std::tgamma(a / 2 + 1);
  double prev = 0.0, last = 0.0;
  for (double B : {1e2, 1e3, 1e4, 1e5, 1e6}) {
    const double f = contact_diameter_ratio(B);
    const double rest = (f - (1.0 - c * std::pow(B, -0.25))) * std::sqrt(B);
    EXPECT_LT(std::abs(rest), 0.2) << "B " << B << " f " << f;
    if (B == 1e6) {
      EXPECT_LT(std::abs(rest - last), 0.01);
    }
    last = rest;
    EXPECT_GT(f, prev);  // a higher barrier: closer to hard rods
    prev = f;
  }
  // Control: the right-angle crossing alone (no orientation average) leaves a remainder
  // that grows like B^1/4.
  const double f = contact_diameter_ratio(1e6);
  EXPECT_GT((f - (1.0 - std::tgamma(1.25) * std::pow(16e6, -0.25))) * 1e3, 0.4);
}

TEST(PhysicsContact, BadGridsAreRefused) {
  const ContactPotential p = unit_potential(3);
  EXPECT_THROW(SelfContact(100, 20.0, p, true), InputError);                 // stride 3 does not divide 100
  EXPECT_THROW(SelfContact(60, 20.0, unit_potential(1), true), InputError);  // h = 0.33 > d_c / 4
  EXPECT_THROW(SelfContact(100, 2.0, unit_potential(1), true), InputError);  // ring shorter than 2 s_ex
}
