// The strand-passage guard of a closed rod with self-contact (docs/topology.md, "Self-contact"):
// its linking number must not change, because the contact forbids the rod to pass through
// itself. After every accepted step the guard either certifies that no segment of the polygon
// can have crossed another, or checks the linking number exactly:
//   certified  every two edges that share no point were farther apart before the step than their
//              end points moved relative to each other (the centreline reconstructed from the
//              strains, the new one superposed on the old: a rigid motion of the whole does not
//              change whether strands cross); along the straight path from the old polygon to
//              the new one no two such edges then meet (uncertified_edge_pairs).
//   otherwise  Lk of the ribbon along d1 (topology.hpp, exact integer, O(N)) against Lk0, the
//              linking number of the state the run starts from, at the first step whose polygon
//              is closed (between the closure holds of an inertial run it may be open).
// A changed Lk is a NumericalError naming the step: the contact let a strand through (a smaller
// solver.dt or a larger contact.barrier_kT). The run's summary counts the steps not certified.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "rodcore/force.hpp"

namespace rodcore {

class Reconstructor;

// The number of edge pairs of the closed polygon x (n x 3) that share no point and are not certified
// to stay apart on the straight path from x to y (n x 3): O(n) for a polygon of bounded density.
std::size_t uncertified_edge_pairs(const double* x, const double* y, std::size_t n);

class StrandPassageGuard : public AfterStep {
 public:
  // y12: the state the run starts from (12 N), which gives Lk0 and the first polygon; a resumed
  // run's first step is then checked by Lk (its Lk is the initial one, or the run had stopped)
  StrandPassageGuard(std::size_t N, double L, const double* y12);
  ~StrandPassageGuard() override;
  bool after_step(double t_prev, double t, double* y, double* anchor) override;  // never moves y
  std::string note() const;                                                      // for the run's summary
  long steps() const { return steps_; }
  long uncertified() const { return uncertified_; }
  long Lk0() const { return Lk0_; }

 private:
  long linking(const double* y12);
  std::size_t N_;
  std::unique_ptr<Reconstructor> rec_;
  std::vector<double> x_old_, x_new_, directors_;
  long Lk0_ = 0, steps_ = 0, uncertified_ = 0;
  bool pending_ = false;  // a step not certified, its Lk not yet checked on a closed state
};

}  // namespace rodcore
