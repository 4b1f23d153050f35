// Time integrators on an ODE with a closed-form solution (the planar limit
// cycle r' = r (1 - r^2), theta' = 1), order conditions of the DOP853
// tableau, observed orders of the steppers and their dense output, and the
// failure modes.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rodcore/error.hpp"
#include "rodcore/integrators.hpp"

using namespace rodcore;

namespace {
#include "../../rodcore/src/dop853_tableau.inc"

OdeSystem limit_cycle() {
  OdeSystem s;
  s.n = 2;
  s.f = [](double, const double* y, double* f) {
    const double r2 = y[0] * y[0] + y[1] * y[1];
    f[0] = -y[1] + y[0] * (1.0 - r2);
    f[1] = y[0] + y[1] * (1.0 - r2);
  };
  return s;
}
// exact solution from (r0, theta0) = (0.5, 0)
std::vector<double> exact(double t) {
  const double r = 1.0 / std::sqrt(1.0 + (1.0 / 0.25 - 1.0) * std::exp(-2.0 * t));
  return {r * std::cos(t), r * std::sin(t)};
}

// Error at t_end = 4 with a fixed step h (adaptive methods forced to fixed
// steps by huge tolerances and dt_max = h) on the non-autonomous system
// y1' = -2 t y1^2, y2' = cos(t) y2 with y = (1/(1+t^2), exp(sin t)). (The
// limit cycle above is special: its phase error cancels at leading order.)
double fixed_step_error(const std::string& kind, double h) {
  OdeSystem s;
  s.n = 2;
  s.f = [](double t, const double* y, double* f) {
    f[0] = -2.0 * t * y[0] * y[0];
    f[1] = std::cos(t) * y[1];
  };
  IntegratorOptions o;
  o.dt = h;
  o.dt_max = h;
  o.rtol = o.atol = 1e10;
  auto in = make_time_integrator(*from_string<TimeMethod>(kind), s, o);
  const double y0[2] = {1.0, 1.0};
  in->reset(0.0, y0);
  while (in->t() < 4.0) in->step(4.0);
  return std::hypot(in->y()[0] - 1.0 / 17.0, in->y()[1] - std::exp(std::sin(4.0)));
}

// Error of the dense output inside ONE step of size h from the exact state.
double dense_error(const std::string& kind, double h) {
  IntegratorOptions o;
  o.dt = h;
  o.dt_max = h;
  o.rtol = o.atol = 1e10;
  auto in = make_time_integrator(*from_string<TimeMethod>(kind), limit_cycle(), o);
  const double y0[2] = {0.5, 0.0};
  in->reset(0.0, y0);
  in->step(10.0);
  double out[2];
  const double t = 0.37 * h;
  in->dense(t, out);
  const auto e = exact(t);
  return std::hypot(out[0] - e[0], out[1] - e[1]);
}
}  // namespace

TEST(NumericsIntegrators, Dop853TableauOrderConditions) {
  // row sums = c; bushy trees sum b c^(q-1) = 1/q (q <= 8);
  // sum b_i a_ij c_j^(q-1) = 1/(q (q+1)) (q <= 7)
  for (int i = 0; i < kDop853Extended; ++i) {
    double s = 0.0;
    for (int j = 0; j < i; ++j) s += kDop853A[i][j];
    EXPECT_NEAR(s, kDop853C[i], 1e-14) << "row " << i;
  }
  const double* b = kDop853A[kDop853Stages];
  for (int q = 1; q <= 8; ++q) {
    double s = 0.0;
    for (int i = 0; i < kDop853Stages; ++i) s += b[i] * std::pow(kDop853C[i], q - 1);
    EXPECT_NEAR(s, 1.0 / q, 1e-14) << "q = " << q;
  }
  for (int q = 1; q <= 7; ++q) {
    double s = 0.0;
    for (int i = 0; i < kDop853Stages; ++i)
      for (int j = 0; j < i; ++j) s += b[i] * kDop853A[i][j] * std::pow(kDop853C[j], q - 1);
    EXPECT_NEAR(s, 1.0 / (q * (q + 1)), 1e-14) << "q = " << q;
  }
  // the error estimators vanish on the polynomial y' = 1 (their weights sum to 0)
  double e5 = 0.0, e3 = 0.0;
  for (int i = 0; i < 13; ++i) {
    e5 += kDop853E5[i];
    e3 += kDop853E3[i];
  }
  EXPECT_NEAR(e5, 0.0, 1e-14);
  EXPECT_NEAR(e3, 0.0, 1e-14);
}

struct OrderCase {
  const char* kind;
  int order;
  double h;
};
class ObservedOrder : public ::testing::TestWithParam<OrderCase> {};

TEST_P(ObservedOrder, HalvingTheStepGains2ToTheOrder) {
  auto c = GetParam();
  if (c.kind == std::string("rk4_doubling")) c.kind = "rk4-doubling";  // extrapolated: order 5
  const double e1 = fixed_step_error(c.kind, c.h);
  const double e2 = fixed_step_error(c.kind, c.h / 2);
  EXPECT_NEAR(std::log2(e1 / e2), c.order, 0.35) << c.kind << ": " << e1 << " " << e2;
}
INSTANTIATE_TEST_SUITE_P(Steppers, ObservedOrder,
                         ::testing::Values(OrderCase{"rk4", 4, 0.1}, OrderCase{"rk4_doubling", 5, 0.2},
                                           OrderCase{"dopri5", 5, 0.1}, OrderCase{"dop853", 8, 0.4}),
                         [](const auto& i) { return std::string(i.param.kind); });

TEST(NumericsIntegrators, DenseOutputOrders) {
  // local error of the continuous extension: O(h^8) DOP853, O(h^5) DOPRI5,
  // O(h^4) cubic Hermite (RK4)
  struct C {
    const char* k;
    double p;
    double h;
  };
  for (const C c : {C{"dop853", 8, 0.4}, C{"dopri5", 5, 0.1}, C{"rk4", 4, 0.1}, C{"rk4-doubling", 4, 0.1}}) {
    const double e1 = dense_error(c.k, c.h), e2 = dense_error(c.k, c.h / 2);
    EXPECT_GT(std::log2(e1 / e2), c.p - 0.6) << c.k << " " << e1 << " " << e2;
  }
}

TEST(NumericsIntegrators, AdaptiveMeetsTolerance) {
  for (const char* kind : {"rk4-doubling", "dopri5", "dop853"}) {
    for (double tol : {1e-6, 1e-10}) {
      IntegratorOptions o;
      o.rtol = o.atol = tol;
      o.dt = 1e-3;
      auto in = make_time_integrator(*from_string<TimeMethod>(kind), limit_cycle(), o);
      const double y0[2] = {0.5, 0.0};
      in->reset(0.0, y0);
      // dense output at many times, never shortening steps
      double worst = 0.0;
      int j = 1;
      while (in->t() < 5.0) {
        in->step(5.0);
        for (; j <= 50 && 0.1 * j <= in->t(); ++j) {
          double out[2];
          in->dense(0.1 * j, out);
          const auto e = exact(0.1 * j);
          worst = std::max(worst, std::hypot(out[0] - e[0], out[1] - e[1]));
        }
      }
      EXPECT_EQ(in->t(), 5.0);
      EXPECT_LT(worst, 50 * tol) << kind << " tol " << tol;
      EXPECT_GT(in->steps(), 3);
    }
  }
}

TEST(NumericsIntegrators, Rk4ShortensOnlyTheLastStep) {
  IntegratorOptions o;
  o.dt = 0.3;
  auto in = make_time_integrator(TimeMethod::rk4, limit_cycle(), o);
  const double y0[2] = {0.5, 0.0};
  in->reset(0.0, y0);
  while (in->t() < 1.0) in->step(1.0);
  EXPECT_EQ(in->t(), 1.0);
  EXPECT_EQ(in->steps(), 4);  // 0.3, 0.6, 0.9, 1.0
  EXPECT_NEAR(in->t_prev(), 0.9, 1e-15);
}

TEST(NumericsIntegrators, StepUnderflowAndNaNAreErrors) {
  OdeSystem blowup;
  blowup.n = 1;
  blowup.f = [](double, const double* y, double* f) { f[0] = y[0] * y[0]; };  // y = 1/(1-t)
  for (const char* kind : {"rk4-doubling", "dopri5", "dop853"}) {
    IntegratorOptions o;
    o.rtol = o.atol = 1e-8;
    o.dt_min = 1e-6;
    auto in = make_time_integrator(*from_string<TimeMethod>(kind), blowup, o);
    const double y0 = 1.0;
    in->reset(0.0, &y0);
    EXPECT_THROW(
        {
          while (in->t() < 2.0) in->step(2.0);
        },
        NumericalError)
        << kind;
  }
  OdeSystem nan;
  nan.n = 1;
  nan.f = [](double t, const double*, double* f) { f[0] = t > 0.05 ? std::nan("") : 1.0; };
  IntegratorOptions o;
  auto in = make_time_integrator(TimeMethod::dop853, nan, o);
  const double y0 = 0.0;
  in->reset(0.0, &y0);
  EXPECT_THROW(
      {
        while (in->t() < 1.0) in->step(1.0);
      },
      NumericalError);
  // automatic is resolved by Simulation before; a value cast from a bad integer is no integrator.
  EXPECT_THROW(make_time_integrator(TimeMethod::automatic, limit_cycle(), o), InputError);
  EXPECT_THROW(make_time_integrator(static_cast<TimeMethod>(99), limit_cycle(), o), InputError);
}
