// The closure of a periodic rod kept during a run (docs/thermal.md, "Closure
// in a run"). The fields are periodic in s, so the continuum rod keeps the
// rigid motion that carries its frame at s = 0 to its frame at s = L, seen
// in the lab:
//   T = g(0) H g(0)^-1,   H = g(0)^-1 g(L)  (the holonomy of the strains),
// the identity for a closed ring, the box translation (and the total twist)
// for a box-held rod. The semi-discrete rod keeps it only to its spatial
// error, which for thermal fields (content at every resolved wavenumber) is
// not small. A ClosureProjector puts a state back on the closure manifold:
// it changes only the strains e = (Gamma, Omega), by the least change in the
// energy metric h sum_i de_i.K_i de_i that makes H(e) = g(0)^-1 T g(0) (six
// constraints), with g(0) the frame at s = 0 now (the run's anchor). The
// velocities are left alone: the continuum flow keeps the closure for any
// periodic velocity field, so the closure constrains no velocity.
//
// The six directions are those of the sampler's conditioning (thermal.hpp):
// the change of H per strain change at point i is the block
//   B_i = h Ad_g(s_i) = h [[0, R_i], [R_i, [r_i]x R_i]]   ((dGamma, dOmega) -> (rotation, translation)),
// with frames (R_i, r_i) from the identity at s = 0, and a chord-Newton step
//   de_i = -K_i^-1 B_i^T S^-1 d,   S = sum_i B_i K_i^-1 B_i^T,
// removes the holonomy defect d (a twist: g_now = exp(d) g_target). Each step
// costs one reconstruction sweep (reconstruction.hpp) and O(N) algebra.
#pragma once
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "rodcore/material.hpp"
#include "rodcore/reconstruction.hpp"

namespace rodcore {

// A rigid motion (R(q), r): a holonomy, or the box motion T in the lab.
struct RigidMotion {
  Quat q{1.0, 0.0, 0.0, 0.0};
  Vec3 r{0.0, 0.0, 0.0};
};

// g a b: the composition of rigid motions, and the inverse.
RigidMotion compose(const RigidMotion& a, const RigidMotion& b);
RigidMotion inverse(const RigidMotion& a);

class ClosureProjector {
 public:
  // N points, rod length L, the resolved material (its K_i give the metric);
  // max_turn: the frame rotation per Magnus substep of its sweeps
  // (reconstruction.hpp; the output's sweep uses 0.05).
  ClosureProjector(std::size_t N, double L, const MaterialField& mf, double max_turn = 0.05);
  ~ClosureProjector();
  ClosureProjector(const ClosureProjector&) = delete;
  ClosureProjector& operator=(const ClosureProjector&) = delete;

  // H = g(0)^-1 g(L) of the 12 N state y (one sweep; frames kept for a
  // following linearise()).
  RigidMotion holonomy(const double* y);

  // B_i and S = sum B_i K_i^-1 B_i^T at the frames of the last holonomy().
  void linearise();
  // sum_i B_i e_i for strain changes e (6 rows of N: Gamma1..3, Omega1..3),
  // at the last linearise(): the linear change of the holonomy twist.
  std::array<double, 6> linear_change(const double* e) const;
  // Adds -K_i^-1 B_i^T S^-1 d to e (6 rows of N): removes the holonomy
  // defect d (rotation, translation) at linear order, in the metric K / h.
  void remove(const std::array<double, 6>& d, double* e) const;

  // The defect twist d of `now` against `target`: now = exp(d) target to
  // first order (rotation vector of R_now R_target^T; r_now - R(d) r_target).
  static std::array<double, 6> defect(const RigidMotion& now, const RigidMotion& target);
  // max(|rotation|, |translation| / max(1, L)): the size of a defect.
  double size(const std::array<double, 6>& d) const;

  // What project() did.
  struct Result {
    double gap_before = 0.0;  // size() of the defect found
    int steps = 0;            // chord-Newton steps taken (each one sweep, the last unchecked)
  };
  // Moves the strains of the 12 N state y onto H = target: linearises at y,
  // then `steps` chord-Newton steps, each but the last checked by a sweep
  // (the gap left by the last one is second order in the gap it found and is
  // removed by the next call). Nothing is changed when the gap is below
  // `tolerance`. relinearise: Newton steps instead, each linearised at the
  // state the last check swept and removing the defect as the screw of its
  // exact SE(3) logarithm, stopping once the gap is below `tolerance`
  // (a long ring, whose defect per step moves its far end by lever arms of
  // its own size, needs them: docs/thermal.md, "The overdamped rod").
  Result project(double* y, const RigidMotion& target, int steps = 1, double tolerance = 1e-13,
                 bool relinearise = false);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The holonomy a box motion T (lab) asks of a rod whose frame at s = 0 is g0:
// g0^-1 T g0; and the box motion of a holonomy H seen from g0: g0 H g0^-1.
RigidMotion holonomy_for(const RigidMotion& T, const RigidMotion& g0);
RigidMotion box_motion(const RigidMotion& H, const RigidMotion& g0);

}  // namespace rodcore
