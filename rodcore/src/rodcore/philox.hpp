// Philox4x32-10, the counter-based random-number generator of Salmon, Moraes,
// Dror & Shaw, "Parallel random numbers: as easy as 1, 2, 3", SC'11 (the
// "Random123" paper), written from the published algorithm: a 128-bit counter
// and a 64-bit key give 128 random bits through 10 rounds of two 32 x 32 ->
// 64-bit multiplications, with a Weyl sequence bumping the key between rounds.
//
// A counter-based generator has no state: the numbers of (seed, step, grid
// point) are a pure function of them. So a thermal run is reproducible,
// independent of threads and of the order points are visited, and a
// checkpoint needs only the step index to resume bit for bit (docs/thermal.md).
// Normal numbers from it: gaussian.hpp.
// Tested against the published known-answer vectors (tests/cpp/test_physics_thermal.cpp).
#pragma once
#include <array>
#include <cstdint>

namespace rodcore {

using Philox4x32 = std::array<std::uint32_t, 4>;

inline Philox4x32 philox4x32_10(Philox4x32 ctr, std::array<std::uint32_t, 2> key) {
  constexpr std::uint32_t M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;  // round multipliers
  constexpr std::uint32_t W0 = 0x9E3779B9u, W1 = 0xBB67AE85u;  // key increments (golden ratio, sqrt 3 - 1)
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      key[0] += W0;
      key[1] += W1;
    }
    const std::uint64_t p0 = static_cast<std::uint64_t>(M0) * ctr[0];
    const std::uint64_t p1 = static_cast<std::uint64_t>(M1) * ctr[2];
    const auto hi0 = static_cast<std::uint32_t>(p0 >> 32), lo0 = static_cast<std::uint32_t>(p0);
    const auto hi1 = static_cast<std::uint32_t>(p1 >> 32), lo1 = static_cast<std::uint32_t>(p1);
    ctr = {hi1 ^ ctr[1] ^ key[0], lo1, hi0 ^ ctr[3] ^ key[1], lo0};
  }
  return ctr;
}

}  // namespace rodcore
