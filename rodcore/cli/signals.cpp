// Stop signals and the checkpoint schedule of rodsim (signals.hpp).
#include "signals.hpp"

#include <atomic>

namespace rodcore {
namespace {

std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_stop_signal(int sig) {
  int expected = 0;
  g_stop_signal.compare_exchange_strong(expected, sig);
}

}  // namespace

void install_stop_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second signal kills at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int stop_signal() { return g_stop_signal.load(); }
void clear_stop_signal() { g_stop_signal.store(0); }

CheckpointSchedule::CheckpointSchedule(double interval_s)
    : interval_s_(interval_s), last_(std::chrono::steady_clock::now()) {}

bool CheckpointSchedule::due() const {
  if (stop_signal() != 0) return true;
  if (!(interval_s_ > 0.0)) return false;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - last_).count() >= interval_s_;
}

void CheckpointSchedule::written() { last_ = std::chrono::steady_clock::now(); }

}  // namespace rodcore
