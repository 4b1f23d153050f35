// Initial conditions: a registry of kinds (the enum InitialKind of
// scene.hpp, one entry each). Each kind declares its
// parameters (so the scene reader can validate them and docs can list them),
// may derive rod settings it implies, makes the 12 N initial state, and may
// fix the lab frame of the rod at s = 0 (for reconstruction; default: the
// directors d_k = e_k and r(0) = 0).
#pragma once
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rodcore/reconstruction.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

struct ParamSpec {
  std::string name;
  double default_value;  // NaN = required
  double min, max;
  std::string unit, doc;
};

struct ChoiceSpec {
  std::string name;
  std::string default_value;
  std::vector<std::string> allowed;
  std::string doc;
};

// A kind of the registry: the enumerator of scene.hpp, its spelling, and
// what the kind declares and does.
struct InitialKindSpec {
  explicit InitialKindSpec(InitialKind kind);
  InitialKind kind;
  std::string name;  // to_string(kind)
  std::string doc;
  std::vector<ParamSpec> numbers;
  std::vector<ChoiceSpec> strings;
  // Optional: fill/verify rod settings the kind implies (e.g. the DNA scene
  // sets length, Gamma0 and Omega0). set_keys: rod keys given explicitly in
  // the scene ("length", "points", "Gamma0", "Omega0"); an explicit value
  // that disagrees is an InputError.
  std::function<void(const Initial&, Rod&, Material&, const std::set<std::string>& set_keys)> derive_rod;
  // Fill y (resized to 12 N) at the grid points s.
  std::function<void(const Scene&, const std::vector<double>& s, std::vector<double>& y)> make;
  // Optional: lab frame (quaternion, position) of the rod at s = 0, t = 0.
  std::function<void(const Scene&, Quat& q0, Vec3& r0)> anchor;
};

// Every kind, in the order of scene.hpp's ChoiceNames<InitialKind>.
const std::vector<InitialKindSpec>& initial_kinds();
// The registry entry of a kind. Throws InputError for a value that is not one.
const InitialKindSpec& initial_kind_spec(InitialKind kind);

// The value of a numeric parameter: scene value, else the declared default,
// else InputError (required). Also checks the declared range.
double initial_number(const Initial& initial, const std::string& name);
std::string initial_string(const Initial& initial, const std::string& name);

// The 12 N initial state of a scene at its grid points s_i = i L / N.
std::vector<double> make_initial_state(const Scene& scene);
// The lab frame at s = 0, t = 0.
std::pair<Quat, Vec3> initial_anchor(const Scene& scene);

}  // namespace rodcore
