#include "rodcore/operators.hpp"

#include <fftw3.h>

#include <cmath>
#include <complex>
#include <mutex>
#include <numbers>
#include <vector>

#include "fftw_lock.hpp"
#include "rodcore/error.hpp"

namespace rodcore {

std::mutex& fftw_planner_mutex() {
  static std::mutex m;
  return m;
}

namespace {

class FD4 final : public DerivativeOperator {
 public:
  FD4(std::size_t N, double L) : DerivativeOperator(N, L) {}
  std::string name() const override { return "fd4"; }
  double max_wavenumber() const override {
    // max over theta of (8 sin(theta) - sin(2 theta)) / (6 h), at cos(theta) = 1 - sqrt(3/2)
    const double c = 1.0 - std::sqrt(1.5);
    const double s = std::sqrt(1.0 - c * c);
    return (8.0 * s - 2.0 * s * c) / 6.0 / h();
  }
  void apply(const double* f, double* df, int rows) const override {
    const std::size_t N = N_;
    const double a = 1.0 / (12.0 * h());
    for (int r = 0; r < rows; ++r) {
      const double* u = f + r * N;
      double* du = df + r * N;
      auto at = [&](std::ptrdiff_t i) {
        return u[(i + static_cast<std::ptrdiff_t>(N)) % static_cast<std::ptrdiff_t>(N)];
      };
      for (std::size_t i = 0; i < 2 && i < N; ++i) {
        const auto j = static_cast<std::ptrdiff_t>(i);
        du[i] = a * (at(j - 2) - 8.0 * at(j - 1) + 8.0 * at(j + 1) - at(j + 2));
      }
      for (std::size_t i = 2; i + 2 < N; ++i)
        du[i] = a * (u[i - 2] - 8.0 * u[i - 1] + 8.0 * u[i + 1] - u[i + 2]);
      for (std::size_t i = N - 2; i < N; ++i) {
        const auto j = static_cast<std::ptrdiff_t>(i);
        du[i] = a * (at(j - 2) - 8.0 * at(j - 1) + 8.0 * at(j + 1) - at(j + 2));
      }
    }
  }
};

class Spectral final : public DerivativeOperator {
 public:
  static constexpr int kMaxRows = 12;

  Spectral(std::size_t N, double L, bool dealias)
      : DerivativeOperator(N, L), dealias_(dealias), M_(N / 2 + 1) {
    real_ = static_cast<double*>(fftw_malloc(sizeof(double) * N * kMaxRows));
    spec_ = static_cast<fftw_complex*>(fftw_malloc(sizeof(fftw_complex) * M_ * kMaxRows));
    if (!real_ || !spec_) throw Error("spectral operator: out of memory (N = " + std::to_string(N) + ")");
    const int n = static_cast<int>(N);
    const int m = static_cast<int>(M_);
    {
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      for (int rows = 1; rows <= kMaxRows; ++rows) {
        forward_[rows - 1] =
            fftw_plan_many_dft_r2c(1, &n, rows, real_, nullptr, 1, n, spec_, nullptr, 1, m, FFTW_ESTIMATE);
        backward_[rows - 1] =
            fftw_plan_many_dft_c2r(1, &n, rows, spec_, nullptr, 1, m, real_, nullptr, 1, n, FFTW_ESTIMATE);
      }
    }
    // i k / N (FFTW's transforms are unnormalised), zero where the mode is cut.
    factor_.assign(M_, 0.0);
    const double dk = 2.0 * std::numbers::pi / L;
    for (std::size_t j = 0; j < M_; ++j) {
      bool keep = true;
      if (N % 2 == 0 && j == N / 2) keep = false;  // Nyquist mode
      if (dealias_ && 3 * j > N) keep = false;     // 2/3 rule: |m| > N/3
      factor_[j] = keep ? dk * static_cast<double>(j) / static_cast<double>(N) : 0.0;
    }
    kmax_ = 0.0;
    for (std::size_t j = 0; j < M_; ++j)
      if (factor_[j] != 0.0) kmax_ = dk * static_cast<double>(j);
  }
  ~Spectral() override {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    for (auto& p : forward_) fftw_destroy_plan(p);
    for (auto& p : backward_) fftw_destroy_plan(p);
    fftw_free(real_);
    fftw_free(spec_);
  }
  std::string name() const override { return dealias_ ? "spectral-dealiased" : "spectral"; }
  double max_wavenumber() const override { return kmax_; }

  void apply(const double* f, double* df, int rows) const override {
    int done = 0;
    while (done < rows) {
      const int r = std::min(kMaxRows, rows - done);
      const std::size_t n = N_ * static_cast<std::size_t>(r);
      std::copy(f + done * N_, f + done * N_ + n, real_);
      fftw_execute(forward_[r - 1]);
      for (int row = 0; row < r; ++row) {
        fftw_complex* c = spec_ + row * M_;
        for (std::size_t j = 0; j < M_; ++j) {
          // (a + i b) * i k = -k b + i k a
          const double re = c[j][0], im = c[j][1];
          c[j][0] = -factor_[j] * im;
          c[j][1] = factor_[j] * re;
        }
      }
      fftw_execute(backward_[r - 1]);
      std::copy(real_, real_ + n, df + done * N_);
      done += r;
    }
  }

 private:
  bool dealias_;
  std::size_t M_;
  double* real_ = nullptr;
  fftw_complex* spec_ = nullptr;
  fftw_plan forward_[kMaxRows]{};
  fftw_plan backward_[kMaxRows]{};
  std::vector<double> factor_;
  double kmax_ = 0.0;
};

}  // namespace

std::unique_ptr<DerivativeOperator> make_derivative_operator(SpaceMethod kind, std::size_t N, double L,
                                                             bool dealias) {
  if (!(L > 0.0) || !std::isfinite(L))
    throw InputError("derivative operator: rod length must be positive and finite, got " + std::to_string(L));
  if (kind == SpaceMethod::fd4) {
    if (N < 5) throw InputError("solver.space = \"fd4\" needs rod.points >= 5, got " + std::to_string(N));
    return std::make_unique<FD4>(N, L);
  }
  if (kind == SpaceMethod::spectral) {
    if (N < 4)
      throw InputError("solver.space = \"spectral\" needs rod.points >= 4, got " + std::to_string(N));
    return std::make_unique<Spectral>(N, L, dealias);
  }
  throw InputError("solver.space = \"" + to_string(kind) +
                   "\" is not a derivative operator; allowed: \"fd4\", \"spectral\"");
}

}  // namespace rodcore
