#include "rodcore/system.hpp"

#include <algorithm>
#include <array>

#include "rodcore/error.hpp"
#include "rodcore/reconstruction.hpp"

namespace rodcore {

RodSystem::RodSystem(const Scene& sc, bool anchor)
    : N_(static_cast<std::size_t>(sc.rod.points)),
      h_(sc.rod.length / static_cast<double>(N_)),
      anchor_(anchor),
      op_(make_derivative_operator(sc.solver.space, N_, sc.rod.length, sc.solver.dealias)),
      rhs_(std::make_unique<RodRHS>(sc.rod, sc.material, *op_)) {
  integrate(std::nullopt);
}

void RodSystem::add_force(std::unique_ptr<Force> force) { forces_.push_back(std::move(force)); }
void RodSystem::set_bath(std::unique_ptr<Bath> bath) { bath_ = std::move(bath); }
void RodSystem::add_after_step(std::unique_ptr<AfterStep> action) {
  after_step_.push_back(std::move(action));
}

void RodSystem::rhs(const double* y, double* dydt) const {
  (*rhs_)(y, dydt);
  for (const auto& force : forces_) force->add_to_rhs(y, dydt);
}

EnergyParts RodSystem::energy_parts(const double* y) const {
  EnergyParts e = rodcore::energy_parts(y, N_, h_, material(), rhs_->Gamma0(), rhs_->Omega0());
  for (const auto& force : forces_) force->add_energy(y, e);
  return e;
}

void RodSystem::integrate(std::optional<Planar> planar) {
  if (planar && (!forces_.empty() || bath_ || !after_step_.empty()))
    throw Error("the reduced planar system cannot carry forces, a bath or step actions");
  planar_rhs_.reset();
  planar_ = planar;
  rows_.clear();
  if (planar) {
    planar_rhs_ = std::make_unique<PlanarRHS>(*rhs_, *planar);
    rows_.assign(planar_rhs_->rows().begin(), planar_rhs_->rows().end());
  } else {
    for (int r = 0; r < 12; ++r) rows_.push_back(r);
  }
  full_.assign(full_size(), 0.0);
}

OdeSystem RodSystem::ode() const {
  OdeSystem sys;
  const std::size_t n = N_;
  const std::size_t at_anchor = rows_.size() * N_;  // the anchor follows the integrated rows
  const bool anchor = anchor_;
  sys.n = at_anchor + (anchor ? 7 : 0);
  // Rows of omega and gamma in the integrated state (-1: identically zero).
  std::array<int, 6> at{-1, -1, -1, -1, -1, -1};
  for (std::size_t k = 0; k < rows_.size(); ++k)
    if (rows_[k] < 6) at[rows_[k]] = static_cast<int>(k);
  const RodSystem* self = this;
  const PlanarRHS* planar = planar_rhs_.get();
  sys.f = [self, planar, n, at_anchor, anchor, at](double, const double* y, double* f) {
    if (planar) (*planar)(y, f);
    else self->rhs(y, f);
    if (anchor) {
      auto v = [&](int k) { return at[k] < 0 ? 0.0 : y[at[k] * n]; };
      const Vec3 w0{v(3), v(4), v(5)};
      const Vec3 g0{v(0), v(1), v(2)};
      anchor_rate(y + at_anchor, w0, g0, f + at_anchor);
    }
  };
  if (bath_) {
    Bath* bath = bath_.get();
    sys.bath = [bath, anchor, at_anchor](long step, double* y) {
      bath->step(step, y, anchor ? y + at_anchor : nullptr);
    };
  }
  if (!after_step_.empty()) {
    sys.project = [self, anchor, at_anchor](double t_prev, double t, double* y) {
      bool moved = false;
      for (const auto& action : self->after_step_)
        if (action->after_step(t_prev, t, y, anchor ? y + at_anchor : nullptr)) moved = true;
      return moved;
    };
  }
  return sys;
}

const double* RodSystem::expand(const double* y) {
  if (!planar_rhs_) return y;
  planar_rhs_->expand(y, full_.data());
  std::copy(y + 6 * N_, y + 6 * N_ + (anchor_ ? 7 : 0), full_.data() + 12 * N_);
  return full_.data();
}

void RodSystem::reduce(const double* full, double* y) const {
  if (!planar_rhs_) {
    std::copy(full, full + full_size(), y);
    return;
  }
  planar_rhs_->reduce(full, y);
  std::copy(full + 12 * N_, full + full_size(), y + 6 * N_);
}

// Every term feeding the six rows is a product with a zero, in exact and in
// floating-point arithmetic alike: this only catches the impossible.
bool RodSystem::reduction_holds(const double* y12) {
  f_guard_.resize(12 * N_);
  (*rhs_)(y12, f_guard_.data());
  for (int r : planar_zero_rows(*planar_))
    for (std::size_t i = 0; i < N_; ++i)
      if (f_guard_[r * N_ + i] != 0.0) return false;
  return true;
}

}  // namespace rodcore
