// Reading one [section] of a scene: typed getters that validate each key and
// say what was found and what is allowed, naming the file, line and dotted
// key; the keys asked for are the section's known keys, and anything left
// over is reported as unknown with a "did you mean". Internal to the scene
// reader (scene_reader.cpp, scene_sections.cpp); the messages are the
// reader's contract (docs/scenes.md, tests/cpp/test_io_scene_reader.cpp).
#pragma once
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "rodcore/scene.hpp"

namespace rodcore {

// A number in messages and in resolved TOML: whole numbers as integers, else
// the shortest text that reads back to the same double.
std::string fmt_num(double v);

// "a", "b" (quoted) or a, b.
std::string join(const std::vector<std::string>& v, const std::string& sep = ", ", bool quote = true);

// What the user wrote, in words ("the string \"x\"", "an array of 2 value(s)").
std::string describe(const toml::node& n);

// Allowed interval of a number, and its wording ("a number > 0 and <= 1").
struct Range {
  double min = -std::numeric_limits<double>::infinity(), max = std::numeric_limits<double>::infinity();
  bool min_open = false, max_open = false;
  bool contains(double v) const;
  std::string text(const std::string& what = "a number") const;
};
Range positive();  // > 0

// Where a key came from and how to say so.
struct Context {
  std::string source;
  std::filesystem::path base_dir;
  std::set<std::string> overridden;  // dotted keys set by --set

  std::string where(const std::string& key, const toml::node* n) const;
  [[noreturn]] void fail(const std::string& key, const toml::node* n, const std::string& msg) const;
};

class Section {
 public:
  Section(const Context& ctx, std::string name, const toml::table* tab)
      : ctx_(&ctx), name_(std::move(name)), tab_(tab) {}

  std::string key(const std::string& k) const { return name_ + "." + k; }
  // The node of key k (or nullptr), now known.
  const toml::node* get(const std::string& k);
  // The node of key k (or nullptr), for a message; does not make it known.
  const toml::node* node(const std::string& k) const { return tab_ ? tab_->get(k) : nullptr; }
  bool has(const std::string& k) const { return tab_ && tab_->contains(k); }
  bool present() const { return tab_ != nullptr; }  // the file has this [section]
  [[noreturn]] void fail(const std::string& k, const toml::node* n, const std::string& msg) const {
    ctx_->fail(key(k), n, msg);
  }
  const Context& context() const { return *ctx_; }

  // A number from an integer or float node, checked against `r`.
  double number_of(const std::string& k, const toml::node& n, const Range& r, const std::string& what) const;
  void number(const std::string& k, double& dst, const Range& r);
  template <class Int>
  void integer(const std::string& k, Int& dst, const Range& r);
  void boolean(const std::string& k, bool& dst);
  // A string, one of `allowed` (any string if empty), with a "did you mean".
  std::string string_of(const std::string& k, const toml::node& n,
                        const std::vector<std::string>& allowed) const;
  // One of a choice's spellings (scene.hpp) onto its enum.
  template <Choice E>
  void choice(const std::string& k, E& dst);
  Vec3 vec3_of(const std::string& k, const toml::node& n, const Range& r) const;
  void vec3(const std::string& k, Vec3& dst, const Range& r);
  // Gamma0 / Omega0: 3 numbers (uniform) or an array of N triples (a profile
  // along s, component-major into `profile`).
  void shape(const std::string& k, Vec3& uniform, std::vector<double>& profile);
  // An n x n matrix written as n arrays of n numbers, row-major.
  std::vector<double> matrix_of(const std::string& k, const toml::node& node, int n,
                                const std::string& allowed) const;
  // An existing file, absolute; relative paths are relative to the scene's folder. "" if absent.
  std::string path(const std::string& k, const std::string& what);

  // A key that belongs in this section but is refused in this scene, and
  // why (initial.path for a kind other than "file"): reported first by
  // reject_unknown() when present, named in the "belongs in [section]" hints
  // of other sections, not in this one's allowed keys.
  void refuse(const std::string& k, const std::string& reason) { refused_.emplace_back(k, reason); }
  // Known and refused keys, for the hints of other sections.
  std::vector<std::string> belonging() const;
  // A refused key present is an error (its reason); keys present but never
  // asked for are unknown: say which, and suggest. all_known: every
  // section's belonging() keys, by section name.
  void reject_unknown(const std::map<std::string, std::vector<std::string>>& all_known) const;

  const std::vector<std::string>& known() const { return known_; }
  const std::string& name() const { return name_; }

 private:
  const Context* ctx_;
  std::string name_;
  const toml::table* tab_;
  std::vector<std::string> known_;
  std::vector<std::pair<std::string, std::string>> refused_;  // key, reason
};

template <class Int>
void Section::integer(const std::string& k, Int& dst, const Range& r) {
  if (auto n = get(k)) {
    auto i = n->as_integer();
    if (!i) fail(k, n, "found " + describe(*n) + "; allowed: " + r.text("an integer"));
    double v = static_cast<double>(i->get());
    if (!r.contains(v))
      fail(k, n, "found " + std::to_string(i->get()) + "; allowed: " + r.text("an integer"));
    dst = static_cast<Int>(i->get());
  }
}

template <Choice E>
void Section::choice(const std::string& k, E& dst) {
  if (auto n = get(k)) dst = *from_string<E>(string_of(k, *n, choice_names<E>()));
}

// TOML text of values, written by hand so doubles keep all 17 digits.
std::string toml_str(const std::string& s);
std::string toml_num(double v);
std::string toml_vec(const Vec3& v);
std::string toml_profile(const std::vector<double>& p, int N);  // N triples from component-major
std::string toml_matrix(const std::vector<double>& A, int n);   // n x n, row-major

}  // namespace rodcore
