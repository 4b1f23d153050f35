// The strand-passage guard (rodcore/src/rodcore/passage_guard.hpp) against geometry that is
// true independently of it: a strand pushed through another along a straight path must not be
// certified, the same strand moved away or the whole polygon moved rigidly must be, and on random
// small moves of a random polygon every certified pair is apart at every sampled point of the path
// (soundness, by brute force). The guard in a run is tests/python/test_thermal_supercoil.py's.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "rodcore/passage_guard.hpp"

using namespace rodcore;

namespace {

// A closed polygon of 7 straight pieces of `per` points each: one along x at z = 0 and one along
// y at height z = rho, joined far from the crossing at height H. Returns 3 x 7 per values.
std::vector<double> crossing(double rho, int per) {
  const double X = 10.0, H = 5.0;
  std::vector<double> r;
  auto line = [&](double x0, double y0, double z0, double x1, double y1, double z1) {
    for (int k = 0; k < per; ++k) {
      const double s = static_cast<double>(k) / per;
      r.insert(r.end(), {x0 + s * (x1 - x0), y0 + s * (y1 - y0), z0 + s * (z1 - z0)});
    }
  };
  line(-X, 0, 0, X, 0, 0);
  line(X, 0, 0, X, 0, H);
  line(X, 0, H, 0, -X, H);
  line(0, -X, H, 0, -X, rho);
  line(0, -X, rho, 0, X, rho);
  line(0, X, rho, -X, 0, H);
  line(-X, 0, H, -X, 0, 0);
  return r;
}

double segment_gap_brute(const double* p0, const double* p1, const double* q0, const double* q1) {
  double best = 1e300;
  for (int a = 0; a <= 16; ++a)
    for (int b = 0; b <= 16; ++b) {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double p = p0[k] + (p1[k] - p0[k]) * a / 16.0, q = q0[k] + (q1[k] - q0[k]) * b / 16.0;
        d2 += (p - q) * (p - q);
      }
      best = std::min(best, std::sqrt(d2));
    }
  return best;
}

}  // namespace

TEST(PhysicsPassageGuard, AStrandPushedThroughIsNotCertifiedAndOneMovedAwayIs) {
  const auto above = crossing(0.5, 40);
  const auto below = crossing(-0.5, 40);  // the y piece moved straight through the x piece
  const auto away = crossing(0.7, 40);    // moved less than the gap, away from it
  ASSERT_EQ(above.size(), below.size());
  const std::size_t n = above.size() / 3;
  EXPECT_GT(uncertified_edge_pairs(above.data(), below.data(), n), 0u);  // this check must be able to fail
  EXPECT_EQ(uncertified_edge_pairs(above.data(), away.data(), n), 0u);
  auto moved = above;  // a rigid translation by far more than the gap: nothing moves relative
  for (std::size_t i = 0; i < n; ++i) moved[3 * i] += 7.0;
  EXPECT_EQ(uncertified_edge_pairs(above.data(), moved.data(), n), 0u);
}

TEST(PhysicsPassageGuard, CertifiedPairsStayApartAlongThePath) {
  // A random ring (a circle with noise) and random moves of up to a third of the spacing: the pairs
  // the guard certifies are checked by brute force at 11 points of the straight path.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  const std::size_t n = 60;
  long certified_cases = 0, open_cases = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<double> x(3 * n), y(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const double phi = 2.0 * std::numbers::pi * static_cast<double>(i) / n;
      const double r = 3.0 + 0.6 * g(rng);
      x[3 * i] = r * std::cos(phi);
      x[3 * i + 1] = r * std::sin(phi);
      x[3 * i + 2] = 0.6 * g(rng);
      for (int k = 0; k < 3; ++k) y[3 * i + k] = x[3 * i + k] + 0.03 * (trial % 4 + 1) * g(rng);
    }
    if (uncertified_edge_pairs(x.data(), y.data(), n) > 0) {
      ++open_cases;
      continue;
    }
    ++certified_cases;
    for (std::size_t e = 0; e < n; ++e)
      for (std::size_t f = e + 2; f < n; ++f) {
        if ((f + 1) % n == e) continue;
        for (int s = 0; s <= 10; ++s) {
          std::vector<double> z(3 * n);
          for (std::size_t k = 0; k < 3 * n; ++k) z[k] = x[k] + (y[k] - x[k]) * s / 10.0;
          EXPECT_GT(segment_gap_brute(&z[3 * e], &z[3 * ((e + 1) % n)], &z[3 * f], &z[3 * ((f + 1) % n)]),
                    0.0)
              << "trial " << trial << " edges " << e << ", " << f;
        }
      }
  }
  EXPECT_GT(certified_cases, 3);  // both outcomes occur, so both branches were exercised
  EXPECT_GT(open_cases, 3);
}
