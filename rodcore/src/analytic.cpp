#include "rodcore/analytic.hpp"

#include <cmath>
#include <numbers>

#include "rodcore/error.hpp"

namespace rodcore::analytic {

double dispersion(double kappa, double D1, double Gamma03, int branch) {
  const double sD = std::sqrt(D1);
  const double a = std::sqrt(kappa * kappa * (sD + 1.0) * (sD + 1.0) + Gamma03 * Gamma03);
  const double b = std::sqrt(kappa * kappa * (sD - 1.0) * (sD - 1.0) + Gamma03 * Gamma03);
  return 0.5 * (a + (branch >= 0 ? b : -b));
}

double energy_ratio(double w, double kappa, double D1, double Gamma03) {
  const double num = w * w - kappa * kappa * D1;
  return num * num / (D1 * kappa * kappa * Gamma03 * Gamma03);
}

double TwistedWave::kappa() const {
  if (kappa_branch == "p") return k + Omega03;
  if (kappa_branch == "m") return k - Omega03;
  throw InputError("twisted wave: kappa branch \"" + kappa_branch + "\" not known; allowed: \"p\", \"m\"");
}
double TwistedWave::sigma() const { return kappa_branch == "p" ? -1.0 : 1.0; }
double TwistedWave::w() const { return dispersion(kappa(), D1, Gamma03, omega_branch); }
double TwistedWave::a_w() const {
  const double ww = w(), kap = kappa();
  const double den = ww * ww - D1 * kap * kap;
  if (den == 0.0 || ww == 0.0)
    throw InputError("twisted wave: degenerate parameters (w = 0 or w^2 = D1 kappa^2)");
  return ww * Gamma03 * A / den;
}
double TwistedWave::period() const { return 2.0 * std::numbers::pi / w(); }

Fields TwistedWave::at(double s, double t) const {
  const double ww = w(), kap = kappa(), sg = sigma(), aw = a_w();
  const double th = ww * t - k * s, c = std::cos(th), sn = std::sin(th);
  return {-kap * A / ww * c,
          -sg * kap * A / ww * sn,
          0.0,
          sg * aw * c,
          aw * sn,
          0.0,
          A * c,
          sg * A * sn,
          Gamma03,
          -sg * kap * aw / ww * c,
          -kap * aw / ww * sn,
          Omega03};
}

Fields TwistedWave::d_dt(double s, double t) const {
  // every field is F(theta) with theta = w t - k s: dF/dt = w F'(theta)
  const double ww = w(), kap = kappa(), sg = sigma(), aw = a_w();
  const double th = ww * t - k * s, c = std::cos(th), sn = std::sin(th);
  return {ww * (kap * A / ww * sn),
          ww * (-sg * kap * A / ww * c),
          0.0,
          ww * (-sg * aw * sn),
          ww * (aw * c),
          0.0,
          ww * (-A * sn),
          ww * (sg * A * c),
          0.0,
          ww * (sg * kap * aw / ww * sn),
          ww * (-kap * aw / ww * c),
          0.0};
}

double UntwistedWave::w() const { return dispersion(k, D1, Gamma03, omega_branch); }
double UntwistedWave::g() const {
  const double ww = w();
  return (ww * ww - D1 * k * k) / (ww * Gamma03);
}

Fields UntwistedWave::at(double s, double t) const {
  const double ww = w(), gg = g();
  const double den = ww * ww - C3 * k * k;
  if (den == 0.0)
    throw InputError("untwisted wave: w^2 = C3 k^2 (the extension wave is resonant); change k or branch");
  const double th = ww * t - k * s, c = std::cos(th), sn = std::sin(th), c2 = std::cos(2.0 * th);
  const double a = eps * (1.0 + eps);
  const double e2 = eps * eps;
  Fields f{};
  f[0] = -(k / ww) * gg * a * c;                         // gamma1
  f[2] = C3 * k * Gamma03 * e2 / (4.0 * ww * den) * c2;  // gamma3
  f[4] = a * sn;                                         // omega2
  f[6] = gg * a * c;                                     // Gamma1
  f[8] = Gamma03 - Gamma03 * e2 / (4.0 * den) * c2;      // Gamma3
  f[10] = -(k / ww) * a * sn;                            // Omega2
  return f;
}

}  // namespace rodcore::analytic
