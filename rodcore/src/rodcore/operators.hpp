// Spatial derivative d/ds on the periodic grid s_i = i L / N (paper Sec 5.1).
// One interface, two discretisations:
//   "fd4"      the paper's 4th-order central difference,
//               f'(s) ~ [f(s-2h) - 8 f(s-h) + 8 f(s+h) - f(s+2h)] / (12 h);
//   "spectral" Fourier pseudo-spectral (FFTW r2c/c2r, plans made once):
//               f' = IFFT(i k FFT(f)), the Nyquist mode zeroed (an odd
//               derivative of a real grid function has no real Nyquist part).
//               With dealias = true the derivative is also low-pass filtered
//               by the 2/3 rule: every mode with |m| > N/3 (m = k L / 2 pi)
//               is zeroed in the derivative. The fields themselves are not
//               filtered; see docs/numerics.md.
// Both operators are skew-symmetric on the grid, so the semi-discrete energy
// (Appendix A) is conserved exactly; only the time integrator changes it.
#pragma once
#include <cstddef>
#include <memory>
#include <string>

#include "rodcore/scene.hpp"  // SpaceMethod

namespace rodcore {

class DerivativeOperator {
 public:
  DerivativeOperator(std::size_t N, double L) : N_(N), L_(L) {}
  virtual ~DerivativeOperator() = default;
  DerivativeOperator(const DerivativeOperator&) = delete;
  DerivativeOperator& operator=(const DerivativeOperator&) = delete;

  virtual std::string name() const = 0;
  // d/ds of `rows` contiguous arrays of length N: f[r*N + i] -> df[r*N + i].
  // f and df must not overlap. No allocation when rows <= 12.
  virtual void apply(const double* f, double* df, int rows) const = 0;
  // Largest |eigenvalue| of the operator (its largest effective wavenumber):
  // FD4 ~1.3722/h, spectral pi/h (or (N/3) 2 pi / L with dealias). Used for
  // the explicit-scheme CFL estimate.
  virtual double max_wavenumber() const = 0;

  std::size_t N() const { return N_; }
  double L() const { return L_; }
  double h() const { return L_ / static_cast<double>(N_); }

 protected:
  std::size_t N_;
  double L_;
};

// kind = fd4 | spectral; throws InputError otherwise (automatic is resolved
// by Simulation before) or when N is too small.
std::unique_ptr<DerivativeOperator> make_derivative_operator(SpaceMethod kind, std::size_t N, double L,
                                                             bool dealias = false);

}  // namespace rodcore
