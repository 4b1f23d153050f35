// State layout of the rod: 12 fields in structure-of-arrays order.
// Component c of field f at grid point i lives at y[(3*f + c) * N + i],
// so every field component is one contiguous array of length N (vectorises,
// and a reduced system can integrate a subset of rows).
#pragma once
#include <array>
#include <cstddef>

namespace rodcore {

using Vec3 = std::array<double, 3>;

// Field order in the state vector (internal/body frame, paper Sec 2).
enum Field : int { gamma = 0, omega = 1, Gamma = 2, Omega = 3 };
inline constexpr int kFields = 4;
inline constexpr int kComponents = 12;  // 4 fields x 3 components
inline constexpr const char* kFieldNames[kFields] = {"gamma", "omega", "Gamma", "Omega"};

// Row index of component c (0..2) of field f.
constexpr int row(Field f, int c) { return 3 * static_cast<int>(f) + c; }

inline double* component(double* y, std::size_t N, Field f, int c) { return y + row(f, c) * N; }
inline const double* component(const double* y, std::size_t N, Field f, int c) { return y + row(f, c) * N; }

}  // namespace rodcore
