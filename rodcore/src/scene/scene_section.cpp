// The typed getters of one scene [section] (scene_section.hpp).
#include "rodcore/scene_section.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "rodcore/did_you_mean.hpp"
#include "rodcore/error.hpp"

namespace fs = std::filesystem;

namespace rodcore {

namespace {
const double kInf = std::numeric_limits<double>::infinity();
}  // namespace

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

std::string join(const std::vector<std::string>& v, const std::string& sep, bool quote) {
  std::string out;
  for (std::size_t k = 0; k < v.size(); ++k) out += (k ? sep : "") + (quote ? "\"" + v[k] + "\"" : v[k]);
  return out;
}

std::string describe(const toml::node& n) {
  if (auto v = n.as_string()) return "the string \"" + v->get() + "\"";
  if (auto v = n.as_integer()) return "the integer " + std::to_string(v->get());
  if (auto v = n.as_floating_point()) return "the number " + fmt_num(v->get());
  if (auto v = n.as_boolean()) return std::string("the boolean ") + (v->get() ? "true" : "false");
  if (auto v = n.as_array()) return "an array of " + std::to_string(v->size()) + " value(s)";
  if (n.is_table()) return "a table";
  return "a date/time";
}

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  if (min_open ? !(v > min) : !(v >= min)) return false;
  if (max_open ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string Range::text(const std::string& what) const {
  std::string t = what;
  bool lo = std::isfinite(min), hi = std::isfinite(max);
  if (lo) t += std::string(min_open ? " > " : " >= ") + fmt_num(min);
  if (lo && hi) t += " and";
  if (hi) t += std::string(max_open ? " < " : " <= ") + fmt_num(max);
  if (!lo && !hi) t += " (finite" + std::string(max == kInf && !max_open ? " or inf" : "") + ")";
  return t;
}

Range positive() { return {0.0, kInf, true, false}; }

std::string Context::where(const std::string& key, const toml::node* n) const {
  if (overridden.count(key)) return source + ": --set " + key;
  std::string w = source;
  if (n && n->source().begin.line > 0) w += ":" + std::to_string(n->source().begin.line);
  return w + ": " + key;
}

void Context::fail(const std::string& key, const toml::node* n, const std::string& msg) const {
  throw InputError(where(key, n) + ": " + msg);
}

const toml::node* Section::get(const std::string& k) {
  known_.push_back(k);
  return tab_ ? tab_->get(k) : nullptr;
}

double Section::number_of(const std::string& k, const toml::node& n, const Range& r,
                          const std::string& what) const {
  double v;
  if (auto i = n.as_integer()) v = static_cast<double>(i->get());
  else if (auto f = n.as_floating_point()) v = f->get();
  else fail(k, &n, "found " + describe(n) + "; allowed: " + r.text(what));
  if (std::isnan(v)) fail(k, &n, "found nan; allowed: " + r.text(what));
  if (!r.contains(v)) fail(k, &n, "found " + fmt_num(v) + "; allowed: " + r.text(what));
  return v;
}

void Section::number(const std::string& k, double& dst, const Range& r) {
  if (auto n = get(k)) dst = number_of(k, *n, r, "a number");
}

void Section::boolean(const std::string& k, bool& dst) {
  if (auto n = get(k)) {
    auto b = n->as_boolean();
    if (!b) fail(k, n, "found " + describe(*n) + "; allowed: true or false");
    dst = b->get();
  }
}

std::string Section::string_of(const std::string& k, const toml::node& n,
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

Vec3 Section::vec3_of(const std::string& k, const toml::node& n, const Range& r) const {
  auto a = n.as_array();
  if (!a || a->size() != 3)
    fail(k, &n, "found " + describe(n) + "; allowed: an array of 3 numbers [x1, x2, x3], each " + r.text(""));
  Vec3 v;
  for (int c = 0; c < 3; ++c) v[c] = number_of(k + "[" + std::to_string(c) + "]", *a->get(c), r, "a number");
  return v;
}

void Section::vec3(const std::string& k, Vec3& dst, const Range& r) {
  if (auto n = get(k)) dst = vec3_of(k, *n, r);
}

void Section::shape(const std::string& k, Vec3& uniform, std::vector<double>& profile) {
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

std::vector<double> Section::matrix_of(const std::string& k, const toml::node& node, int n,
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

std::string Section::path(const std::string& k, const std::string& what) {
  auto n = get(k);
  if (!n) return {};
  std::string p = string_of(k, *n, {});
  fs::path full = fs::path(p).is_absolute() ? fs::path(p) : ctx_->base_dir / p;
  full = full.lexically_normal();
  // the non-throwing overload: a name the OS cannot look up (too long, found by
  // fuzz/scene_reader_fuzz.cpp) is bad input like a missing file, not a crash
  std::error_code ec;
  if (!fs::exists(full, ec))
    fail(k, n,
         what + " '" + full.string() + "' does not exist" + (ec ? " (" + ec.message() + ")" : "") +
             (fs::path(p).is_absolute() ? "" : " (relative paths are relative to the scene file's folder)"));
  return fs::absolute(full).string();
}

std::vector<std::string> Section::belonging() const {
  std::vector<std::string> all = known_;
  for (const auto& r : refused_) all.push_back(r.first);
  return all;
}

void Section::reject_unknown(const std::map<std::string, std::vector<std::string>>& all_known) const {
  if (!tab_) return;
  for (const auto& [k, reason] : refused_)
    if (has(k)) fail(k, node(k), reason);
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
  // Appended, not "[" + ...: GCC 12 warns (-Wrestrict, falsely) on that form here.
  std::string o = "[";
  for (int c = 0; c < 3; ++c) o.append(c ? ", " : "").append(toml_num(v[c]));
  return o + "]";
}

std::string toml_profile(const std::vector<double>& p, int N) {
  std::string o = "[\n";
  for (int i = 0; i < N; ++i) o += "  " + toml_vec({p[0 * N + i], p[1 * N + i], p[2 * N + i]}) + ",\n";
  return o + "]";
}

std::string toml_matrix(const std::vector<double>& A, int n) {
  std::string t = "[";
  for (int r = 0; r < n; ++r) {
    t += r ? ", [" : "[";
    for (int c = 0; c < n; ++c) t += (c ? ", " : "") + toml_num(A[r * n + c]);
    t += "]";
  }
  return t + "]";
}

}  // namespace rodcore
