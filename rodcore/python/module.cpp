// Python module `rodcore`: run a scene from Python and get numpy arrays back.
//
//   import rodcore
//   out = rodcore.run({"rod": {"length": 6.28, "points": 32}, "output": {"t_end": 1.0}})
//   out["fields"]["Gamma"]      # (T, N, 3)
//
// The scene is the same thing as a scene file (docs/scenes.md): a dict with
// the TOML structure, TOML text, or a path. Everything goes through the same
// reader and Simulation as rodsim, so Python and the CLI cannot disagree.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/analytic.hpp"
#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/h5_initial.hpp"
#include "rodcore/h5_output.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/scene_reader.hpp"
#include "rodcore/simulation.hpp"

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
    table.insert_or_assign(key, py::int_(py::reinterpret_borrow<py::object>(v)).cast<long long>());  // int, numpy integers
  } else if (py::hasattr(v, "__float__")) {
    table.insert_or_assign(key, py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>());  // float, numpy floats
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
      throw InputError("<string>:" + std::to_string(e.source().begin.line) + ": not valid TOML: " +
                       std::string(e.description()));
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
      throw InputError(std::string("initial: missing '") + name + "' (need gamma, omega, Gamma, Omega, each N x 3)");
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

// A temporary file removed when this goes out of scope.
struct TempFile {
  std::string path;
  TempFile() {
    static std::atomic<int> counter{0};
    path = (fs::temp_directory_path() /
            ("rodcore_initial_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".h5"))
               .string();
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

// Resolves the scene, with initial= arrays replacing [initial] if given.
Scene resolve(const py::object& scene, const py::object& initial, const std::vector<std::string>& sets,
              std::optional<TempFile>& tmp) {
  SceneSource src = scene_source(scene);
  if (initial.is_none()) return read_scene_table(std::move(src.table), src.label, src.base_dir, sets);
  if (!py::isinstance<py::dict>(initial))
    throw InputError("initial must be a dict of (N, 3) arrays gamma, omega, Gamma, Omega, or None");
  std::size_t N = 0;
  std::vector<double> y = initial_state(py::reinterpret_borrow<py::dict>(initial), N);
  // The arrays fix N; the scene fixes L. Resolve the rod first (as a scene at
  // rest), then write the arrays on its grid and read them as kind = "file".
  toml::table table = src.table;
  auto* rod = table["rod"].as_table();
  if (!rod) table.insert("rod", toml::table{}), rod = table["rod"].as_table();
  if (!rod->contains("points")) rod->insert("points", static_cast<long long>(N));
  table.insert_or_assign("initial", toml::table{{"kind", "rest"}});
  Scene probe = read_scene_table(table, src.label, src.base_dir, sets);
  if (static_cast<std::size_t>(probe.rod.points) != N)
    throw InputError(src.label + ": rod.points = " + std::to_string(probe.rod.points) + " but the initial arrays have N = " +
                     std::to_string(N) + " points");
  std::vector<double> s(N);
  for (std::size_t i = 0; i < N; ++i) s[i] = static_cast<double>(i) * probe.rod.length / static_cast<double>(N);
  tmp.emplace();
  write_initial_fields(tmp->path, s, y);
  table.insert_or_assign("initial", toml::table{{"kind", "file"}, {"path", tmp->path}});
  return read_scene_table(std::move(table), src.label, src.base_dir, sets);
}

py::dict run(const py::object& scene, const py::object& initial, const std::vector<std::string>& sets,
             const py::object& output) {
  std::optional<TempFile> tmp;
  Scene sc = resolve(scene, initial, sets, tmp);
  Simulation sim(sc);  // reads the initial state now
  // The temporary IC file dies with this call: say where the state came from instead.
  if (tmp) sc.initial.path = "(initial= arrays given to rodcore.run; the t = 0 frame holds them)";
  const std::vector<double> s = sim.grid();
  const std::size_t N = s.size();

  std::vector<double> time, energy, centerline, directors;
  std::vector<double> fields[kFields];
  std::map<std::string, std::vector<double>> parts;
  std::optional<H5Output> h5;
  if (!output.is_none())
    h5.emplace(py::module_::import("os").attr("fspath")(output).cast<std::string>(), sc, s);

  auto on_frame = [&](const Frame& fr) {
    time.push_back(fr.t);
    if (sc.output.internal)
      for (int f = 0; f < kFields; ++f)
        for (std::size_t i = 0; i < N; ++i)
          for (int c = 0; c < 3; ++c) fields[f].push_back(component(fr.y, N, static_cast<Field>(f), c)[i]);
    if (sc.output.energy && fr.energy) energy.push_back(*fr.energy);
    if (sc.output.energy_parts)
      for (const auto& [k, v] : fr.energy_parts) parts[k].push_back(v);
    if (sc.output.centerline && fr.centerline) centerline.insert(centerline.end(), fr.centerline, fr.centerline + 3 * N);
    if (sc.output.directors && fr.directors) directors.insert(directors.end(), fr.directors, fr.directors + 9 * N);
    if (h5) h5->write_frame(fr);
  };

  RunSummary sum;
  {
    py::gil_scoped_release release;  // the integration touches no Python object
    try {
      sum = sim.run(on_frame);
    } catch (const NumericalError& e) {
      if (h5) h5->fail(e.what());
      throw;
    }
  }
  if (h5) h5->finish(sum);

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
  if (sc.output.energy_parts) {
    py::dict p;
    for (const auto& [k, v] : parts) p[py::str(k)] = array(v, {T});
    out["energy_parts"] = p;
  }
  if (sc.output.centerline) out["centerline"] = array(centerline, {T, n, 3});
  if (sc.output.directors) out["directors"] = array(directors, {T, n, 3, 3});
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
  out["summary"] = summary;
  Scene as_run = sim.scene();  // solver.space/time as resolved from "auto"
  as_run.initial.path = sc.initial.path;
  out["scene"] = scene_to_toml(as_run);
  out["scales"] = py::dict(py::arg("tau_ps") = dna_units::tau_ps, py::arg("ell_A") = dna_units::ell_A,
                           py::arg("velocity_A_per_ps") = dna_units::velocity_A_per_ps);
  return out;
}

py::list kinds() {
  py::list out;
  for (const auto& k : initial_kinds()) {
    py::list numbers, strings;
    for (const auto& p : k.numbers)
      numbers.append(py::dict(py::arg("name") = p.name, py::arg("default") = p.default_value, py::arg("min") = p.min,
                              py::arg("max") = p.max, py::arg("unit") = p.unit, py::arg("doc") = p.doc));
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

}  // namespace

PYBIND11_MODULE(rodcore, m) {
  m.doc() =
      "rodcore: the geometrically exact elastic rod solver (paper Eqs 11-14) from Python.\n\n"
      "run(scene, initial=None, set=(), output=None) -> dict of numpy arrays\n"
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
                                          std::to_string(e.source().begin.line) + ": not valid TOML: " +
                                          std::string(e.description()))
                                             .c_str());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  m.def("run", &run, py::arg("scene"), py::arg("initial") = py::none(), py::arg("set") = std::vector<std::string>{},
        py::arg("output") = py::none(),
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
output.fields asks -- and summary, scene (resolved TOML), scales.
Raises rodcore.InputError (a ValueError) for bad input and
rodcore.NumericalError (a FloatingPointError) for bad numbers.
The GIL is released while integrating.)");

  m.def("kinds", &kinds, "Initial-condition kinds: list of dicts name, doc, numbers, strings.");
  m.def(
      "resolve",
      [](const py::object& scene, const std::vector<std::string>& sets) {
        std::optional<TempFile> tmp;
        return scene_to_toml(resolve(scene, py::none(), sets, tmp));
      },
      py::arg("scene"), py::arg("set") = std::vector<std::string>{},
      "Validate a scene and return it resolved (every key, defaults filled) as TOML text.");

  auto a = m.def_submodule("analytic", "Closed-form results of the paper (rodcore/include/rodcore/analytic.hpp).");
  a.def("dispersion", &analytic::dispersion, py::arg("kappa"), py::arg("D1"), py::arg("Gamma03"), py::arg("branch"),
        "Eq 26 / 39: frequency w of the bend-shear wave, branch +1 (w_+) or -1 (w_-).");
  a.def("energy_ratio", &analytic::energy_ratio, py::arg("w"), py::arg("kappa"), py::arg("D1"), py::arg("Gamma03"),
        "Eq 27: shear / bend energy ratio of the exact wave.");
  py::class_<analytic::TwistedWave>(a, "TwistedWave", "The exact twisted-rod wave (Eq 24, checked form).")
      .def(py::init<>())
      .def(py::init([](double A, double k, double Gamma03, double Omega03, double D1, std::string kappa_branch,
                       int omega_branch) {
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
  py::class_<analytic::UntwistedWave>(a, "UntwistedWave", "The asymptotic untwisted-rod wave (Eqs 40-45, corrected).")
      .def(py::init<>())
      .def(py::init([](double eps, double k, double Gamma03, double D1, double C3, int omega_branch) {
             analytic::UntwistedWave w;
             w.eps = eps, w.k = k, w.Gamma03 = Gamma03, w.D1 = D1, w.C3 = C3, w.omega_branch = omega_branch;
             return w;
           }),
           py::arg("eps") = 0.1, py::arg("k") = 2.0, py::arg("Gamma03") = 1.0, py::arg("D1") = dna_units::D_star[0],
           py::arg("C3") = dna_units::C_star[2], py::arg("omega_branch") = 1)
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
