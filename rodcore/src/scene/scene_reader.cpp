// TOML scene -> validated Scene. The reader is strict on purpose: a scene key
// that is misspelt and silently ignored would run a different experiment than
// the one the user wrote down.
#include "rodcore/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "rodcore/error.hpp"
#include "rodcore/h5_initial.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/material.hpp"

namespace fs = std::filesystem;

namespace rodcore {

int edit_distance(const std::string& a, const std::string& b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                  std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = std::numeric_limits<int>::max();
  for (const auto& c : candidates) {
    int d = edit_distance(word, c);
    if (d < best_d) best_d = d, best = c;
  }
  // Plausible misspelling: a couple of edits, or a third of the word.
  int limit = std::max(2, static_cast<int>(word.size()) / 3);
  return best_d <= limit ? best : std::string();
}

namespace {

const double kInf = std::numeric_limits<double>::infinity();

std::string fmt_num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream o;
  o.precision(17);
  o << v;
  std::string s = o.str();
  // Whole numbers as integers, else the shortest text that reads back to the
  // same double, so messages stay short.
  if (v == std::floor(v) && std::abs(v) < 1e15) {
    std::ostringstream q;
    q << std::fixed;
    q.precision(0);
    q << v;
    return q.str();
  }
  for (int p = 1; p <= 17; ++p) {
    std::ostringstream q;
    q.precision(p);
    q << v;
    // strtod, not stod: stod throws out_of_range on subnormals such as 1e-320
    // (found by fuzz/scene_reader_fuzz.cpp).
    if (std::strtod(q.str().c_str(), nullptr) == v) return q.str();
  }
  return s;
}

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ", bool quote = true) {
  std::string out;
  for (std::size_t k = 0; k < v.size(); ++k) out += (k ? sep : "") + (quote ? "\"" + v[k] + "\"" : v[k]);
  return out;
}

// What the user wrote, in words, for messages.
std::string describe(const toml::node& n) {
  if (auto v = n.as_string()) return "the string \"" + v->get() + "\"";
  if (auto v = n.as_integer()) return "the integer " + std::to_string(v->get());
  if (auto v = n.as_floating_point()) return "the number " + fmt_num(v->get());
  if (auto v = n.as_boolean()) return std::string("the boolean ") + (v->get() ? "true" : "false");
  if (auto v = n.as_array()) return "an array of " + std::to_string(v->size()) + " value(s)";
  if (n.is_table()) return "a table";
  return "a date/time";
}

// Allowed interval of a number, and its wording ("a number > 0 and <= 1").
struct Range {
  double min = -kInf, max = kInf;
  bool min_open = false, max_open = false;
  bool contains(double v) const {
    if (std::isnan(v)) return false;
    if (min_open ? !(v > min) : !(v >= min)) return false;
    if (max_open ? !(v < max) : !(v <= max)) return false;
    return true;
  }
  std::string text(const std::string& what = "a number") const {
    std::string t = what;
    bool lo = std::isfinite(min), hi = std::isfinite(max);
    if (lo) t += std::string(min_open ? " > " : " >= ") + fmt_num(min);
    if (lo && hi) t += " and";
    if (hi) t += std::string(max_open ? " < " : " <= ") + fmt_num(max);
    if (!lo && !hi) t += " (finite" + std::string(max == kInf && !max_open ? " or inf" : "") + ")";
    return t;
  }
};
Range positive() { return {0.0, kInf, true, false}; }

const std::vector<std::string> kSections = {"rod", "material", "initial", "solver", "output", "checks"};
const std::vector<std::string> kOutputFields = {"internal", "energy", "energy_parts", "centerline",
                                                "directors"};

// Where a key came from and how to say so.
struct Context {
  std::string source;
  fs::path base_dir;
  std::set<std::string> overridden;  // dotted keys set by --set

  std::string where(const std::string& key, const toml::node* n) const {
    if (overridden.count(key)) return source + ": --set " + key;
    std::string w = source;
    if (n && n->source().begin.line > 0) w += ":" + std::to_string(n->source().begin.line);
    return w + ": " + key;
  }
  [[noreturn]] void fail(const std::string& key, const toml::node* n, const std::string& msg) const {
    throw InputError(where(key, n) + ": " + msg);
  }
};

// One [section]: typed getters that validate and remember which keys are
// known, so that anything left over is reported as unknown.
class Section {
 public:
  Section(const Context& ctx, std::string name, const toml::table* tab)
      : ctx_(ctx), name_(std::move(name)), tab_(tab) {}

  std::string key(const std::string& k) const { return name_ + "." + k; }
  const toml::node* get(const std::string& k) {
    known_.push_back(k);
    return tab_ ? tab_->get(k) : nullptr;
  }
  bool has(const std::string& k) const { return tab_ && tab_->contains(k); }
  [[noreturn]] void fail(const std::string& k, const toml::node* n, const std::string& msg) const {
    ctx_.fail(key(k), n, msg);
  }

  // A number from an integer or float node, checked against `r`.
  double number_of(const std::string& k, const toml::node& n, const Range& r, const std::string& what) const {
    double v;
    if (auto i = n.as_integer()) v = static_cast<double>(i->get());
    else if (auto f = n.as_floating_point()) v = f->get();
    else fail(k, &n, "found " + describe(n) + "; allowed: " + r.text(what));
    if (std::isnan(v)) fail(k, &n, "found nan; allowed: " + r.text(what));
    if (!r.contains(v)) fail(k, &n, "found " + fmt_num(v) + "; allowed: " + r.text(what));
    return v;
  }

  void number(const std::string& k, double& dst, const Range& r) {
    if (auto n = get(k)) dst = number_of(k, *n, r, "a number");
  }

  template <class Int>
  void integer(const std::string& k, Int& dst, const Range& r) {
    if (auto n = get(k)) {
      auto i = n->as_integer();
      if (!i) fail(k, n, "found " + describe(*n) + "; allowed: " + r.text("an integer"));
      double v = static_cast<double>(i->get());
      if (!r.contains(v))
        fail(k, n, "found " + std::to_string(i->get()) + "; allowed: " + r.text("an integer"));
      dst = static_cast<Int>(i->get());
    }
  }

  void boolean(const std::string& k, bool& dst) {
    if (auto n = get(k)) {
      auto b = n->as_boolean();
      if (!b) fail(k, n, "found " + describe(*n) + "; allowed: true or false");
      dst = b->get();
    }
  }

  std::string string_of(const std::string& k, const toml::node& n,
                        const std::vector<std::string>& allowed) const {
    auto s = n.as_string();
    std::string allowed_text = allowed.empty() ? "a string" : "one of " + join(allowed);
    if (!s) fail(k, &n, "found " + describe(n) + "; allowed: " + allowed_text);
    std::string v = s->get();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
      std::string hint = closest_match(v, allowed);
      fail(k, &n,
           "found \"" + v + "\"; allowed: " + allowed_text +
               (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
    }
    return v;
  }

  void choice(const std::string& k, std::string& dst, const std::vector<std::string>& allowed) {
    if (auto n = get(k)) dst = string_of(k, *n, allowed);
  }

  Vec3 vec3_of(const std::string& k, const toml::node& n, const Range& r) const {
    auto a = n.as_array();
    if (!a || a->size() != 3)
      fail(k, &n,
           "found " + describe(n) + "; allowed: an array of 3 numbers [x1, x2, x3], each " + r.text(""));
    Vec3 v;
    for (int c = 0; c < 3; ++c)
      v[c] = number_of(k + "[" + std::to_string(c) + "]", *a->get(c), r, "a number");
    return v;
  }

  void vec3(const std::string& k, Vec3& dst, const Range& r) {
    if (auto n = get(k)) dst = vec3_of(k, *n, r);
  }

  // Gamma0 / Omega0: 3 numbers (uniform) or an array of N triples (a profile
  // along s, component-major into `profile`).
  void shape(const std::string& k, Vec3& uniform, std::vector<double>& profile) {
    auto n = get(k);
    if (!n) return;
    auto a = n->as_array();
    if (a && !a->empty() && a->get(0)->is_array()) {
      std::size_t N = a->size();
      profile.assign(3 * N, 0.0);
      for (std::size_t i = 0; i < N; ++i) {
        Vec3 v = vec3_of(k + "[" + std::to_string(i) + "]", *a->get(i), Range{});
        for (int c = 0; c < 3; ++c) profile[c * N + i] = v[c];
      }
      return;
    }
    if (!a || a->size() != 3)
      fail(k, n,
           "found " + describe(*n) +
               "; allowed: an array of 3 numbers (uniform), or an array of rod.points arrays of 3 "
               "numbers (varying along s)");
    uniform = vec3_of(k, *n, Range{});
  }

  // An n x n matrix written as n arrays of n numbers, row-major into `out`.
  std::vector<double> matrix_of(const std::string& k, const toml::node& node, int n,
                                const std::string& allowed) const {
    auto a = node.as_array();
    const std::string dim = std::to_string(n) + " x " + std::to_string(n);
    if (!a || a->size() != static_cast<std::size_t>(n))
      fail(k, &node, "found " + describe(node) + "; allowed: " + allowed);
    std::vector<double> out(static_cast<std::size_t>(n * n));
    for (int r = 0; r < n; ++r) {
      auto row = a->get(r)->as_array();
      if (!row || row->size() != static_cast<std::size_t>(n))
        fail(k + "[" + std::to_string(r) + "]", a->get(r),
             "found " + describe(*a->get(r)) + "; allowed: an array of " + std::to_string(n) +
                 " numbers (row " + std::to_string(r) + " of a " + dim + " matrix)");
      for (int c = 0; c < n; ++c)
        out[r * n + c] = number_of(k + "[" + std::to_string(r) + "][" + std::to_string(c) + "]", *row->get(c),
                                   Range{}, "a finite number");
    }
    return out;
  }

  std::string path(const std::string& k, const std::string& what) {
    auto n = get(k);
    if (!n) return {};
    std::string p = string_of(k, *n, {});
    fs::path full = fs::path(p).is_absolute() ? fs::path(p) : ctx_.base_dir / p;
    full = full.lexically_normal();
    if (!fs::exists(full))
      fail(
          k, n,
          what + " '" + full.string() + "' does not exist" +
              (fs::path(p).is_absolute() ? "" : " (relative paths are relative to the scene file's folder)"));
    return fs::absolute(full).string();
  }

  // Keys present but never asked for are unknown: say which, and suggest.
  void reject_unknown(const std::map<std::string, std::vector<std::string>>& all_known) const {
    if (!tab_) return;
    for (const auto& [k, n] : *tab_) {
      std::string kk(k.str());
      if (std::find(known_.begin(), known_.end(), kk) != known_.end()) continue;
      std::string msg = "unknown key in [" + name_ + "]";
      std::string hint = closest_match(kk, known_);
      if (!hint.empty()) {
        msg += "; did you mean " + key(hint) + "?";
      } else {
        for (const auto& [sec, keys] : all_known)
          if (sec != name_ && std::find(keys.begin(), keys.end(), kk) != keys.end())
            msg += "; " + kk + " belongs in [" + sec + "]";
      }
      msg += " Allowed keys: " + join(known_, ", ", false);
      fail(kk, &n, msg);
    }
  }

  const std::vector<std::string>& known() const { return known_; }
  const std::string& name() const { return name_; }

 private:
  const Context& ctx_;
  std::string name_;
  const toml::table* tab_;
  std::vector<std::string> known_;
};

// --set section.key=value into the table.
void apply_overrides(toml::table& table, const std::vector<std::string>& overrides, Context& ctx) {
  for (const auto& o : overrides) {
    auto eq = o.find('=');
    std::string key = o.substr(0, eq);
    auto dot = key.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == key.size())
      throw InputError(ctx.source + ": --set '" + o +
                       "': expected section.key=value, e.g. --set solver.rtol=1e-8");
    std::string sec = key.substr(0, dot), k = key.substr(dot + 1);
    std::string value = o.substr(eq + 1);
    if (std::find(kSections.begin(), kSections.end(), sec) == kSections.end()) {
      std::string hint = closest_match(sec, kSections);
      throw InputError(ctx.source + ": --set " + key + ": unknown section [" + sec + "]" +
                       (hint.empty() ? "" : "; did you mean [" + hint + "]?") +
                       " Allowed sections: " + join(kSections, ", ", false));
    }
    toml::table parsed;
    try {
      parsed = toml::parse("v = " + value);
    } catch (const toml::parse_error&) {
      parsed.insert_or_assign("v", value);  // a bare word: take it as a string
    }
    if (!table.contains(sec)) table.insert(sec, toml::table{});
    auto* t = table.get(sec)->as_table();
    if (!t) throw InputError(ctx.source + ": [" + sec + "] is not a table");
    t->insert_or_assign(k, *parsed.get("v"));
    ctx.overridden.insert(key);
  }
}

int min_points(const std::string& space) { return space == "fd4" ? 5 : 4; }  // auto: spectral below 5

Scene build_scene(toml::table& table, Context& ctx) {
  Scene sc;
  sc.source = ctx.source;

  for (const auto& [k, n] : table) {
    std::string kk(k.str());
    if (std::find(kSections.begin(), kSections.end(), kk) == kSections.end()) {
      std::string hint = closest_match(kk, kSections);
      ctx.fail(kk, &n,
               "unknown section" + (hint.empty() ? std::string() : "; did you mean [" + hint + "]?") +
                   " Allowed sections: " + join(kSections, ", ", false));
    }
    if (!n.is_table()) ctx.fail(kk, &n, "found " + describe(n) + "; expected a table [" + kk + "]");
  }
  auto section = [&](const std::string& name) { return Section(ctx, name, table[name].as_table()); };

  // [rod]
  Section rod = section("rod");
  // Keys the scene gives explicitly, by bare name: a kind's derive_rod fills
  // only the others and checks these for consistency.
  std::set<std::string> set_keys;
  for (const char* k : {"length", "points", "Gamma0", "Omega0"})
    if (rod.has(k)) set_keys.insert(k);
  if (rod.has("intrinsic_file")) set_keys.insert({"Gamma0", "Omega0"});
  rod.number("length", sc.rod.length, positive());
  rod.integer("points", sc.rod.points, Range{1, 1e8});
  rod.shape("Gamma0", sc.rod.Gamma0, sc.rod.Gamma0_s);
  rod.shape("Omega0", sc.rod.Omega0, sc.rod.Omega0_s);
  std::string intrinsic_file = rod.path("intrinsic_file", "intrinsic-shape file");
  if (!intrinsic_file.empty() && (rod.has("Gamma0") || rod.has("Omega0")))
    rod.fail("intrinsic_file", rod.get("intrinsic_file"),
             "give either rod.intrinsic_file or rod.Gamma0/rod.Omega0, not both");

  // [material]: the paper's diagonals C, D, I, or a full K (6 x 6) and I
  // (3 x 3), and rho; or a per-point material file (material.hpp).
  Section mat = section("material");
  for (const char* k : {"C", "D", "I", "K", "rho", "material_file"})
    if (mat.has(k)) set_keys.insert(k);
  for (const char* k : {"C", "D"})
    if (mat.has(k) && mat.has("K"))
      mat.fail(k, mat.get(k),
               "give either material.K (the full 6 x 6 stiffness) or material.C/material.D (its "
               "diagonal shorthand), not both");
  mat.vec3("C", sc.material.C, positive());
  mat.vec3("D", sc.material.D, positive());
  if (auto n = mat.get("K")) {
    sc.material.K =
        mat.matrix_of("K", *n, 6,
                      "a symmetric positive-definite 6 x 6 matrix (6 arrays of 6 numbers), rows and "
                      "columns Gamma1, Gamma2, Gamma3, Omega1, Omega2, Omega3");
    check_stiffness(sc.material.K.data(), ctx.where(mat.key("K"), n));
  }
  if (auto n = mat.get("I")) {
    auto a = n->as_array();
    if (a && !a->empty() && a->get(0)->is_array()) {
      sc.material.I_full = mat.matrix_of("I", *n, 3,
                                         "3 numbers > 0 (a diagonal I) or a symmetric positive-definite "
                                         "3 x 3 matrix (3 arrays of 3 numbers)");
      check_inertia(sc.material.I_full.data(), ctx.where(mat.key("I"), n));
    } else {
      sc.material.I = mat.vec3_of("I", *n, positive());
    }
  }
  mat.number("rho", sc.material.rho, positive());
  std::string material_file = mat.path("material_file", "material file");
  if (!material_file.empty())
    for (const char* k : {"C", "D", "I", "K", "rho"})
      if (mat.has(k))
        mat.fail(k, mat.get(k),
                 "give either material.material_file (K, I, rho at every grid point) or "
                 "material." +
                     std::string(k) + ", not both");
  // A diagonal K or I is the paper's shorthand: store it as C, D / I, so
  // everything that reads C, D, I (the analytic kinds, records) sees it.
  auto off_diagonal_zero = [](const std::vector<double>& A, int n) {
    for (int k = 0; k < n * n; ++k)
      if (k / n != k % n && A[k] != 0.0) return false;
    return true;
  };
  if (sc.material.K.size() == 36 && off_diagonal_zero(sc.material.K, 6)) {
    for (int c = 0; c < 3; ++c) {
      sc.material.C[c] = sc.material.K[c * 7];
      sc.material.D[c] = sc.material.K[(c + 3) * 7];
    }
    sc.material.K.clear();
  }
  if (sc.material.I_full.size() == 9 && off_diagonal_zero(sc.material.I_full, 3)) {
    for (int c = 0; c < 3; ++c) sc.material.I[c] = sc.material.I_full[c * 4];
    sc.material.I_full.clear();
  }

  // [solver]
  Section sol = section("solver");
  sol.choice("space", sc.solver.space, {"auto", "fd4", "spectral"});
  sol.boolean("dealias", sc.solver.dealias);
  sol.choice("time", sc.solver.time, {"auto", "rk4", "rk4-doubling", "dopri5", "dop853"});
  sol.number("rtol", sc.solver.rtol, {0.0, 1.0, true, true});
  sol.number("atol", sc.solver.atol, positive());
  sol.number("dt", sc.solver.dt, positive());
  sol.number("dt_min", sc.solver.dt_min, positive());
  sol.integer("max_steps", sc.solver.max_steps, Range{1, 9e18});
  sol.choice("reduce", sc.solver.reduce, {"auto", "off"});
  if (sc.solver.dealias && sc.solver.space != "spectral" && sc.solver.space != "auto")
    sol.fail("dealias", sol.get("dealias"),
             "applies only to solver.space = \"spectral\" (found \"" + sc.solver.space + "\")");
  if (sc.solver.dt_min > sc.solver.dt)
    sol.fail("dt_min", sol.get("dt_min"),
             "found " + fmt_num(sc.solver.dt_min) + "; must not exceed solver.dt = " + fmt_num(sc.solver.dt));

  // [output]
  Section out = section("output");
  out.number("t_end", sc.output.t_end, positive());
  out.integer("frames", sc.output.frames, Range{2, 1e8});
  if (auto n = out.get("fields")) {
    auto a = n->as_array();
    if (!a)
      out.fail("fields", n,
               "found " + describe(*n) + "; allowed: an array of strings from " + join(kOutputFields));
    sc.output.internal = sc.output.energy = sc.output.energy_parts = false;
    sc.output.centerline = sc.output.directors = false;
    for (std::size_t i = 0; i < a->size(); ++i) {
      std::string f = out.string_of("fields[" + std::to_string(i) + "]", *a->get(i), kOutputFields);
      if (f == "internal") sc.output.internal = true;
      if (f == "energy") sc.output.energy = true;
      if (f == "energy_parts") sc.output.energy_parts = true;
      if (f == "centerline") sc.output.centerline = true;
      if (f == "directors") sc.output.directors = true;
    }
  }
  out.number("checkpoint_interval_s", sc.output.checkpoint_interval_s, Range{0.0, kInf, false, false});

  // [checks]
  Section chk = section("checks");
  chk.number("max_energy_drift", sc.checks.max_energy_drift, positive());
  chk.number("max_director_norm_error", sc.checks.max_director_norm_error, positive());
  chk.boolean("stop_on_fold", sc.checks.stop_on_fold);

  // [initial]: the kind declares its own parameters (initial_conditions.hpp).
  Section ini = section("initial");
  std::vector<std::string> kind_names;
  for (const auto& k : initial_kinds()) kind_names.push_back(k.name);
  ini.choice("kind", sc.initial.kind, kind_names);
  const InitialKind& kind = initial_kind(sc.initial.kind);
  for (const auto& p : kind.numbers) {
    Range r{p.min, p.max, false, false};
    std::string what = "a number" + (p.unit.empty() ? std::string() : " [" + p.unit + "]");
    if (auto n = ini.get(p.name)) {
      sc.initial.numbers[p.name] = ini.number_of(p.name, *n, r, what);
    } else if (std::isnan(p.default_value)) {
      ini.fail(
          p.name, nullptr,
          "is required for initial.kind = \"" + kind.name + "\" (" + p.doc + "); allowed: " + r.text(what));
    } else {
      sc.initial.numbers[p.name] = p.default_value;
    }
  }
  for (const auto& c : kind.strings) {
    if (auto n = ini.get(c.name)) sc.initial.strings[c.name] = ini.string_of(c.name, *n, c.allowed);
    else sc.initial.strings[c.name] = c.default_value;
  }
  if (sc.initial.kind == "file") {
    if (!ini.has("path"))
      ini.fail("path", nullptr,
               "is required for initial.kind = \"file\": the HDF5 file with s and "
               "fields/{gamma,omega,Gamma,Omega}");
    sc.initial.path = ini.path("path", "initial-condition file");
  }

  // Unknown keys anywhere, now that every section has said what it knows.
  std::map<std::string, std::vector<std::string>> all_known;
  for (const Section* s : {&rod, &mat, &sol, &out, &chk, &ini}) all_known[s->name()] = s->known();
  if (sc.initial.kind != "file") all_known["initial"].push_back("path");
  for (const Section* s : {&rod, &mat, &sol, &out, &chk, &ini}) {
    if (s == &ini && sc.initial.kind != "file" && ini.has("path"))
      ini.fail("path", table["initial"]["path"].node(),
               "is only used by initial.kind = \"file\" (this scene has kind \"" + sc.initial.kind + "\")");
    s->reject_unknown(all_known);
  }

  // The kind may set rod values it implies (e.g. dna_planar: L, Omega0).
  if (kind.derive_rod) {
    try {
      kind.derive_rod(sc.initial, sc.rod, sc.material, set_keys);
    } catch (const InputError& e) {
      throw InputError(ctx.source + ": initial.kind = \"" + kind.name + "\": " + e.what());
    }
  }

  // Cross-checks that need the final rod.
  if (!(sc.rod.length > 0.0))
    rod.fail("length", nullptr, "is required: the fiducial length L > 0 (dimensionless)");
  if (sc.rod.points <= 0) rod.fail("points", nullptr, "is required: the number of grid points N");
  int nmin = min_points(sc.solver.space);
  if (sc.rod.points < nmin)
    rod.fail("points", table["rod"]["points"].node(),
             "found " + std::to_string(sc.rod.points) + "; solver.space = \"" +
                 (sc.solver.space == "fd4" ? "fd4" : "spectral") + "\" needs at least " +
                 std::to_string(nmin) + " points (fd4: 5, its stencil spans 5 points; spectral: 4)");
  const auto N3 = 3 * static_cast<std::size_t>(sc.rod.points);
  for (auto [k, prof] : {std::pair{"Gamma0", &sc.rod.Gamma0_s}, std::pair{"Omega0", &sc.rod.Omega0_s}}) {
    if (!prof->empty() && prof->size() != N3)
      rod.fail(k, table["rod"][k].node(),
               "has " + std::to_string(prof->size() / 3) + " points; a profile along s needs rod.points = " +
                   std::to_string(sc.rod.points) + " triples");
  }
  if (!intrinsic_file.empty()) {
    try {
      read_intrinsic_shape(intrinsic_file, sc.rod.points, sc.rod.Gamma0_s, sc.rod.Omega0_s);
    } catch (const InputError& e) {
      rod.fail("intrinsic_file", table["rod"]["intrinsic_file"].node(), e.what());
    }
  }
  if (!material_file.empty()) {
    std::vector<double> G0, O0;
    try {
      read_material_file(material_file, sc.rod.points, sc.material, G0, O0);
    } catch (const InputError& e) {
      mat.fail("material_file", table["material"]["material_file"].node(), e.what());
    }
    if (!G0.empty() || !O0.empty()) {
      for (const char* k : {"Gamma0", "Omega0", "intrinsic_file"})
        if (rod.has(k))
          rod.fail(k, table["rod"][k].node(),
                   "the material file '" + material_file +
                       "' holds the intrinsic shape (datasets Gamma0, Omega0): give it "
                       "there or in [rod], not both");
      if (!G0.empty()) sc.rod.Gamma0_s = std::move(G0);
      if (!O0.empty()) sc.rod.Omega0_s = std::move(O0);
      sc.material.file_has_shape = true;
    }
  }
  if (sc.initial.kind == "file") {
    // Read it once now so that a bad file is reported as a scene problem.
    std::vector<double> s(sc.rod.points), y;
    for (int i = 0; i < sc.rod.points; ++i) s[i] = i * sc.rod.length / sc.rod.points;
    try {
      read_initial_fields(sc.initial.path, s, y);
    } catch (const InputError& e) {
      ini.fail("path", table["initial"]["path"].node(), e.what());
    }
  }
  return sc;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("scene file '" + path + "' cannot be read (does it exist?)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

toml::table parse(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(source + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) +
                     ": not valid TOML: " + std::string(e.description()));
  }
}

// TOML text of values, written by hand so doubles keep all 17 digits.
std::string toml_str(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\', o += c;
    else if (c == '\n') o += "\\n";
    else if (c == '\t') o += "\\t";
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
    } else o += c;
  }
  return o + "\"";
}
std::string toml_num(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::string s = fmt_num(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}
std::string toml_vec(const Vec3& v) {
  return "[" + toml_num(v[0]) + ", " + toml_num(v[1]) + ", " + toml_num(v[2]) + "]";
}
std::string toml_profile(const std::vector<double>& p, int N) {
  std::string o = "[\n";
  for (int i = 0; i < N; ++i) o += "  " + toml_vec({p[0 * N + i], p[1 * N + i], p[2 * N + i]}) + ",\n";
  return o + "]";
}

}  // namespace

Scene read_scene_table(toml::table table, const std::string& source, const std::string& base_dir,
                       const std::vector<std::string>& overrides) {
  Context ctx{source, fs::path(base_dir), {}};
  apply_overrides(table, overrides, ctx);
  return build_scene(table, ctx);
}

Scene read_scene_string(const std::string& text, const std::string& source, const std::string& base_dir,
                        const std::vector<std::string>& overrides) {
  return read_scene_table(parse(text, source), source, base_dir, overrides);
}

Scene read_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::string text = read_text(path);
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  return read_scene_table(parse(text, path), path, dir.string(), overrides);
}

std::string scene_to_toml(const Scene& sc) {
  std::ostringstream o;
  const Rod& r = sc.rod;
  o << "# Resolved scene (every key, defaults filled) from " << sc.source << "\n";
  o << "[rod]\nlength = " << toml_num(r.length) << "\npoints = " << r.points << "\n";
  const Material& m = sc.material;
  if (m.file_has_shape) {
    o << "# Gamma0, Omega0: from material.material_file\n";
  } else {
    o << "Gamma0 = " << (r.Gamma0_s.empty() ? toml_vec(r.Gamma0) : toml_profile(r.Gamma0_s, r.points))
      << "\n";
    o << "Omega0 = " << (r.Omega0_s.empty() ? toml_vec(r.Omega0) : toml_profile(r.Omega0_s, r.points))
      << "\n";
  }
  auto matrix = [](const std::vector<double>& A, int n) {
    std::string t = "[";
    for (int r = 0; r < n; ++r) {
      t += r ? ", [" : "[";
      for (int c = 0; c < n; ++c) t += (c ? ", " : "") + toml_num(A[r * n + c]);
      t += "]";
    }
    return t + "]";
  };
  o << "\n[material]\n";
  if (!m.file.empty()) {
    o << "material_file = " << toml_str(m.file) << "\n";
  } else {
    if (m.K.empty()) o << "C = " << toml_vec(m.C) << "\nD = " << toml_vec(m.D) << "\n";
    else o << "K = " << matrix(m.K, 6) << "\n";
    o << "I = " << (m.I_full.empty() ? toml_vec(m.I) : matrix(m.I_full, 3)) << "\nrho = " << toml_num(m.rho)
      << "\n";
  }
  o << "\n[initial]\nkind = " << toml_str(sc.initial.kind) << "\n";
  for (const auto& [k, v] : sc.initial.numbers) o << k << " = " << toml_num(v) << "\n";
  for (const auto& [k, v] : sc.initial.strings) o << k << " = " << toml_str(v) << "\n";
  if (!sc.initial.path.empty()) o << "path = " << toml_str(sc.initial.path) << "\n";
  const SolverOptions& s = sc.solver;
  o << "\n[solver]\nspace = " << toml_str(s.space) << "\ndealias = " << (s.dealias ? "true" : "false")
    << "\ntime = " << toml_str(s.time) << "\nrtol = " << toml_num(s.rtol) << "\natol = " << toml_num(s.atol)
    << "\ndt = " << toml_num(s.dt) << "\ndt_min = " << toml_num(s.dt_min) << "\nmax_steps = " << s.max_steps
    << "\nreduce = " << toml_str(s.reduce) << "\n";
  const OutputOptions& out = sc.output;
  std::vector<std::string> fields;
  if (out.internal) fields.push_back("internal");
  if (out.energy) fields.push_back("energy");
  if (out.energy_parts) fields.push_back("energy_parts");
  if (out.centerline) fields.push_back("centerline");
  if (out.directors) fields.push_back("directors");
  o << "\n[output]\nt_end = " << toml_num(out.t_end) << "\nframes = " << out.frames << "\nfields = ["
    << join(fields) << "]\ncheckpoint_interval_s = " << toml_num(out.checkpoint_interval_s) << "\n";
  o << "\n[checks]\nmax_energy_drift = " << toml_num(sc.checks.max_energy_drift)
    << "\nmax_director_norm_error = " << toml_num(sc.checks.max_director_norm_error)
    << "\nstop_on_fold = " << (sc.checks.stop_on_fold ? "true" : "false") << "\n";
  return o.str();
}

}  // namespace rodcore
