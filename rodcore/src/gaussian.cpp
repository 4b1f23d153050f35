#include "rodcore/gaussian.hpp"

#include <cmath>

namespace rodcore {
namespace {

constexpr double kR = 3.442619855899;       // right edge of the widest strip
constexpr double kV = 9.91256303526217e-3;  // area of every strip (and of the base with its tail)
constexpr double kTwo31 = 2147483648.0;     // 2^31: a signed word as a fraction of a strip's width

double f(double x) { return std::exp(-0.5 * x * x); }  // the unnormalised density

// Strip i covers [0, x_i] x [f(x_i), f(x_{i-1})]; strip 0 is the base: the
// rectangle [0, r] x [0, f(r)] with the tail beyond r, as one strip of width
// q = v / f(r). w[i] = x_i / 2^31, k[i] = 2^31 x_{i-1} / x_i (below it a point
// is under the curve for sure), fx[i] = f(x_i).
struct Tables {
  std::uint32_t k[128];
  double w[128], fx[128];
  Tables() {
    const double q = kV / f(kR);
    k[0] = static_cast<std::uint32_t>(kR / q * kTwo31);
    k[1] = 0;
    w[0] = q / kTwo31;
    w[127] = kR / kTwo31;
    fx[0] = 1.0;
    fx[127] = f(kR);
    double x = kR;
    for (int i = 126; i >= 1; --i) {
      const double inner = std::sqrt(-2.0 * std::log(kV / x + f(x)));  // x_i from x_{i+1}: equal areas
      k[i + 1] = static_cast<std::uint32_t>(inner / x * kTwo31);
      x = inner;
      fx[i] = f(x);
      w[i] = x / kTwo31;
    }
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

std::uint32_t magnitude(std::int32_t v) {
  return v < 0 ? static_cast<std::uint32_t>(-(static_cast<std::int64_t>(v))) : static_cast<std::uint32_t>(v);
}

}  // namespace

std::uint32_t GaussianStream::word() {
  if (used_ == 4) {
    Philox4x32 c = ctr_;
    c[1] |= next_block_++;
    buffer_ = philox4x32_10(c, key_);
    used_ = 0;
  }
  return buffer_[used_++];
}

double GaussianStream::uniform() { return (static_cast<double>(word()) + 0.5) * 0x1p-32; }

double GaussianStream::slow(std::int32_t value, unsigned strip) {
  const Tables& t = tables();
  for (;;) {
    const double x = value * t.w[strip];
    if (strip == 0) {  // the tail beyond r (Marsaglia 1964)
      double a, b;
      do {
        a = -std::log(uniform()) / kR;
        b = -std::log(uniform());
      } while (b + b < a * a);
      return value > 0 ? kR + a : -kR - a;
    }
    if (t.fx[strip] + uniform() * (t.fx[strip - 1] - t.fx[strip]) < f(x)) return x;  // the wedge
    value = static_cast<std::int32_t>(word());
    strip = word() & 127u;
    if (magnitude(value) < t.k[strip]) return value * t.w[strip];
  }
}

void GaussianStream::six(double z[6]) {
  const Tables& t = tables();
  const Philox4x32 a = philox4x32_10(ctr_, key_);
  Philox4x32 c = ctr_;
  c[1] |= 1u;
  const Philox4x32 b = philox4x32_10(c, key_);
  const std::uint32_t values[6] = {a[0], a[1], a[2], a[3], b[0], b[1]};
  const std::uint64_t strips = static_cast<std::uint64_t>(b[2]) | (static_cast<std::uint64_t>(b[3]) << 32);
  for (int j = 0; j < 6; ++j) {
    const auto v = static_cast<std::int32_t>(values[j]);
    const unsigned s = static_cast<unsigned>(strips >> (8 * j)) & 127u;
    z[j] = magnitude(v) < t.k[s] ? v * t.w[s] : slow(v, s);
  }
}

}  // namespace rodcore
