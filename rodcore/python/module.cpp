// Python module `rodcore`: run a scene from Python and get numpy arrays back.
//
//   import rodcore
//   out = rodcore.run({"rod": {"length": 6.28, "points": 32}, "output": {"t_end": 1.0}})
//   out["fields"]["Gamma"]      # (T, N, 3)
//
// or hold a simulation and step it (the C++ Simulation, rodcore/simulation.hpp):
//
//   sim = rodcore.Simulation(scene)          # dict, TOML text or path; initial= arrays
//   sim.add_observer(lambda frame: ...)      # called at every output frame
//   sim.step_to(1.0); sim.state["Gamma"]; sim.energy(); sim.rhs(sim.state)
//
// The scene is the same thing as a scene file (docs/scenes.md): a dict with
// the TOML structure, TOML text, or a path. Everything goes through the same
// reader and Simulation as rodsim, so Python and the CLI cannot disagree.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/analytic.hpp"
#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/h5_writer.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/scene_reader.hpp"
#include "rodcore/simulation.hpp"
#include "rodcore/topology.hpp"
#include "rodcore/version.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace rodcore;

namespace {

// ---- Python values -> TOML ------------------------------------------------

toml::array to_toml_array(const py::handle& seq, const std::string& where);

// A numpy array (not a 0-d scalar)?
bool is_array(const py::handle& v) {
  return py::hasattr(v, "tolist") && py::hasattr(v, "shape") && py::len(v.attr("shape")) > 0;
}
// Python bool or numpy bool_ scalar.
bool is_bool(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return true;
  return py::hasattr(v, "dtype") && !is_array(v) &&
         py::str(v.attr("dtype").attr("kind")).cast<std::string>() == "b";
}

// One Python value as a TOML node inserted into `table` under `key`.
void insert_value(toml::table& table, const std::string& key, const py::handle& v, const std::string& where) {
  if (py::isinstance<py::dict>(v)) {
    toml::table sub;
    for (auto item : py::reinterpret_borrow<py::dict>(v)) {
      std::string k = py::str(item.first);
      insert_value(sub, k, item.second, where.empty() ? k : where + "." + k);
    }
    table.insert_or_assign(key, std::move(sub));
  } else if (is_bool(v)) {
    table.insert_or_assign(key, v.cast<bool>());
  } else if (py::isinstance<py::str>(v)) {
    table.insert_or_assign(key, v.cast<std::string>());
  } else if (is_array(v)) {
    table.insert_or_assign(key, to_toml_array(v.attr("tolist")(), where));  // numpy array
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    table.insert_or_assign(key, to_toml_array(v, where));
  } else if (py::hasattr(v, "__index__")) {
    table.insert_or_assign(
        key, py::int_(py::reinterpret_borrow<py::object>(v)).cast<long long>());  // int, numpy integers
  } else if (py::hasattr(v, "__float__")) {
    table.insert_or_assign(
        key, py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>());  // float, numpy floats
  } else if (py::hasattr(v, "__fspath__")) {
    table.insert_or_assign(key, py::module_::import("os").attr("fspath")(v).cast<std::string>());
  } else {
    throw InputError("scene dict: " + where + ": cannot use a value of Python type " +
                     std::string(py::str(v.get_type().attr("__name__"))) +
                     " (allowed: dict, list, str, bool, int, float, numpy arrays)");
  }
}

toml::array to_toml_array(const py::handle& seq, const std::string& where) {
  toml::table tmp;
  toml::array out;
  std::size_t i = 0;
  for (auto item : seq) {
    insert_value(tmp, "v", item, where + "[" + std::to_string(i++) + "]");
    out.push_back(std::move(*tmp.get("v")));
  }
  return out;
}

// A scene given as dict, TOML text or path (str / os.PathLike) -> TOML table,
// its label for messages, and the folder relative paths refer to.
struct SceneSource {
  toml::table table;
  std::string label;
  std::string base_dir = ".";
};

SceneSource scene_source(const py::object& scene) {
  SceneSource src;
  if (py::isinstance<py::dict>(scene)) {
    toml::table wrapper;
    insert_value(wrapper, "scene", scene, "");
    src.table = std::move(*wrapper.get("scene")->as_table());
    src.label = "<dict>";
    return src;
  }
  std::string text;
  bool is_path = py::hasattr(scene, "__fspath__");
  if (is_path) {
    text = py::module_::import("os").attr("fspath")(scene).cast<std::string>();
  } else if (py::isinstance<py::str>(scene)) {
    text = scene.cast<std::string>();
    // TOML text has a table header or an assignment; a path has neither.
    is_path = text.find('\n') == std::string::npos && text.find('=') == std::string::npos &&
              text.find('[') == std::string::npos;
  } else {
    throw InputError("scene must be a dict, TOML text or a path to a .toml file (got " +
                     std::string(py::str(scene.get_type().attr("__name__"))) + ")");
  }
  if (is_path) {
    if (!fs::exists(text)) throw InputError("scene file '" + text + "' does not exist");
    src.table = toml::parse_file(text);
    src.label = text;
    fs::path dir = fs::path(text).parent_path();
    src.base_dir = dir.empty() ? "." : dir.string();
  } else {
    try {
      src.table = toml::parse(text, std::string_view("<string>"));
    } catch (const toml::parse_error& e) {
      throw InputError("<string>:" + std::to_string(e.source().begin.line) +
                       ": not valid TOML: " + std::string(e.description()));
    }
    src.label = "<string>";
  }
  return src;
}

// ---- numpy helpers -----------------------------------------------------------

py::array_t<double> array(const std::vector<double>& v, std::vector<py::ssize_t> shape) {
  py::array_t<double> a(shape);
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
  return a;
}

// The initial= dict: four (N, 3) arrays -> state layout.
std::vector<double> initial_state(const py::dict& initial, std::size_t& N) {
  for (auto item : initial) {
    std::string k = py::str(item.first);
    bool known = false;
    for (const char* name : kFieldNames) known |= (k == name);
    if (!known)
      throw InputError("initial: unknown key '" + k + "'; allowed: gamma, omega, Gamma, Omega (each N x 3)");
  }
  std::vector<double> y;
  N = 0;
  for (int f = 0; f < kFields; ++f) {
    const char* name = kFieldNames[f];
    if (!initial.contains(name))
      throw InputError(std::string("initial: missing '") + name +
                       "' (need gamma, omega, Gamma, Omega, each N x 3)");
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(initial[name]);
    if (!a || a.ndim() != 2 || a.shape(1) != 3)
      throw InputError(std::string("initial['") + name + "']: expected an array of shape (N, 3)");
    if (f == 0) {
      N = static_cast<std::size_t>(a.shape(0));
      y.assign(kComponents * N, 0.0);
    } else if (static_cast<std::size_t>(a.shape(0)) != N) {
      throw InputError(std::string("initial['") + name + "'] has " + std::to_string(a.shape(0)) +
                       " points, initial['gamma'] has " + std::to_string(N));
    }
    auto r = a.unchecked<2>();
    for (int c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < N; ++i) component(y.data(), N, static_cast<Field>(f), c)[i] = r(i, c);
  }
  return y;
}

// A resolved scene, and the initial state when initial= arrays replace its
// [initial] section (then recorded as kind = "file" with a note as path).
struct Resolved {
  Scene scene;
  std::optional<InitialState> initial;
};

constexpr const char* kArraysNote = "(initial= arrays given to rodcore.run; the t = 0 frame holds them)";

Resolved resolve(const py::object& scene, const py::object& initial, const std::vector<std::string>& sets) {
  SceneSource src = scene_source(scene);
  if (initial.is_none()) return {read_scene_table(std::move(src.table), src.label, src.base_dir, sets), {}};
  if (!py::isinstance<py::dict>(initial))
    throw InputError("initial must be a dict of (N, 3) arrays gamma, omega, Gamma, Omega, or None");
  std::size_t N = 0;
  InitialState state;
  state.y = initial_state(py::reinterpret_borrow<py::dict>(initial), N);
  // The arrays fix N; the scene fixes L. Resolve the rod as a scene at rest;
  // the arrays are the state on its grid (no file in between).
  toml::table table = src.table;
  auto* rod = table["rod"].as_table();
  if (!rod) table.insert("rod", toml::table{}), rod = table["rod"].as_table();
  if (!rod->contains("points")) rod->insert("points", static_cast<long long>(N));
  table.insert_or_assign("initial", toml::table{{"kind", "rest"}});
  Scene probe = read_scene_table(std::move(table), src.label, src.base_dir, sets);
  if (static_cast<std::size_t>(probe.rod.points) != N)
    throw InputError(src.label + ": rod.points = " + std::to_string(probe.rod.points) +
                     " but the initial arrays have N = " + std::to_string(N) + " points");
  probe.initial = Initial{};
  probe.initial.kind = InitialKind::file;
  probe.initial.path = kArraysNote;
  return {std::move(probe), std::move(state)};
}

std::unique_ptr<Simulation> make_simulation(Resolved& r) {
  if (r.initial) return std::make_unique<Simulation>(r.scene, std::move(*r.initial));
  return std::make_unique<Simulation>(r.scene);
}

py::dict summary_dict(const RunSummary& sum) {
  py::dict summary;
  summary["steps"] = sum.steps;
  summary["rejected"] = sum.rejected;
  summary["rhs_evaluations"] = sum.rhs_evaluations;
  summary["wall_seconds"] = sum.wall_seconds;
  summary["energy_drift"] = sum.energy_drift;
  summary["method"] = sum.method;
  summary["reduced"] = sum.reduced;
  summary["reduce_note"] = sum.reduce_note;
  summary["method_note"] = sum.method_note;
  if (!sum.thermal_note.empty()) summary["thermal_note"] = sum.thermal_note;
  return summary;
}

py::dict scales_dict() {
  return py::dict(py::arg("tau_ps") = dna_units::tau_ps, py::arg("ell_A") = dna_units::ell_A,
                  py::arg("velocity_A_per_ps") = dna_units::velocity_A_per_ps);
}

py::dict run(const py::object& scene, const py::object& initial, const std::vector<std::string>& sets,
             const py::object& output) {
  Resolved r = resolve(scene, initial, sets);
  const Scene sc = r.scene;
  auto simp = make_simulation(r);
  Simulation& sim = *simp;
  const std::vector<double> s = sim.grid();
  const std::size_t N = s.size();

  std::vector<double> time, energy, kinetic, centerline, directors, topology[3];
  std::vector<double> fields[kFields];
  std::map<std::string, std::vector<double>> parts;
  if (!output.is_none())
    sim.add_observer(std::make_shared<H5Writer>(
        py::module_::import("os").attr("fspath")(output).cast<std::string>(), sc, s));

  auto collect = [&](const Frame& fr) {
    time.push_back(fr.t);
    if (sc.output.internal)
      for (int f = 0; f < kFields; ++f)
        for (std::size_t i = 0; i < N; ++i)
          for (int c = 0; c < 3; ++c) fields[f].push_back(component(fr.y, N, static_cast<Field>(f), c)[i]);
    if (sc.output.energy && fr.energy) energy.push_back(*fr.energy);
    if (fr.kinetic_kT) kinetic.push_back(*fr.kinetic_kT);
    if (sc.output.energy_parts)
      for (const auto& [k, v] : fr.energy_parts) parts[k].push_back(v);
    if (sc.output.centerline && fr.centerline)
      centerline.insert(centerline.end(), fr.centerline, fr.centerline + 3 * N);
    if (sc.output.directors && fr.directors)
      directors.insert(directors.end(), fr.directors, fr.directors + 9 * N);
    if (fr.topology) {
      topology[0].push_back(fr.topology->Lk);
      topology[1].push_back(fr.topology->Tw);
      topology[2].push_back(fr.topology->Wr);
    }
  };

  sim.add_observer(on_frame(collect));
  RunSummary sum;
  {
    py::gil_scoped_release release;  // the integration touches no Python object
    sum = sim.run();                 // a NumericalError marks the file failed (H5Writer::failed)
  }

  const auto T = static_cast<py::ssize_t>(time.size());
  const auto n = static_cast<py::ssize_t>(N);
  py::dict out;
  out["time"] = array(time, {T});
  out["s"] = array(s, {n});
  if (sc.output.internal) {
    py::dict f;
    for (int k = 0; k < kFields; ++k) f[kFieldNames[k]] = array(fields[k], {T, n, 3});
    out["fields"] = f;
  }
  if (sc.output.energy) out["energy"] = array(energy, {T});
  if (sc.thermal.on) out["kinetic_kT"] = array(kinetic, {T});
  if (sc.output.energy_parts) {
    py::dict p;
    for (const auto& [k, v] : parts) p[py::str(k)] = array(v, {T});
    out["energy_parts"] = p;
  }
  if (sc.output.centerline) out["centerline"] = array(centerline, {T, n, 3});
  if (sc.output.directors) out["directors"] = array(directors, {T, n, 3, 3});
  if (!topology[0].empty()) {
    py::dict t;
    const char* names[3] = {"Lk", "Tw", "Wr"};
    for (int k = 0; k < 3; ++k) t[names[k]] = array(topology[k], {T});
    out["topology"] = t;
  }
  out["summary"] = summary_dict(sum);
  Scene as_run = sim.scene();  // solver.space/time as resolved from automatic
  as_run.initial.path = sc.initial.path;
  out["scene"] = scene_to_toml(as_run);
  out["scales"] = scales_dict();
  return out;
}

// ---- the Simulation object ---------------------------------------------------

// The four fields of a 12 N state as a dict of (N, 3) arrays.
py::dict fields_dict(const double* y, std::size_t N) {
  py::dict out;
  for (int f = 0; f < kFields; ++f) {
    py::array_t<double> a({static_cast<py::ssize_t>(N), py::ssize_t{3}});
    auto w = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < N; ++i)
      for (int c = 0; c < 3; ++c) w(i, c) = component(y, N, static_cast<Field>(f), c)[i];
    out[kFieldNames[f]] = a;
  }
  return out;
}

// A state given as a dict of (N, 3) arrays or a flat array of 12 N values
// (layout of state.hpp) -> 12 N values; `as_dict` says which it was.
std::vector<double> state_values(const py::object& state, std::size_t N, bool& as_dict) {
  as_dict = py::isinstance<py::dict>(state);
  if (as_dict) {
    std::size_t n = 0;
    std::vector<double> y = initial_state(py::reinterpret_borrow<py::dict>(state), n);
    if (n != N)
      throw InputError("state: the arrays have N = " + std::to_string(n) + " points, the rod has " +
                       std::to_string(N));
    return y;
  }
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(state);
  if (!a || static_cast<std::size_t>(a.size()) != kComponents * N)
    throw InputError(
        "state: expected a dict of (N, 3) arrays gamma, omega, Gamma, Omega or an array of 12 N = " +
        std::to_string(kComponents * N) + " values (layout: rows gamma1..Omega3, each N long)");
  return std::vector<double>(a.data(), a.data() + a.size());
}

// A frame as a dict of numpy arrays (copies: they outlive the call).
py::dict frame_dict(const Frame& fr) {
  const std::size_t N = fr.N;
  const auto n = static_cast<py::ssize_t>(N);
  py::dict d;
  d["index"] = fr.index;
  d["t"] = fr.t;
  d["fields"] = fields_dict(fr.y, N);
  if (fr.energy) d["energy"] = *fr.energy;
  if (fr.checked_energy) d["checked_energy"] = *fr.checked_energy;
  if (fr.energy_drift) d["energy_drift"] = *fr.energy_drift;
  if (!fr.energy_parts.empty()) {
    py::dict p;
    for (const auto& [k, v] : fr.energy_parts) p[py::str(k)] = v;
    d["energy_parts"] = p;
  }
  if (fr.centerline)
    d["centerline"] = array(std::vector<double>(fr.centerline, fr.centerline + 3 * N), {n, 3});
  if (fr.directors)
    d["directors"] = array(std::vector<double>(fr.directors, fr.directors + 9 * N), {n, 3, 3});
  if (fr.end_to_end)
    d["end_to_end"] = array(std::vector<double>(fr.end_to_end->begin(), fr.end_to_end->end()), {3});
  if (fr.end_rotation) d["end_rotation"] = *fr.end_rotation;
  if (fr.kinetic_kT) d["kinetic_kT"] = *fr.kinetic_kT;
  if (fr.end_rotation) d["max_director_norm_error"] = fr.max_director_norm_error;
  return d;
}

// A Python callable as an observer: callback(frame_dict) at every frame.
// The GIL is taken for the call only (step_to releases it).
struct PyFrameObserver : Observer {
  py::object callback;
  explicit PyFrameObserver(py::object cb) : callback(std::move(cb)) {}
  ~PyFrameObserver() override {
    py::gil_scoped_acquire gil;
    callback = py::object();
  }
  void frame(const Simulation&, const Frame& fr) override {
    py::gil_scoped_acquire gil;
    callback(frame_dict(fr));
  }
};

struct PySimulation {
  Resolved resolved;
  std::unique_ptr<Simulation> sim;
  std::vector<std::shared_ptr<Observer>> python_observers;  // kept to release them with the GIL held

  PySimulation(const py::object& scene, const py::object& initial, const std::vector<std::string>& sets)
      : resolved(resolve(scene, initial, sets)), sim(make_simulation(resolved)) {}

  void step_to(double t) {
    py::gil_scoped_release release;
    sim->step_to(t);
  }
  py::dict run() {
    RunSummary sum;
    {
      py::gil_scoped_release release;
      sum = sim->run();
    }
    return summary_dict(sum);
  }
  void add_observer(py::object callback) {
    if (!PyCallable_Check(callback.ptr()))
      throw InputError("add_observer: expected a callable f(frame: dict)");
    auto o = std::make_shared<PyFrameObserver>(std::move(callback));
    python_observers.push_back(o);
    sim->add_observer(o);
  }
  void add_output(const py::object& path) {
    sim->add_observer(std::make_shared<H5Writer>(
        py::module_::import("os").attr("fspath")(path).cast<std::string>(), resolved.scene, sim->grid()));
  }
  py::object rhs(const py::object& state) const {
    const std::size_t N = sim->grid().size();
    bool as_dict = false;
    const std::vector<double> y = state_values(state, N, as_dict);
    std::vector<double> f(kComponents * N);
    sim->rhs(y.data(), f.data());
    if (as_dict) return fields_dict(f.data(), N);
    return array(f, {static_cast<py::ssize_t>(kComponents * N)});
  }
  std::string scene_text() const {
    Scene as_run = sim->scene();
    as_run.initial.path = resolved.scene.initial.path;
    return scene_to_toml(as_run);
  }
};

}  // namespace

namespace {

py::list kinds() {
  py::list out;
  for (const auto& k : initial_kinds()) {
    py::list numbers, strings;
    for (const auto& p : k.numbers)
      numbers.append(py::dict(py::arg("name") = p.name, py::arg("default") = p.default_value,
                              py::arg("min") = p.min, py::arg("max") = p.max, py::arg("unit") = p.unit,
                              py::arg("doc") = p.doc));
    for (const auto& c : k.strings)
      strings.append(py::dict(py::arg("name") = c.name, py::arg("default") = c.default_value,
                              py::arg("allowed") = c.allowed, py::arg("doc") = c.doc));
    out.append(py::dict(py::arg("name") = k.name, py::arg("doc") = k.doc, py::arg("numbers") = numbers,
                        py::arg("strings") = strings));
  }
  return out;
}

// analytic.*: the 12 values at each s as a dict of (len(s), 3) arrays.
template <class Wave>
py::dict wave_fields(const Wave& w, const py::array_t<double, py::array::forcecast>& s_in, double t) {
  auto s = s_in.unchecked();
  if (s.ndim() > 1) throw InputError("s must be a number or a 1-D array");
  const py::ssize_t n = s.ndim() == 0 ? 1 : s.shape(0);
  std::vector<double> f[kFields];
  for (py::ssize_t i = 0; i < n; ++i) {
    double si = s.ndim() == 0 ? s_in.data()[0] : s_in.data()[i];
    analytic::Fields v = w.at(si, t);
    for (int k = 0; k < kFields; ++k)
      for (int c = 0; c < 3; ++c) f[k].push_back(v[3 * k + c]);
  }
  py::dict out;
  for (int k = 0; k < kFields; ++k) out[kFieldNames[k]] = array(f[k], {n, 3});
  return out;
}

// ---- rodcore.topology: the curve topology of topology.hpp on numpy arrays ----------

// An (n, 3) array of finite numbers, C-contiguous (a copy if needed).
py::array_t<double, py::array::c_style | py::array::forcecast> points(const py::object& x, const char* name) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(x);
  if (!a || a.ndim() != 2 || a.shape(1) != 3)
    throw InputError(std::string(name) + ": need an array of points of shape (n, 3)");
  return a;
}
const double* period_ptr(const py::object& period, std::array<double, 3>& buf) {
  if (period.is_none()) return nullptr;
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(period);
  if (!a || a.size() != 3) throw InputError("period: need 3 numbers");
  for (int c = 0; c < 3; ++c) buf[c] = a.data()[c];
  return buf.data();
}
py::array_t<double> as_points(const std::vector<double>& v) {
  return array(v, {static_cast<py::ssize_t>(v.size() / 3), py::ssize_t{3}});
}

void bind_topology(py::module_& m) {
  auto t = m.def_submodule("topology",
                           "Linking number, twist and writhe of polygons (rodcore/src/rodcore/topology.hpp, "
                           "docs/topology.md). Points: (n, 3) arrays; period: 3 numbers (box-periodic) or "
                           "None (closed).");
  namespace tp = rodcore::topology;
  t.def(
      "linking_number",
      [](const py::object& A, const py::object& B, const py::object& period) {
        auto a = points(A, "linking_number: A"), b = points(B, "linking_number: B");
        std::array<double, 3> buf{};
        return tp::linking_number(a.data(), a.shape(0), b.data(), b.shape(0), period_ptr(period, buf));
      },
      py::arg("A"), py::arg("B"), py::arg("period") = py::none(),
      "Exact integer linking number by crossings.");
  t.def(
      "gauss_linking_integral",
      [](const py::object& A, const py::object& B) {
        auto a = points(A, "A"), b = points(B, "B");
        return tp::gauss_linking_integral(a.data(), a.shape(0), b.data(), b.shape(0));
      },
      py::arg("A"), py::arg("B"), "(1/4 pi) sum of the segment solid angles of two closed polygons.");
  t.def(
      "polygon_writhe",
      [](const py::object& x) {
        auto a = points(x, "writhe");
        return tp::polygon_writhe(a.data(), a.shape(0));
      },
      py::arg("x"), "Exact writhe of the closed polygon (Klenin & Langowski), O(n^2).");
  t.def(
      "writhe",
      [](const py::object& x, int stride) {
        auto a = points(x, "writhe");
        return tp::writhe(a.data(), a.shape(0), stride);
      },
      py::arg("x"), py::arg("stride") = 1, "Writhe of the closed polygon, coarsened with stride.");
  t.def(
      "periodic_writhe",
      [](const py::object& x, const py::object& period) {
        auto a = points(x, "periodic writhe");
        std::array<double, 3> buf{};
        const double* p = period_ptr(period, buf);
        if (!p) throw InputError("periodic writhe: the period is required");
        return tp::periodic_writhe(a.data(), a.shape(0), p);
      },
      py::arg("x"), py::arg("period"), "Writhe per period relative to the straight box axis (Fuller).");
  t.def(
      "centred_tangents",
      [](const py::object& x, const py::object& period) {
        auto a = points(x, "tangents");
        std::array<double, 3> buf{};
        return as_points(tp::centred_tangents(a.data(), a.shape(0), period_ptr(period, buf)));
      },
      py::arg("x"), py::arg("period") = py::none(), "Unit tangents x_{i+1} - x_{i-1}.");
  t.def(
      "perpendicular_unit",
      [](const py::object& v, const py::object& t) {
        auto a = points(v, "ribbon vectors"), b = points(t, "tangents");
        if (a.shape(0) != b.shape(0)) throw InputError("perpendicular_unit: v and t differ in length");
        return as_points(tp::perpendicular_unit(a.data(), b.data(), a.shape(0)));
      },
      py::arg("v"), py::arg("t"), "v made perpendicular to the unit tangents t and normalised.");
  t.def(
      "twist_angles",
      [](const py::object& t, const py::object& u) {
        auto a = points(t, "tangents"), b = points(u, "ribbon");
        if (a.shape(0) != b.shape(0)) throw InputError("twist_angles: t and u differ in length");
        const auto v = tp::twist_angles(a.data(), b.data(), a.shape(0));
        return array(v, {static_cast<py::ssize_t>(v.size())});
      },
      py::arg("t"), py::arg("u"), "Transported twist angle per point [rad], cyclic.");
  t.def(
      "ribbon_topology",
      [](const py::object& x, const py::object& v, const py::object& period, int writhe_stride,
         bool coarsening) {
        auto a = points(x, "ribbon: centreline"), b = points(v, "ribbon: vectors");
        if (a.shape(0) != b.shape(0))
          throw InputError("ribbon: the centreline and the vectors differ in length");
        std::array<double, 3> buf{};
        const auto r = tp::ribbon_topology(a.data(), b.data(), a.shape(0), period_ptr(period, buf),
                                           writhe_stride, coarsening);
        return py::dict(py::arg("Lk") = r.Lk, py::arg("Tw") = r.Tw, py::arg("Wr") = r.Wr,
                        py::arg("Wr_coarsening") = r.Wr_coarsening);
      },
      py::arg("x"), py::arg("v"), py::arg("period") = py::none(), py::arg("writhe_stride") = 1,
      py::arg("coarsening") = true, "Lk, Tw, Wr (and Wr_coarsening) of the curve x framed by v.");
  t.def(
      "is_closed",
      [](const py::object& x) {
        auto a = points(x, "is_closed");
        return tp::is_closed(a.data(), a.shape(0));
      },
      py::arg("x"), "A ring: the closing edge no longer than twice the longest other edge.");
  t.def("writhe_stride", &tp::writhe_stride, py::arg("n"), py::arg("writhe_points") = tp::kWrithePoints,
        "Stride of the coarsened writhe: at most writhe_points blocks.");
  t.attr("MAX_TWIST_PER_POINT") = tp::kMaxTwistPerPoint;
  t.attr("WRITHE_POINTS") = tp::kWrithePoints;
}

}  // namespace

PYBIND11_MODULE(rodcore, m) {
  m.doc() =
      "rodcore: the geometrically exact elastic rod solver (paper Eqs 11-14) from Python.\n\n"
      "run(scene, initial=None, set=(), output=None) -> dict of numpy arrays\n"
      "Simulation(scene, initial=None, set=()): construct, step_to(t), read state, add_observer(callback)\n"
      "kinds() -> the initial-condition kinds and their parameters\n"
      "resolve(scene, set=()) -> the resolved scene as TOML text (all defaults filled)\n"
      "analytic: closed-form waves and dispersion of the paper (Eqs 24, 26, 27, 39-45)";
  m.attr("__version__") = kRodcoreVersion;
  m.attr("git_revision") = git_revision();

  // InputError is a ValueError, NumericalError a FloatingPointError, so plain
  // `except ValueError` works; the message is the C++ one, unchanged.
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<NumericalError> numerical_error(m, "NumericalError", PyExc_FloatingPointError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const NumericalError& e) {
      PyErr_SetString(numerical_error.ptr(), e.what());
    } catch (const toml::parse_error& e) {
      PyErr_SetString(input_error.ptr(), (std::string(e.source().path ? *e.source().path : "<scene>") + ":" +
                                          std::to_string(e.source().begin.line) +
                                          ": not valid TOML: " + std::string(e.description()))
                                             .c_str());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  bind_topology(m);

  m.def("run", &run, py::arg("scene"), py::arg("initial") = py::none(),
        py::arg("set") = std::vector<std::string>{}, py::arg("output") = py::none(),
        R"(Run a scene; return numpy arrays.

scene:   dict with the structure of a scene file (docs/scenes.md), TOML text,
         or a path to a .toml file. Relative paths in a dict or text are
         relative to the current folder, in a file to the file's folder.
initial: optional dict of (N, 3) arrays gamma, omega, Gamma, Omega (internal
         frame, dimensionless) on the grid s_i = i L / N; replaces the scene's
         [initial] section (rod.points defaults to N).
set:     overrides "section.key=value", as rodsim --set.
output:  optional path: also write the HDF5 file rodsim would write.

Returns a dict: time (T), s (N), fields {gamma, omega, Gamma, Omega: (T, N, 3)},
energy (T), energy_parts {name: (T)}, centerline (T, N, 3), directors
(T, N, 3, 3) [t][i][xyz][k] = component xyz of d_k -- each only if the scene's
output.fields asks --, kinetic_kT (T) for a scene with [thermal], and
summary, scene (resolved TOML), scales.
Raises rodcore.InputError (a ValueError) for bad input and
rodcore.NumericalError (a FloatingPointError) for bad numbers.
The GIL is released while integrating.)");

  m.def("kinds", &kinds, "Initial-condition kinds: list of dicts name, doc, numbers, strings.");
  m.def(
      "resolve",
      [](const py::object& scene, const std::vector<std::string>& sets) {
        return scene_to_toml(resolve(scene, py::none(), sets).scene);
      },
      py::arg("scene"), py::arg("set") = std::vector<std::string>{},
      "Validate a scene and return it resolved (every key, defaults filled) as TOML text.");

  py::class_<PySimulation>(m, "Simulation",
                           R"(A simulation of one scene that you step and read (C++ rodcore::Simulation).

Simulation(scene, initial=None, set=()): scene and initial as for run().
Everything is dimensionless (paper Sec 2.2); rodcore.run(...)["scales"] and
the output file say how to convert.)")
      .def(py::init<const py::object&, const py::object&, const std::vector<std::string>&>(),
           py::arg("scene"), py::arg("initial") = py::none(), py::arg("set") = std::vector<std::string>{})
      .def("step_to", &PySimulation::step_to, py::arg("t"),
           "Advance to time t (>= time). Frames the integrator passes go to the observers (frame 0 on the "
           "first call). Steps are not shortened to stop at t: the state at t comes from the continuous "
           "extension, so stepping in pieces equals one run. The GIL is released while integrating.")
      .def("run", &PySimulation::run,
           "Integrate to the last output time; return the summary dict (as run()['summary']).")
      .def(
          "add_observer", &PySimulation::add_observer, py::arg("callback"),
          "Call callback(frame) at every output frame; frame is a dict: index, t, fields {gamma, omega, "
          "Gamma, "
          "Omega: (N, 3)}, and when computed energy, energy_parts, checked_energy, energy_drift, centerline "
          "(N, 3), "
          "directors (N, 3, 3), end_to_end, end_rotation. An exception raised by the callback stops the run.")
      .def("add_output", &PySimulation::add_output, py::arg("path"),
           "Also write the HDF5 file rodsim would write (an observer; complete when run() finishes).")
      .def_property_readonly("time", [](const PySimulation& p) { return p.sim->time(); })
      .def_property_readonly("s",
                             [](const PySimulation& p) {
                               const auto s = p.sim->grid();
                               return array(s, {static_cast<py::ssize_t>(s.size())});
                             })
      .def_property_readonly(
          "state",
          [](const PySimulation& p) { return fields_dict(p.sim->state().data(), p.sim->grid().size()); },
          "The state at time: dict gamma, omega, Gamma, Omega of (N, 3) arrays (internal frame).")
      .def_property_readonly(
          "y",
          [](const PySimulation& p) {
            return array(p.sim->state(), {static_cast<py::ssize_t>(p.sim->state().size())});
          },
          "The state at time as 12 N values (rows gamma1..Omega3, each N long; state.hpp).")
      .def_property_readonly("frames_delivered",
                             [](const PySimulation& p) { return p.sim->frames_delivered(); })
      .def(
          "frame_time", [](const PySimulation& p, int k) { return p.sim->frame_time(k); }, py::arg("index"))
      .def(
          "energy", [](const PySimulation& p) { return p.sim->energy(); },
          "Total energy of the state (Appendix A).")
      .def("energy_parts", [](const PySimulation& p) { return p.sim->energy_parts(); })
      .def_property_readonly(
          "kinetic_kT", [](const PySimulation& p) { return p.sim->kinetic_kT(); },
          "2 KE / (6 N) of the state now: the kinetic temperature in energy units (docs/thermal.md).")
      .def("rhs", &PySimulation::rhs, py::arg("state"),
           "d(state)/dt of Eqs (11)-(14) for this rod and material (with [contact] the self-contact force "
           "included): state as a dict of (N, 3) arrays "
           "(returns the same) or 12 N values (returns 12 N values).")
      .def("summary", [](const PySimulation& p) { return summary_dict(p.sim->summary()); })
      .def_property_readonly("scene", &PySimulation::scene_text, "The scene as run, resolved, as TOML text.")
      .def_property_readonly_static("scales", [](const py::object&) { return scales_dict(); });

  auto a =
      m.def_submodule("analytic", "Closed-form results of the paper (rodcore/src/rodcore/analytic.hpp).");
  a.def("dispersion", &analytic::dispersion, py::arg("kappa"), py::arg("D1"), py::arg("Gamma03"),
        py::arg("branch"), "Eq 26 / 39: frequency w of the bend-shear wave, branch +1 (w_+) or -1 (w_-).");
  a.def("energy_ratio", &analytic::energy_ratio, py::arg("w"), py::arg("kappa"), py::arg("D1"),
        py::arg("Gamma03"), "Eq 27: shear / bend energy ratio of the exact wave.");
  py::class_<analytic::TwistedWave>(a, "TwistedWave", "The exact twisted-rod wave (Eq 24, checked form).")
      .def(py::init<>())
      .def(py::init([](double A, double k, double Gamma03, double Omega03, double D1,
                       std::string kappa_branch, int omega_branch) {
             analytic::TwistedWave w;
             w.A = A, w.k = k, w.Gamma03 = Gamma03, w.Omega03 = Omega03, w.D1 = D1;
             w.kappa_branch = std::move(kappa_branch), w.omega_branch = omega_branch;
             return w;
           }),
           py::arg("A") = 0.5, py::arg("k") = 2.0, py::arg("Gamma03") = 1.0, py::arg("Omega03") = 1.0,
           py::arg("D1") = dna_units::D_star[0], py::arg("kappa_branch") = "p", py::arg("omega_branch") = 1)
      .def_readwrite("A", &analytic::TwistedWave::A)
      .def_readwrite("k", &analytic::TwistedWave::k)
      .def_readwrite("Gamma03", &analytic::TwistedWave::Gamma03)
      .def_readwrite("Omega03", &analytic::TwistedWave::Omega03)
      .def_readwrite("D1", &analytic::TwistedWave::D1)
      .def_readwrite("kappa_branch", &analytic::TwistedWave::kappa_branch)
      .def_readwrite("omega_branch", &analytic::TwistedWave::omega_branch)
      .def("kappa", &analytic::TwistedWave::kappa)
      .def("sigma", &analytic::TwistedWave::sigma)
      .def("w", &analytic::TwistedWave::w)
      .def("a_w", &analytic::TwistedWave::a_w)
      .def("period", &analytic::TwistedWave::period)
      .def("fields", &wave_fields<analytic::TwistedWave>, py::arg("s"), py::arg("t"),
           "Fields at points s (array) and time t: dict gamma, omega, Gamma, Omega of (len(s), 3) arrays.");
  py::class_<analytic::UntwistedWave>(a, "UntwistedWave",
                                      "The asymptotic untwisted-rod wave (Eqs 40-45, corrected).")
      .def(py::init<>())
      .def(py::init([](double eps, double k, double Gamma03, double D1, double C3, int omega_branch) {
             analytic::UntwistedWave w;
             w.eps = eps, w.k = k, w.Gamma03 = Gamma03, w.D1 = D1, w.C3 = C3, w.omega_branch = omega_branch;
             return w;
           }),
           py::arg("eps") = 0.1, py::arg("k") = 2.0, py::arg("Gamma03") = 1.0,
           py::arg("D1") = dna_units::D_star[0], py::arg("C3") = dna_units::C_star[2],
           py::arg("omega_branch") = 1)
      .def_readwrite("eps", &analytic::UntwistedWave::eps)
      .def_readwrite("k", &analytic::UntwistedWave::k)
      .def_readwrite("Gamma03", &analytic::UntwistedWave::Gamma03)
      .def_readwrite("D1", &analytic::UntwistedWave::D1)
      .def_readwrite("C3", &analytic::UntwistedWave::C3)
      .def_readwrite("omega_branch", &analytic::UntwistedWave::omega_branch)
      .def("w", &analytic::UntwistedWave::w)
      .def("g", &analytic::UntwistedWave::g)
      .def("fields", &wave_fields<analytic::UntwistedWave>, py::arg("s"), py::arg("t"),
           "Fields at points s (array) and time t: dict gamma, omega, Gamma, Omega of (len(s), 3) arrays.");
}
