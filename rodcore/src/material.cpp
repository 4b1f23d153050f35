#include "rodcore/material.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"

namespace rodcore {
namespace {

std::string num(double v) { return message_number(v); }

const char* kStrainNames[6] = {"Gamma1", "Gamma2", "Gamma3", "Omega1", "Omega2", "Omega3"};

// Symmetric (to 1e-12 relative, then symmetrised), finite, positive definite.
template <int n>
void check_spd(double* A, const std::string& where, const std::string& what) {
  const std::string allowed = "; allowed: " + what;
  double amax = 0.0;
  for (int k = 0; k < n * n; ++k) {
    if (!std::isfinite(A[k]))
      throw InputError(where + ": entry [" + std::to_string(k / n) + "][" + std::to_string(k % n) +
                       "] is not finite (" + num(A[k]) + ")" + allowed);
    amax = std::max(amax, std::abs(A[k]));
  }
  for (int r = 0; r < n; ++r)
    for (int c = r + 1; c < n; ++c) {
      const double a = A[r * n + c], b = A[c * n + r];
      if (std::abs(a - b) > 1e-12 * amax)
        throw InputError(where + ": not symmetric: [" + std::to_string(r) + "][" + std::to_string(c) +
                         "] = " + num(a) + " but [" + std::to_string(c) + "][" + std::to_string(r) +
                         "] = " + num(b) + allowed);
      A[r * n + c] = A[c * n + r] = 0.5 * (a + b);
    }
  Eigen::Map<const Eigen::Matrix<double, n, n, Eigen::RowMajor>> M(A);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, n, n>> es(M, Eigen::EigenvaluesOnly);
  const double lmin = es.eigenvalues().minCoeff();
  Eigen::LLT<Eigen::Matrix<double, n, n>> llt(M);
  if (!(lmin > 0.0) || llt.info() != Eigen::Success)
    throw InputError(where + ": not positive definite (smallest eigenvalue " + num(lmin) + ")" + allowed);
}

std::array<double, 9> inverse3(const double* I) {
  Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> M(I);
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> inv = M.inverse();
  std::array<double, 9> out;
  for (int k = 0; k < 9; ++k) out[k] = inv(k / 3, k % 3);
  // Exactly symmetric, like I (the kernel stores only the upper triangle).
  for (int r = 0; r < 3; ++r)
    for (int c = r + 1; c < 3; ++c) out[r * 3 + c] = out[c * 3 + r] = 0.5 * (out[r * 3 + c] + out[c * 3 + r]);
  return out;
}

bool is_diagonal(const double* A, int n) {
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      if (r != c && A[r * n + c] != 0.0) return false;
  return true;
}

}  // namespace

void check_stiffness(double* K36, const std::string& where) {
  check_spd<6>(K36, where,
               "a symmetric positive-definite 6 x 6 matrix, rows and columns Gamma1, Gamma2, Gamma3, Omega1, "
               "Omega2, Omega3");
}

void check_inertia(double* I9, const std::string& where) {
  check_spd<3>(I9, where, "a symmetric positive-definite 3 x 3 matrix (or 3 positive numbers, its diagonal)");
}

MaterialKind material_kind(const Material& m) {
  if (!m.K_s.empty()) return MaterialKind::per_point;
  if (m.K.empty() && m.I_full.empty()) return m.rho == 1.0 ? MaterialKind::diagonal : MaterialKind::uniform;
  std::array<double, 36> K{};
  std::array<double, 9> I{};
  if (m.K.size() == 36) std::copy(m.K.begin(), m.K.end(), K.begin());
  if (m.I_full.size() == 9) std::copy(m.I_full.begin(), m.I_full.end(), I.begin());
  return (m.K.empty() || is_diagonal(K.data(), 6)) && (m.I_full.empty() || is_diagonal(I.data(), 3)) &&
                 m.rho == 1.0
             ? MaterialKind::diagonal
             : MaterialKind::uniform;
}

namespace {

// A per-point material (a material file): every point's K, I and rho checked and stored.
MaterialField resolve_per_point(const Material& m, std::size_t N) {
  MaterialField f;
  f.N = N;
  const std::string src = m.file.empty() ? std::string("material (per point)") : "file '" + m.file + "'";
  if (m.K_s.size() != 36 * N || m.I_s.size() != 9 * N || m.rho_s.size() != N)
    throw InputError(src +
                     ": per-point material needs K (N x 6 x 6), I (N x 3 x 3) and rho (N) with N = "
                     "rod.points = " +
                     std::to_string(N) + "; got " + std::to_string(m.K_s.size() / 36) + ", " +
                     std::to_string(m.I_s.size() / 9) + " and " + std::to_string(m.rho_s.size()) + " points");
  f.kind = MaterialKind::per_point;
  f.K_s.assign(21 * N, 0.0);
  f.I_s.assign(6 * N, 0.0);
  f.Iinv_s.assign(6 * N, 0.0);
  f.rho_s.assign(N, 0.0);
  f.irho_s.assign(N, 0.0);
  for (std::size_t i = 0; i < N; ++i) {
    const std::string at = " at point " + std::to_string(i);
    double K[36], I[9];
    std::copy(m.K_s.begin() + 36 * i, m.K_s.begin() + 36 * (i + 1), K);
    std::copy(m.I_s.begin() + 9 * i, m.I_s.begin() + 9 * (i + 1), I);
    check_stiffness(K, src + ": dataset 'K'" + at);
    check_inertia(I, src + ": dataset 'I'" + at);
    const double rho = m.rho_s[i];
    if (!(rho > 0.0) || !std::isfinite(rho))
      throw InputError(src + ": dataset 'rho'" + at + " is " + num(rho) + "; allowed: a finite number > 0");
    const auto Iinv = inverse3(I);
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c) f.K_s[sym6(r, c) * N + i] = K[r * 6 + c];
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) {
        f.I_s[sym3(r, c) * N + i] = I[r * 3 + c];
        f.Iinv_s[sym3(r, c) * N + i] = Iinv[r * 3 + c];
      }
    f.rho_s[i] = rho;
    f.irho_s[i] = 1.0 / rho;
  }
  return f;
}

}  // namespace

MaterialField resolve_material(const Material& m, std::size_t N) {
  if (!m.K_s.empty() || !m.I_s.empty() || !m.rho_s.empty()) return resolve_per_point(m, N);
  MaterialField f;
  f.N = N;

  // Uniform: the full matrices from K / I_full, or from the diagonals.
  if (!m.K.empty() && m.K.size() != 36)
    throw InputError("material.K: found " + std::to_string(m.K.size()) +
                     " values; allowed: a 6 x 6 matrix (6 arrays of 6 numbers)");
  if (!m.I_full.empty() && m.I_full.size() != 9)
    throw InputError("material.I: found " + std::to_string(m.I_full.size()) +
                     " values; allowed: 3 numbers or a 3 x 3 matrix");
  for (int c = 0; c < 3; ++c) {
    if (m.K.empty() &&
        (!(m.C[c] > 0.0) || !std::isfinite(m.C[c]) || !(m.D[c] > 0.0) || !std::isfinite(m.D[c])))
      throw InputError("material.C and material.D: all components must be positive and finite (got C[" +
                       std::to_string(c) + "] = " + num(m.C[c]) + ", D[" + std::to_string(c) +
                       "] = " + num(m.D[c]) + ")");
    if (m.I_full.empty() && (!(m.I[c] > 0.0) || !std::isfinite(m.I[c])))
      throw InputError("material.I: all three components must be positive and finite (got I[" +
                       std::to_string(c) + "] = " + num(m.I[c]) + ")");
  }
  if (!(m.rho > 0.0) || !std::isfinite(m.rho))
    throw InputError("material.rho: found " + num(m.rho) + "; allowed: a finite number > 0");
  if (m.K.empty()) {
    for (int c = 0; c < 3; ++c) {
      f.K[c * 7] = m.C[c];
      f.K[(c + 3) * 7] = m.D[c];
    }
  } else {
    std::copy(m.K.begin(), m.K.end(), f.K.begin());
    check_stiffness(f.K.data(), "material.K");
  }
  if (m.I_full.empty()) {
    for (int c = 0; c < 3; ++c) f.I[c * 4] = m.I[c];
  } else {
    std::copy(m.I_full.begin(), m.I_full.end(), f.I.begin());
    check_inertia(f.I.data(), "material.I");
  }
  f.Iinv = inverse3(f.I.data());
  f.rho = m.rho;
  // The paper's kernel has no 1/rho (rho = 1 in its units); rho != 1 runs the
  // coupled kernel, which has.
  f.kind = is_diagonal(f.K.data(), 6) && is_diagonal(f.I.data(), 3) && m.rho == 1.0 ? MaterialKind::diagonal
                                                                                    : MaterialKind::uniform;
  return f;
}

namespace {

// Full n x n matrix at point i: the uniform one, or unpacked from the
// per-point upper-triangle rows (`index` = sym6 or sym3).
template <int n, std::size_t m>
void matrix_at(const MaterialField& f, const std::array<double, m>& uniform, const std::vector<double>& rows,
               int (*index)(int, int), std::size_t i, double* out) {
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      out[r * n + c] = f.kind == MaterialKind::per_point ? rows[index(r, c) * f.N + i] : uniform[r * n + c];
}

}  // namespace

void MaterialField::K_at(std::size_t i, double* K36) const { matrix_at<6>(*this, K, K_s, sym6, i, K36); }
void MaterialField::I_at(std::size_t i, double* I9) const { matrix_at<3>(*this, I, I_s, sym3, i, I9); }

double MaterialField::rho_at(std::size_t i) const { return kind == MaterialKind::per_point ? rho_s[i] : rho; }

double max_wave_speed(const MaterialField& mf) {
  const std::size_t points = mf.kind == MaterialKind::per_point ? mf.N : 1;
  double c2 = 0.0;
  for (std::size_t i = 0; i < points; ++i) {
    double K[36], I[9];
    mf.K_at(i, K);
    mf.I_at(i, I);
    Eigen::Matrix<double, 6, 6> Km, Mm = Eigen::Matrix<double, 6, 6>::Zero();
    for (int k = 0; k < 36; ++k) Km(k / 6, k % 6) = K[k];
    for (int c = 0; c < 3; ++c) Mm(c, c) = mf.rho_at(i);
    for (int k = 0; k < 9; ++k) Mm(3 + k / 3, 3 + k % 3) = I[k];
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(Km, Mm, Eigen::EigenvaluesOnly);
    c2 = std::max(c2, es.eigenvalues().maxCoeff());
  }
  return std::sqrt(c2);
}

std::string planar_coupling(const MaterialField& mf, const std::array<int, 3>& kept, int axis) {
  auto is_kept = [&](int j) { return std::find(kept.begin(), kept.end(), j) != kept.end(); };
  const std::size_t points = mf.kind == MaterialKind::per_point ? mf.N : 1;
  for (std::size_t i = 0; i < points; ++i) {
    const std::string at = mf.kind == MaterialKind::per_point ? " at point " + std::to_string(i) : "";
    double K[36], I[9];
    mf.K_at(i, K);
    mf.I_at(i, I);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c)
        if (is_kept(r) && !is_kept(c) && K[r * 6 + c] != 0.0)
          return "K[" + std::to_string(r) + "][" + std::to_string(c) + "] = " + num(K[r * 6 + c]) + at +
                 " couples " + kStrainNames[r] + " to " + kStrainNames[c];
    for (int c = 0; c < 3; ++c)
      if (c != axis && (I[axis * 3 + c] != 0.0 || I[c * 3 + axis] != 0.0))
        return "I[" + std::to_string(axis) + "][" + std::to_string(c) + "] = " + num(I[axis * 3 + c]) + at +
               " couples omega" + std::to_string(axis + 1) + " to omega" + std::to_string(c + 1);
  }
  return {};
}

}  // namespace rodcore
