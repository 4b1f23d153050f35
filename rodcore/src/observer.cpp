// The observers made of functions (observer.hpp).
#include "rodcore/observer.hpp"

namespace rodcore {

void FunctionObserver::started(const Simulation& sim) {
  if (on_started) on_started(sim);
}
void FunctionObserver::step(const Simulation& sim, const StepView& view) {
  if (on_step) on_step(sim, view);
}
void FunctionObserver::frame(const Simulation& sim, const Frame& frame) {
  if (on_frame) on_frame(sim, frame);
}
void FunctionObserver::stepped(const Simulation& sim) {
  if (on_stepped) on_stepped(sim);
}
void FunctionObserver::finished(const Simulation& sim, const RunSummary& summary) {
  if (on_finished) on_finished(sim, summary);
}
void FunctionObserver::failed(const Simulation& sim, const std::string& message) {
  if (on_failed) on_failed(sim, message);
}

std::shared_ptr<FunctionObserver> on_frame(std::function<void(const Frame&)> f) {
  auto o = std::make_shared<FunctionObserver>();
  if (f) o->on_frame = [f = std::move(f)](const Simulation&, const Frame& fr) { f(fr); };
  return o;
}

}  // namespace rodcore
