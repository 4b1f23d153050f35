#include "rodcore/initial_conditions.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "rodcore/analytic.hpp"
#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/h5_initial.hpp"
#include "rodcore/material.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/state.hpp"

namespace rodcore {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;

std::string num(double x) {
  std::ostringstream o;
  o.precision(10);
  o << x;
  return o.str();
}

// y[row(f, c) * N + i] = value
void set(std::vector<double>& y, std::size_t N, Field f, int c, std::size_t i, double v) {
  y[static_cast<std::size_t>(row(f, c)) * N + i] = v;
}

void fill_intrinsic(const Scene& sc, std::vector<double>& y) {
  const std::size_t N = static_cast<std::size_t>(sc.rod.points);
  const auto G0 = intrinsic_Gamma0(sc.rod);
  const auto O0 = intrinsic_Omega0(sc.rod);
  y.assign(12 * N, 0.0);
  std::copy(G0.begin(), G0.end(), y.begin() + 6 * N);
  std::copy(O0.begin(), O0.end(), y.begin() + 9 * N);
}

// The straight-rod kinds need a uniform intrinsic shape Gamma0 = (0, 0, G03),
// Omega0 = (0, 0, O03) and the paper's C1 = C2 = I1 = I2 = 1, D1 = D2.
void require_straight_paper_rod(const Scene& sc, const std::string& kind, bool untwisted) {
  const Rod& r = sc.rod;
  const Material& m = sc.material;
  auto fail = [&](const std::string& what) {
    throw InputError(sc.source + ": initial.kind = \"" + kind + "\" " + what);
  };
  if (!r.Gamma0_s.empty() || !r.Omega0_s.empty())
    fail("needs a uniform intrinsic shape (rod.Gamma0 / rod.Omega0 vectors, not per-point arrays)");
  if (r.Gamma0[0] != 0.0 || r.Gamma0[1] != 0.0 || !(r.Gamma0[2] > 0.0))
    fail("needs rod.Gamma0 = [0, 0, Gamma03] with Gamma03 > 0");
  if (r.Omega0[0] != 0.0 || r.Omega0[1] != 0.0)
    fail("needs rod.Omega0 = [0, 0, Omega03] (a straight, possibly twisted rod)");
  if (untwisted && r.Omega0[2] != 0.0) fail("needs an untwisted rod: rod.Omega0 = [0, 0, 0]");
  if (material_kind(m) != MaterialKind::diagonal || m.rho != 1.0)
    fail("is the paper's solution for a diagonal material (material.C, D, I) with material.rho = 1");
  if (m.C[0] != 1.0 || m.C[1] != 1.0)
    fail("is the paper's solution for material.C = [1, 1, C3] (dimensionless shear modulus 1)");
  if (m.I[0] != 1.0 || m.I[1] != 1.0) fail("is the paper's solution for material.I = [1, 1, I3]");
  if (m.D[0] != m.D[1]) fail("needs isotropic bending, material.D[0] == material.D[1]");
}

int omega_branch(const std::string& b) { return b == "plus" ? +1 : -1; }

// k = 2 pi m / L, with m the integer number of wavelengths on the rod.
double wavenumber(const Scene& sc, const std::string& kind) {
  const double m = initial_number(sc.initial, "mode");
  if (m != std::round(m))
    throw InputError(sc.source + ": initial.mode of kind \"" + kind +
                     "\" must be an integer (wavelengths on the periodic rod), got " + num(m));
  return 2.0 * kPi * m / sc.rod.length;
}

analytic::TwistedWave twisted_wave(const Scene& sc) {
  analytic::TwistedWave w;
  w.A = initial_number(sc.initial, "A");
  w.k = wavenumber(sc, "twisted_wave");
  w.Gamma03 = sc.rod.Gamma0[2];
  w.Omega03 = sc.rod.Omega0[2];
  w.D1 = sc.material.D[0];
  w.kappa_branch = initial_string(sc.initial, "kappa");
  w.omega_branch = omega_branch(initial_string(sc.initial, "branch"));
  return w;
}

void fill_analytic(const std::vector<double>& s, std::vector<double>& y,
                   const std::function<analytic::Fields(double)>& at) {
  const std::size_t N = s.size();
  y.assign(12 * N, 0.0);
  for (std::size_t i = 0; i < N; ++i) {
    const auto f = at(s[i]);
    for (int r = 0; r < 12; ++r) y[static_cast<std::size_t>(r) * N + i] = f[r];
  }
}

void check_rod_value(const std::set<std::string>& set_keys, const std::string& key, double given,
                     double implied, const std::string& kind) {
  if (set_keys.count(key) && std::abs(given - implied) > 1e-9 * std::max(1.0, std::abs(implied)))
    throw InputError("rod." + key + " = " + num(given) + " contradicts initial.kind = \"" + kind +
                     "\", which implies " + num(implied) + "; remove rod." + key + " or make it agree");
}

std::vector<InitialKindSpec> build_kinds() {
  std::vector<InitialKindSpec> k;

  // ------------------------------------------------------------- rest
  {
    InitialKindSpec r(InitialKind::rest);
    r.doc = "The intrinsic shape at rest: Gamma = Gamma0(s), Omega = Omega0(s), omega = 0, and a "
            "rigid translation with lab-frame velocity (v1, v2, v3), i.e. gamma(s) = R(s)^T v "
            "with R(s) the intrinsic directors (d_k(0) = e_k). Stays at rest / translating.";
    for (const char* c : {"v1", "v2", "v3"})
      r.numbers.push_back(
          {c, 0.0, -kInf, kInf, "l/tau", std::string("lab-frame translation velocity, component ") + c[1]});
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      fill_intrinsic(sc, y);
      const Vec3 v{initial_number(sc.initial, "v1"), initial_number(sc.initial, "v2"),
                   initial_number(sc.initial, "v3")};
      if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0) return;
      const std::size_t N = s.size();
      Reconstructor rec(N, sc.rod.length);
      std::vector<double> d(9 * N);
      const auto end = rec.sweep(y.data(), Quat{1, 0, 0, 0}, Vec3{0, 0, 0}, nullptr, d.data());
      // gamma(s) = R(s)^T v is periodic only if R(L)^T v = R(0)^T v = v.
      double qe[3][3];
      quat_to_matrix(end.q, qe);
      const double vn = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int c = 0; c < 3; ++c) {
        const double gL = qe[0][c] * v[0] + qe[1][c] * v[1] + qe[2][c] * v[2];
        if (std::abs(gL - v[c]) > 1e-8 * vn)
          throw InputError(sc.source +
                           ": initial.kind = \"rest\" with velocity (v1, v2, v3): the "
                           "intrinsic frame does not return to itself over rod.length, so a rigid "
                           "translation is not periodic (gamma" +
                           std::to_string(c + 1) + " jumps by " + num(gL - v[c]) +
                           " at s = L). Use a velocity along the axis the frame "
                           "turns about, or a twist/curvature that closes over L.");
      }
      for (std::size_t i = 0; i < N; ++i)
        for (int c = 0; c < 3; ++c) {  // gamma_c = d_c . v
          double g = 0.0;
          for (int a = 0; a < 3; ++a) g += d[9 * i + 3 * a + c] * v[a];
          set(y, N, gamma, c, i, g);
        }
    };
    k.push_back(r);
  }

  // ----------------------------------------------------- twisted_wave
  {
    InitialKindSpec r(InitialKind::twisted_wave);
    r.doc = "Exact large-amplitude bend-shear wave of a straight twisted rod (paper Eq 24 in the "
            "checked form of docs/numerics.md), k = 2 pi mode / L; needs rod.Gamma0 = [0,0,G03], "
            "rod.Omega0 = [0,0,O03] and material C1 = C2 = I1 = I2 = 1.";
    r.numbers = {{"mode", 1.0, -1e6, 1e6, "1", "integer number of wavelengths on the rod"},
                 {"A", 0.5, -kInf, kInf, "1", "shear amplitude Gamma_1^A"}};
    r.strings = {{"kappa", "p", {"p", "m"}, "modified wavenumber: p = k + Omega03, m = k - Omega03"},
                 {"branch", "plus", {"plus", "minus"}, "frequency branch w_+ or w_- of Eq 26"}};
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      require_straight_paper_rod(sc, "twisted_wave", false);
      const auto w = twisted_wave(sc);
      fill_analytic(s, y, [&](double si) { return w.at(si, 0.0); });
    };
    k.push_back(r);
  }

  // --------------------------------------------------- untwisted_wave
  {
    InitialKindSpec r(InitialKind::untwisted_wave);
    r.doc = "Asymptotic bend-shear wave of a straight untwisted rod, paper Eqs 40-45 with the "
            "corrections of docs/numerics.md, k = 2 pi mode / L; needs rod.Omega0 = 0, "
            "rod.Gamma0 = [0,0,G03], material C1 = C2 = I1 = I2 = 1.";
    r.numbers = {{"mode", 1.0, -1e6, 1e6, "1", "integer number of wavelengths on the rod"},
                 {"epsilon", 0.1, -kInf, kInf, "1", "perturbation amplitude eps"}};
    r.strings = {{"branch", "plus", {"plus", "minus"}, "frequency branch w_+ or w_- of Eq 39"}};
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      require_straight_paper_rod(sc, "untwisted_wave", true);
      analytic::UntwistedWave w;
      w.eps = initial_number(sc.initial, "epsilon");
      w.k = wavenumber(sc, "untwisted_wave");
      w.Gamma03 = sc.rod.Gamma0[2];
      w.D1 = sc.material.D[0];
      w.C3 = sc.material.C[2];
      w.omega_branch = omega_branch(initial_string(sc.initial, "branch"));
      fill_analytic(s, y, [&](double si) { return w.at(si, 0.0); });
    };
    k.push_back(r);
  }

  // ------------------------------------------------ shear_oscillation
  {
    InitialKindSpec r(InitialKind::shear_oscillation);
    r.doc = "Pure shear oscillation (paper Sec 3.1.1, Fig 4): every cross-section tilts by the same "
            "angle, the centerline stays straight. Untwisted rod: the s-independent state omega = "
            "(0, omega2, 0), Gamma = (Gamma1, 0, Gamma3), gamma = 0, Omega = Omega0. Twisted rod "
            "(Omega0 = (0, 0, O3)): the same motion seen through the twist, th = O3 s: omega = "
            "omega2 (sin th, cos th, 0), Gamma = (Gamma1 cos th, -Gamma1 sin th, Gamma3) (an "
            "s-independent omega2 would bend a twisted rod through omega x Omega0); needs Gamma0 = "
            "(0, 0, G03), C1 = C2, I1 = I2 and O3 L a multiple of 2 pi. Needs a uniform intrinsic shape.";
    r.numbers = {{"omega2", 0.0, -kInf, kInf, "1/tau", "angular velocity omega2 (of the untwisted frame)"},
                 {"Gamma1", 0.5, -kInf, kInf, "1", "shear Gamma1 (of the untwisted frame)"},
                 {"Gamma3", 1.0, -kInf, kInf, "1", "extension Gamma3 (> 0)"}};
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      if (!sc.rod.Gamma0_s.empty() || !sc.rod.Omega0_s.empty())
        throw InputError(sc.source + ": initial.kind = \"shear_oscillation\" needs a uniform "
                                     "intrinsic shape (rod.Gamma0, rod.Omega0 vectors)");
      const double O3 = sc.rod.Omega0[2];
      if (O3 != 0.0) {
        // The body frame turns by th = O3 s about d3 relative to the untwisted
        // frame in which the motion is s-independent (Eqs 28-30); that is a
        // solution only if the cross-section is isotropic in the d1-d2 plane
        // and nothing else in the intrinsic shape picks a direction.
        const Material& m = sc.material;
        if (sc.rod.Omega0[0] != 0.0 || sc.rod.Omega0[1] != 0.0 || sc.rod.Gamma0[0] != 0.0 ||
            sc.rod.Gamma0[1] != 0.0)
          throw InputError(sc.source + ": initial.kind = \"shear_oscillation\" on a twisted rod needs "
                                       "rod.Gamma0 = [0, 0, G03] and rod.Omega0 = [0, 0, O3]");
        if (material_kind(m) != MaterialKind::diagonal)
          throw InputError(sc.source + ": initial.kind = \"shear_oscillation\" on a twisted rod needs a "
                                       "diagonal material (material.C, D, I)");
        if (m.C[0] != m.C[1] || m.I[0] != m.I[1])
          throw InputError(sc.source +
                           ": initial.kind = \"shear_oscillation\" on a twisted rod needs "
                           "material.C[0] = C[1] and material.I[0] = I[1] (an isotropic cross-section)");
        const double turns = O3 * sc.rod.length / (2.0 * kPi);
        if (std::abs(turns - std::round(turns)) > 1e-9)
          throw InputError(sc.source +
                           ": initial.kind = \"shear_oscillation\" on a twisted rod needs "
                           "rod.Omega0[2] * rod.length = 2 pi x integer (the fields turn with the twist "
                           "and must be periodic); got " +
                           std::to_string(turns) + " turns");
      }
      fill_intrinsic(sc, y);
      const double w2 = initial_number(sc.initial, "omega2");
      const double G1 = initial_number(sc.initial, "Gamma1");
      const std::size_t N = s.size();
      for (std::size_t i = 0; i < N; ++i) {
        const double th = O3 * s[i];
        const double c = std::cos(th), sn = std::sin(th);
        set(y, N, omega, 0, i, w2 * sn);
        set(y, N, omega, 1, i, w2 * c);
        set(y, N, Gamma, 0, i, G1 * c);
        set(y, N, Gamma, 1, i, -G1 * sn);
        set(y, N, Gamma, 2, i, initial_number(sc.initial, "Gamma3"));
      }
    };
    k.push_back(r);
  }

  // -------------------------------------------------------- dna_planar
  {
    InitialKindSpec r(InitialKind::dna_planar);
    r.doc = "The paper's 158-bp DNA scene (Sec 6.1, Table 1): a straight twisted rod along lab Y "
            "(d1 || Z, d2 || X at s = 0) with centerline r(s,0) = (0, s, A cos(2 pi s/L)) made "
            "entirely by shear, and lab velocity (0, 0, A_v sin(2 pi s/L)). Sets rod.length = "
            "bp rise / l, rod.Gamma0 = [0,0,1], rod.Omega0 = [0,0,2 pi turns/L], and rod.points "
            "= bp unless given.";
    r.numbers = {
        {"bp", 158.0, 2.0, 1e7, "base pairs", "number of base pairs (rod length bp * rise)"},
        {"turns", 15.0, 0.0, 1e6, "turns", "helical turns over the rod (integer for a ligated ring)"},
        {"A_v_A_per_ps", 1.0, -kInf, kInf, "A/ps", "velocity amplitude A_v"},
        {"A_A", 0.0, -kInf, kInf, "A",
         "displacement amplitude A of r = A cos(2 pi s/L) (the paper does not state it)"},
        {"rise_A", dna_units::rise_A, 1e-3, 100.0, "A", "rise per base pair"}};
    r.derive_rod = [](const Initial& ini, Rod& rod, Material&, const std::set<std::string>& keys) {
      const double bp = initial_number(ini, "bp");
      const double L = bp * initial_number(ini, "rise_A") / dna_units::ell_A;
      const double O3 = 2.0 * kPi * initial_number(ini, "turns") / L;
      check_rod_value(keys, "length", rod.length, L, "dna_planar");
      if (keys.count("Gamma0")) {
        for (int c = 0; c < 3; ++c)
          check_rod_value(keys, "Gamma0", rod.Gamma0[c], c == 2 ? 1.0 : 0.0, "dna_planar");
      }
      if (keys.count("Omega0")) {
        for (int c = 0; c < 3; ++c)
          check_rod_value(keys, "Omega0", rod.Omega0[c], c == 2 ? O3 : 0.0, "dna_planar");
      }
      rod.length = L;
      rod.Gamma0 = {0.0, 0.0, 1.0};
      rod.Omega0 = {0.0, 0.0, O3};
      if (!keys.count("points") || rod.points <= 0) rod.points = static_cast<int>(std::lround(bp));
    };
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      const std::size_t N = s.size();
      const double L = sc.rod.length;
      const double O3 = sc.rod.Omega0[2], G3 = sc.rod.Gamma0[2];
      const double A = initial_number(sc.initial, "A_A") / dna_units::ell_A;
      const double Av = initial_number(sc.initial, "A_v_A_per_ps") / dna_units::velocity_A_per_ps;
      const double q = 2.0 * kPi / L;
      y.assign(12 * N, 0.0);
      for (std::size_t i = 0; i < N; ++i) {
        // Directors in the lab (X, Y, Z): d1 = (sin O3 s, 0, cos O3 s),
        // d2 = (cos O3 s, 0, -sin O3 s), d3 = (0, 1, 0); Gamma = T^-1 dr/ds
        // with dr/ds = (0, G3, -A q sin(q s)) (Eq 47), gamma = T^-1 v.
        const double c = std::cos(O3 * s[i]), sn = std::sin(O3 * s[i]);
        const double drz = -A * q * std::sin(q * s[i]);
        const double vz = Av * std::sin(q * s[i]);
        set(y, N, gamma, 0, i, c * vz);
        set(y, N, gamma, 1, i, -sn * vz);
        set(y, N, Gamma, 0, i, c * drz);
        set(y, N, Gamma, 1, i, -sn * drz);
        set(y, N, Gamma, 2, i, G3);
        set(y, N, Omega, 2, i, O3);
      }
    };
    r.anchor = [](const Scene& sc, Quat& q0, Vec3& r0) {
      const double R[3][3] = {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}};  // columns d1 = Z, d2 = X, d3 = Y
      q0 = matrix_to_quat(R);
      r0 = {0.0, 0.0, initial_number(sc.initial, "A_A") / dna_units::ell_A};
    };
    k.push_back(r);
  }

  // ------------------------------------------------------ ring_rotating
  {
    InitialKindSpec r(InitialKind::ring_rotating);
    r.doc = "A rod closed into a ring (Omega1 = 2 pi / L: the directors turn once over the "
            "fiducial length; radius Gamma3 L / 2 pi) with uniform tangential velocity gamma3. "
            "balanced = 1: Gamma3 from the force balance gamma3^2/Gamma3 = C3 (Gamma3 - Gamma03) "
            "and omega1 = Omega1 gamma3 / Gamma3 (steady rotation, constant radius); balanced = "
            "0: Gamma3 = Gamma03, omega = 0 (the ring expands and contracts). Needs rod.Gamma0 = "
            "[0,0,G03] and rod.Omega0 = [O01,0,0] (straight or intrinsically circular).";
    r.numbers = {{"gamma3", 0.5, -kInf, kInf, "l/tau", "tangential velocity gamma3"},
                 {"balanced", 1.0, 0.0, 1.0, "0/1", "1: steady rotation from the force balance"}};
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      const Rod& rod = sc.rod;
      if (!rod.Gamma0_s.empty() || !rod.Omega0_s.empty() || rod.Gamma0[0] != 0.0 || rod.Gamma0[1] != 0.0 ||
          rod.Omega0[1] != 0.0 || rod.Omega0[2] != 0.0)
        throw InputError(sc.source + ": initial.kind = \"ring_rotating\" needs uniform "
                                     "rod.Gamma0 = [0,0,G03] and rod.Omega0 = [O01,0,0]");
      const double b = initial_number(sc.initial, "balanced");
      if (b != 0.0 && b != 1.0)
        throw InputError(sc.source + ": initial.balanced must be 0 or 1, got " + num(b));
      const double g3 = initial_number(sc.initial, "gamma3");
      const double G03 = rod.Gamma0[2], C3 = sc.material.C[2];
      const double O1 = 2.0 * kPi / rod.length;
      double G3 = G03, w1 = 0.0;
      if (b == 1.0) {
        if (!(C3 > 0.0)) throw InputError(sc.source + ": ring_rotating balanced = 1 needs material.C[2] > 0");
        G3 = (C3 * G03 + std::sqrt(C3 * C3 * G03 * G03 + 4.0 * C3 * g3 * g3)) / (2.0 * C3);
        w1 = O1 * g3 / G3;
      }
      const std::size_t N = s.size();
      y.assign(12 * N, 0.0);
      for (std::size_t i = 0; i < N; ++i) {
        set(y, N, gamma, 2, i, g3);
        set(y, N, omega, 0, i, w1);
        set(y, N, Gamma, 2, i, G3);
        set(y, N, Omega, 0, i, O1);
      }
    };
    k.push_back(r);
  }

  // ------------------------------------------------------ ring_twisting
  {
    InitialKindSpec r(InitialKind::ring_twisting);
    r.doc = "A rod closed into a ring, Omega = (0, A, Omega03), Gamma = Gamma0, spinning about "
            "its centerline with uniform omega3 (paper Eq 46: with Omega0 = 0, Omega1 = A sin "
            "omega3 t, Omega2 = A cos omega3 t). A = 0 means 2 pi / L (closed ring). An "
            "intrinsic bend rod.Omega0[1] = Omega02 gives the elliptic-function motion.";
    r.numbers = {{"omega3", 0.5, -kInf, kInf, "1/tau", "spin rate omega3"},
                 {"A", 0.0, -kInf, kInf, "1/l", "bend amplitude (0: 2 pi / L, a closed ring)"}};
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      if (!sc.rod.Gamma0_s.empty() || !sc.rod.Omega0_s.empty())
        throw InputError(sc.source + ": initial.kind = \"ring_twisting\" needs a uniform intrinsic shape");
      fill_intrinsic(sc, y);
      double A = initial_number(sc.initial, "A");
      if (A == 0.0) A = 2.0 * kPi / sc.rod.length;
      const std::size_t N = s.size();
      for (std::size_t i = 0; i < N; ++i) {
        set(y, N, omega, 2, i, initial_number(sc.initial, "omega3"));
        set(y, N, Omega, 0, i, 0.0);
        set(y, N, Omega, 1, i, A);
      }
    };
    k.push_back(r);
  }

  // --------------------------------------------------------------- file
  {
    InitialKindSpec r(InitialKind::file);
    r.doc = "Initial fields from an HDF5 file (initial.path): datasets s (N) and fields/gamma, "
            "fields/omega, fields/Gamma, fields/Omega (N x 3, internal frame).";
    r.make = [](const Scene& sc, const std::vector<double>& s, std::vector<double>& y) {
      if (sc.initial.path.empty())
        throw InputError(sc.source + ": initial.kind = \"file\" needs initial.path");
      read_initial_fields(sc.initial.path, s, y);
    };
    k.push_back(r);
  }
  return k;
}

const ParamSpec* find_number(const InitialKindSpec& kind, const std::string& name) {
  for (const auto& p : kind.numbers)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace

InitialKindSpec::InitialKindSpec(InitialKind k) : kind(k), name(to_string(k)) {}

const std::vector<InitialKindSpec>& initial_kinds() {
  static const std::vector<InitialKindSpec> kinds = [] {
    std::vector<InitialKindSpec> k = build_kinds();
    // One entry per enumerator, in the order of scene.hpp's table (the order
    // messages and docs list them).
    const auto& all = ChoiceNames<InitialKind>::all;
    bool same = k.size() == all.size();
    for (std::size_t i = 0; same && i < k.size(); ++i) same = k[i].kind == all[i].value;
    if (!same)
      throw Error("initial_conditions.cpp: build_kinds() must list every InitialKind in table order");
    return k;
  }();
  return kinds;
}

const InitialKindSpec& initial_kind_spec(InitialKind kind) {
  for (const auto& k : initial_kinds())
    if (k.kind == kind) return k;
  throw InputError(invalid_choice("initial.kind", kind));
}

double initial_number(const Initial& initial, const std::string& name) {
  const InitialKindSpec& kind = initial_kind_spec(initial.kind);
  const ParamSpec* p = find_number(kind, name);
  if (!p) throw Error("initial kind \"" + kind.name + "\" has no parameter \"" + name + "\"");
  double v = p->default_value;
  if (auto it = initial.numbers.find(name); it != initial.numbers.end()) v = it->second;
  if (std::isnan(v))
    throw InputError("initial." + name + " is required for initial.kind = \"" + kind.name + "\"");
  if (!std::isfinite(v) || v < p->min || v > p->max)
    throw InputError("initial." + name + " = " + num(v) + " is out of range [" + num(p->min) + ", " +
                     num(p->max) + "] for initial.kind = \"" + kind.name + "\"");
  return v;
}

std::string initial_string(const Initial& initial, const std::string& name) {
  const InitialKindSpec& kind = initial_kind_spec(initial.kind);
  for (const auto& c : kind.strings) {
    if (c.name != name) continue;
    std::string v = c.default_value;
    if (auto it = initial.strings.find(name); it != initial.strings.end()) v = it->second;
    for (const auto& a : c.allowed)
      if (a == v) return v;
    std::string allowed;
    for (const auto& a : c.allowed) allowed += (allowed.empty() ? "\"" : ", \"") + a + "\"";
    throw InputError("initial." + name + " = \"" + v + "\" is not allowed for initial.kind = \"" + kind.name +
                     "\"; allowed: " + allowed);
  }
  throw Error("initial kind \"" + kind.name + "\" has no choice \"" + name + "\"");
}

std::vector<double> make_initial_state(const Scene& scene) {
  const InitialKindSpec& kind = initial_kind_spec(scene.initial.kind);
  const std::size_t N = static_cast<std::size_t>(scene.rod.points);
  if (scene.rod.points <= 0 || !(scene.rod.length > 0.0))
    throw InputError(scene.source + ": rod.points and rod.length must be positive");
  std::vector<double> s(N);
  for (std::size_t i = 0; i < N; ++i)
    s[i] = static_cast<double>(i) * scene.rod.length / static_cast<double>(N);
  std::vector<double> y;
  kind.make(scene, s, y);
  if (y.size() != 12 * N)
    throw Error("initial kind \"" + kind.name + "\" produced " + std::to_string(y.size()) +
                " values, expected 12 N = " + std::to_string(12 * N));
  return y;
}

std::pair<Quat, Vec3> initial_anchor(const Scene& scene) {
  const InitialKindSpec& kind = initial_kind_spec(scene.initial.kind);
  Quat q{1.0, 0.0, 0.0, 0.0};
  Vec3 r{0.0, 0.0, 0.0};
  if (kind.anchor) kind.anchor(scene, q, r);
  return {q, r};
}

}  // namespace rodcore
