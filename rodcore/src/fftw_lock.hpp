// FFTW's planner is not thread-safe: every plan in rodcore is made and
// destroyed under this one lock (internal header).
#pragma once
#include <mutex>

namespace rodcore {
std::mutex& fftw_planner_mutex();
}
