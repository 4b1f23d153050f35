// TOML scene -> validated Scene. The reader is strict on purpose: a scene key
// that is misspelt and silently ignored would run a different experiment than
// the one the user wrote down.
//
// The file is read one section at a time, by the readers of
// scene_sections.hpp; then unknown keys are rejected (every section has said
// what it knows, so a key in the wrong section is named); then
// check_across_sections() checks what spans sections.
#include "rodcore/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "rodcore/did_you_mean.hpp"
#include "rodcore/error.hpp"
#include "rodcore/guards.hpp"
#include "rodcore/h5_initial.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/material.hpp"
#include "rodcore/scene_section.hpp"
#include "rodcore/scene_sections.hpp"
#include "rodcore/solvent.hpp"

namespace fs = std::filesystem;

namespace rodcore {

namespace {

std::vector<std::string> section_names() {
  std::vector<std::string> names;
  for (const auto& s : scene_sections()) names.push_back(s.name);
  return names;
}

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
    const std::vector<std::string> sections = section_names();
    if (std::find(sections.begin(), sections.end(), sec) == sections.end()) {
      std::string hint = closest_match(sec, sections);
      throw InputError(ctx.source + ": --set " + key + ": unknown section [" + sec + "]" +
                       (hint.empty() ? "" : "; did you mean [" + hint + "]?") +
                       " Allowed sections: " + join(sections, ", ", false));
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

int min_points(SpaceMethod space) { return space == SpaceMethod::fd4 ? 5 : 4; }  // auto: spectral below 5

// Every top-level key is a known section, and a table.
void check_sections(const toml::table& table, const Context& ctx) {
  const std::vector<std::string> sections = section_names();
  for (const auto& [k, n] : table) {
    std::string kk(k.str());
    if (std::find(sections.begin(), sections.end(), kk) == sections.end()) {
      std::string hint = closest_match(kk, sections);
      ctx.fail(kk, &n,
               "unknown section" + (hint.empty() ? std::string() : "; did you mean [" + hint + "]?") +
                   " Allowed sections: " + join(sections, ", ", false));
    }
    if (!n.is_table()) ctx.fail(kk, &n, "found " + describe(n) + "; expected a table [" + kk + "]");
  }
}

// Unknown keys anywhere, now that every section has said what it knows.
void reject_unknown_keys(const std::vector<Section>& sections) {
  std::map<std::string, std::vector<std::string>> all_known;
  for (const Section& s : sections) all_known[s.name()] = s.belonging();
  for (const Section& s : sections) s.reject_unknown(all_known);
}

// What spans sections, on the sections as read.
void check_across_sections(SceneDraft& d, Section& rod, Section& mat, Section& ini) {
  Scene& sc = d.scene;
  // The kind may set rod values it implies (e.g. dna_planar: L, Omega0).
  const InitialKindSpec& kind = initial_kind_spec(sc.initial.kind);
  if (kind.derive_rod) {
    try {
      kind.derive_rod(sc.initial, sc.rod, sc.material, d.set_keys);
    } catch (const InputError& e) {
      throw InputError(sc.source + ": initial.kind = \"" + kind.name + "\": " + e.what());
    }
  }

  // The grid, against the solver's operator.
  if (!(sc.rod.length > 0.0))
    rod.fail("length", nullptr, "is required: the fiducial length L > 0 (dimensionless)");
  if (sc.rod.points <= 0) rod.fail("points", nullptr, "is required: the number of grid points N");
  int nmin = min_points(sc.solver.space);
  if (sc.rod.points < nmin)
    rod.fail("points", rod.node("points"),
             "found " + std::to_string(sc.rod.points) + "; solver.space = \"" +
                 (sc.solver.space == SpaceMethod::fd4 ? "fd4" : "spectral") + "\" needs at least " +
                 std::to_string(nmin) + " points (fd4: 5, its stencil spans 5 points; spectral: 4)");
  const auto N3 = 3 * static_cast<std::size_t>(sc.rod.points);
  for (auto [k, prof] : {std::pair{"Gamma0", &sc.rod.Gamma0_s}, std::pair{"Omega0", &sc.rod.Omega0_s}}) {
    if (!prof->empty() && prof->size() != N3)
      rod.fail(k, rod.node(k),
               "has " + std::to_string(prof->size() / 3) + " points; a profile along s needs rod.points = " +
                   std::to_string(sc.rod.points) + " triples");
  }

  // The files that need the grid.
  if (!d.intrinsic_file.empty()) {
    try {
      read_intrinsic_shape(d.intrinsic_file, sc.rod.points, sc.rod.Gamma0_s, sc.rod.Omega0_s);
    } catch (const InputError& e) {
      rod.fail("intrinsic_file", rod.node("intrinsic_file"), e.what());
    }
  }
  if (!d.material_file.empty()) {
    std::vector<double> G0, O0;
    try {
      read_material_file(d.material_file, sc.rod.points, sc.material, G0, O0);
    } catch (const InputError& e) {
      mat.fail("material_file", mat.node("material_file"), e.what());
    }
    if (!G0.empty() || !O0.empty()) {
      for (const char* k : {"Gamma0", "Omega0", "intrinsic_file"})
        if (rod.has(k))
          rod.fail(k, rod.node(k),
                   "the material file '" + d.material_file +
                       "' holds the intrinsic shape (datasets Gamma0, Omega0): give it "
                       "there or in [rod], not both");
      if (!G0.empty()) sc.rod.Gamma0_s = std::move(G0);
      if (!O0.empty()) sc.rod.Omega0_s = std::move(O0);
      sc.material.file_has_shape = true;
    }
  }
  if (sc.initial.kind == InitialKind::file) {
    // Read it once now so that a bad file is reported as a scene problem.
    std::vector<double> s(sc.rod.points), y;
    for (int i = 0; i < sc.rod.points; ++i) s[i] = i * sc.rod.length / sc.rod.points;
    try {
      read_initial_fields(sc.initial.path, s, y);
    } catch (const InputError& e) {
      ini.fail("path", ini.node("path"), e.what());
    }
  }
}

// [thermal] against the rest, once the rod's length is known: the "water"
// frictions, then the settings that span sections (thermal_settings_problem).
template <class SectionOf>
void check_thermal(Scene& sc, SectionOf& section) {
  Thermal& t = sc.thermal;
  Section& th = section("thermal");
  // the length of the motion: the rod's own unless given (solvent.hpp)
  if ((t.translational_water || t.rotational_water) && std::isnan(t.friction_length_nm))
    t.friction_length_nm = sc.rod.length * dna_length_nm();
  for (auto [water, key, dst] :
       {std::tuple{t.translational_water, "friction_translational", &t.friction_translational},
        std::tuple{t.rotational_water, "friction_rotational", &t.friction_rotational}}) {
    if (!water) continue;
    try {
      const WaterFriction w =
          water_friction_rod(t.viscosity_mPa_s, t.radius_nm, t.friction_length_nm / dna_length_nm());
      *dst = std::string(key) == "friction_translational" ? w.translational : w.rotational;
    } catch (const InputError& e) {
      th.fail(key, th.node(key), e.what());
    }
  }
  const auto [key, problem] = thermal_settings_problem(sc);
  if (key.empty()) return;
  const auto dot = key.find('.');
  Section& s = section(key.substr(0, dot));
  const std::string k = key.substr(dot + 1);
  s.fail(k, s.node(k), problem);
}

Scene build_scene(toml::table& table, Context& ctx) {
  check_sections(table, ctx);
  SceneDraft draft;
  draft.scene.source = ctx.source;
  std::vector<Section> sections;
  sections.reserve(scene_sections().size());
  for (bool last : {false, true})
    for (const auto& reader : scene_sections())
      if (reader.read_last == last) {
        sections.emplace_back(ctx, reader.name, table[reader.name].as_table());
        reader.read(sections.back(), draft);
      }
  reject_unknown_keys(sections);
  auto section = [&](const std::string& name) -> Section& {
    return *std::find_if(sections.begin(), sections.end(),
                         [&](const Section& s) { return s.name() == name; });
  };
  check_across_sections(draft, section("rod"), section("material"), section("initial"));
  check_thermal(draft.scene, section);
  return std::move(draft.scene);
}

// The first byte at which TEXT stops being UTF-8 (RFC 3629: no overlong forms, no surrogates,
// at most U+10FFFF), or npos.
std::size_t first_non_utf8(const std::string& text) {
  const auto* b = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned c = b[i];
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (c < 0x80) len = 1;
    else if (c >= 0xC2 && c <= 0xDF) len = 2;
    else if (c == 0xE0) len = 3, lo = 0xA0;
    else if (c == 0xED) len = 3, hi = 0x9F;
    else if (c >= 0xE1 && c <= 0xEF) len = 3;
    else if (c == 0xF0) len = 4, lo = 0x90;
    else if (c == 0xF4) len = 4, hi = 0x8F;
    else if (c >= 0xF1 && c <= 0xF3) len = 4;
    else return i;
    if (i + len > n) return i;
    for (std::size_t k = 1; k < len; ++k)
      if (b[i + k] < (k == 1 ? lo : 0x80u) || b[i + k] > (k == 1 ? hi : 0xBFu)) return i;
    i += len;
  }
  return std::string::npos;
}

// The scene file's text, refused when it is not a scene's: a folder, no such file, an empty
// file, or binary bytes (a NUL, or not UTF-8, which TOML requires), each named for what it is
// rather than left to the TOML parser or to the first required key.
std::string read_text(const std::string& path) {
  const std::string what = "scene file '" + path + "'";
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(what + ": is a folder, not a scene TOML file");
  if (!fs::exists(path, ec)) throw InputError(what + ": no such file (a scene TOML file is expected)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(what + ": cannot be read (" + std::strerror(errno) + ")");
  std::ostringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InputError(
        what + ": is empty" + (text.empty() ? "" : " (only white space)") +
        "; a scene TOML file is expected, with at least [rod] length and points (docs/scenes.md)");
  const std::size_t nul = text.find('\0');
  const std::size_t bad = nul != std::string::npos ? nul : first_non_utf8(text);
  if (bad != std::string::npos) {
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(bad), '\n');
    throw InputError(what + ": is not a TOML file: its bytes are binary (" +
                     (nul != std::string::npos ? "a NUL byte" : "bytes that are not UTF-8") + " on line " +
                     std::to_string(line) + "); a scene is UTF-8 text");
  }
  return text;
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
  std::string o = "# Resolved scene (every key, defaults filled) from " + sc.source + "\n";
  bool first = true;
  for (const auto& section : scene_sections()) {
    const std::string body = section.write(sc);
    if (body.empty()) continue;
    o += (first ? "[" : "\n[") + section.name + "]\n" + body;
    first = false;
  }
  return o;
}

}  // namespace rodcore
