// Standard normal numbers from the counter-based generator (philox.hpp), by
// the ziggurat method of Marsaglia & Tsang (J Stat Softw 5(8), 2000; 128
// strips, r = 3.442619855899), with the strip index taken from random bits of
// its own (Doornik 2005, "An improved ziggurat method to generate normal random
// samples"): one 32-bit word per number in ~99 % of cases, no log or sin on
// that path. The numbers of a grid point are a pure function of (seed, stream,
// step, point), as the counter-based generator's; rejections draw further
// counter blocks, so they stay so (docs/thermal.md). Tested for normality
// (moments, Kolmogorov-Smirnov, tails) in tests/cpp/test_physics_thermal.cpp.
#pragma once
#include <array>
#include <cstdint>

#include "rodcore/philox.hpp"

namespace rodcore {

class GaussianStream {
 public:
  // The counter words (w0, w1 | block, w2, w3), block = 0, 1, 2, ... (w1's low 8 bits must be 0).
  GaussianStream(std::array<std::uint32_t, 2> key, std::uint32_t w0, std::uint32_t w1, std::uint32_t w2,
                 std::uint32_t w3)
      : key_(key), ctr_{w0, w1, w2, w3} {}
  // Six numbers (a grid point's six degrees of freedom): their values from
  // blocks 0 and 1 (6 words), their strips from the other 2 words.
  void six(double z[6]);

 private:
  std::uint32_t word();  // the next word of blocks 2, 3, ... (rejections)
  double uniform();      // (0, 1) from one word
  double slow(std::int32_t value, unsigned strip);
  std::array<std::uint32_t, 2> key_;
  Philox4x32 ctr_;
  Philox4x32 buffer_{};
  unsigned next_block_ = 2, used_ = 4;
};

}  // namespace rodcore
