// One reader and one writer per scene section (scene_sections.hpp). A reader
// asks its Section for each key in the order "Allowed keys" lists them,
// checks what lies within its section, and leaves what needs other sections
// in the SceneDraft; a writer gives every key of its section, resolved.
#include "rodcore/scene_sections.hpp"

#include <cmath>

#include "rodcore/initial_conditions.hpp"
#include "rodcore/material.hpp"
#include "rodcore/solvent.hpp"

namespace rodcore {
namespace {

const double kInf = std::numeric_limits<double>::infinity();

// ---- [rod]: the fiducial length, the grid and the intrinsic shape

void read_rod(Section& rod, SceneDraft& d) {
  Scene& sc = d.scene;
  for (const char* k : {"length", "points", "Gamma0", "Omega0"})
    if (rod.has(k)) d.set_keys.insert(k);
  if (rod.has("intrinsic_file")) d.set_keys.insert({"Gamma0", "Omega0"});
  rod.number("length", sc.rod.length, positive());
  rod.integer("points", sc.rod.points, Range{1, 1e8});
  rod.shape("Gamma0", sc.rod.Gamma0, sc.rod.Gamma0_s);
  rod.shape("Omega0", sc.rod.Omega0, sc.rod.Omega0_s);
  d.intrinsic_file = rod.path("intrinsic_file", "intrinsic-shape file");
  if (!d.intrinsic_file.empty() && (rod.has("Gamma0") || rod.has("Omega0")))
    rod.fail("intrinsic_file", rod.get("intrinsic_file"),
             "give either rod.intrinsic_file or rod.Gamma0/rod.Omega0, not both");
}

std::string write_rod(const Scene& sc) {
  const Rod& r = sc.rod;
  std::string o = "length = " + toml_num(r.length) + "\npoints = " + std::to_string(r.points) + "\n";
  if (sc.material.file_has_shape) return o + "# Gamma0, Omega0: from material.material_file\n";
  o += "Gamma0 = " + (r.Gamma0_s.empty() ? toml_vec(r.Gamma0) : toml_profile(r.Gamma0_s, r.points)) + "\n";
  o += "Omega0 = " + (r.Omega0_s.empty() ? toml_vec(r.Omega0) : toml_profile(r.Omega0_s, r.points)) + "\n";
  return o;
}

// ---- [material]: the paper's diagonals C, D, I, or a full K (6 x 6) and I
// (3 x 3), and rho; or a per-point material file (material.hpp).

void read_material(Section& mat, SceneDraft& d) {
  Scene& sc = d.scene;
  for (const char* k : {"C", "D", "I", "K", "rho", "material_file"})
    if (mat.has(k)) d.set_keys.insert(k);
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
    check_stiffness(sc.material.K.data(), mat.context().where(mat.key("K"), n));
  }
  if (auto n = mat.get("I")) {
    auto a = n->as_array();
    if (a && !a->empty() && a->get(0)->is_array()) {
      sc.material.I_full = mat.matrix_of("I", *n, 3,
                                         "3 numbers > 0 (a diagonal I) or a symmetric positive-definite "
                                         "3 x 3 matrix (3 arrays of 3 numbers)");
      check_inertia(sc.material.I_full.data(), mat.context().where(mat.key("I"), n));
    } else {
      sc.material.I = mat.vec3_of("I", *n, positive());
    }
  }
  mat.number("rho", sc.material.rho, positive());
  d.material_file = mat.path("material_file", "material file");
  if (!d.material_file.empty())
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
}

std::string write_material(const Scene& sc) {
  const Material& m = sc.material;
  if (!m.file.empty()) return "material_file = " + toml_str(m.file) + "\n";
  std::string o = m.K.empty() ? "C = " + toml_vec(m.C) + "\nD = " + toml_vec(m.D) + "\n"
                              : "K = " + toml_matrix(m.K, 6) + "\n";
  o += "I = " + (m.I_full.empty() ? toml_vec(m.I) : toml_matrix(m.I_full, 3)) + "\nrho = " + toml_num(m.rho) +
       "\n";
  return o;
}

// ---- [initial]: the kind declares its own parameters (initial_conditions.hpp).

void read_initial(Section& ini, SceneDraft& d) {
  Initial& initial = d.scene.initial;
  ini.choice("kind", initial.kind);
  const InitialKindSpec& kind = initial_kind_spec(initial.kind);
  for (const auto& p : kind.numbers) {
    Range r{p.min, p.max, false, false};
    std::string what = "a number" + (p.unit.empty() ? std::string() : " [" + p.unit + "]");
    if (auto n = ini.get(p.name)) {
      initial.numbers[p.name] = ini.number_of(p.name, *n, r, what);
    } else if (std::isnan(p.default_value)) {
      ini.fail(
          p.name, nullptr,
          "is required for initial.kind = \"" + kind.name + "\" (" + p.doc + "); allowed: " + r.text(what));
    } else {
      initial.numbers[p.name] = p.default_value;
    }
  }
  for (const auto& c : kind.strings) {
    if (auto n = ini.get(c.name)) initial.strings[c.name] = ini.string_of(c.name, *n, c.allowed);
    else initial.strings[c.name] = c.default_value;
  }
  if (initial.kind == InitialKind::file) {
    if (!ini.has("path"))
      ini.fail("path", nullptr,
               "is required for initial.kind = \"file\": the HDF5 file with s and "
               "fields/{gamma,omega,Gamma,Omega}");
    initial.path = ini.path("path", "initial-condition file");
  } else {
    ini.refuse("path", "is only used by initial.kind = \"file\" (this scene has kind \"" + kind.name + "\")");
  }
}

std::string write_initial(const Scene& sc) {
  std::string o = "kind = " + toml_str(to_string(sc.initial.kind)) + "\n";
  for (const auto& [k, v] : sc.initial.numbers) o += k + " = " + toml_num(v) + "\n";
  for (const auto& [k, v] : sc.initial.strings) o += k + " = " + toml_str(v) + "\n";
  if (!sc.initial.path.empty()) o += "path = " + toml_str(sc.initial.path) + "\n";
  return o;
}

// ---- [solver]: the method (space, time, reduction) and its tolerances.

void read_solver(Section& sol, SceneDraft& d) {
  SolverOptions& s = d.scene.solver;
  sol.choice("space", s.space);
  sol.boolean("dealias", s.dealias);
  sol.choice("time", s.time);
  sol.number("rtol", s.rtol, {0.0, 1.0, true, true});
  sol.number("atol", s.atol, positive());
  sol.number("dt", s.dt, positive());
  sol.number("dt_min", s.dt_min, positive());
  sol.integer("max_steps", s.max_steps, Range{1, 9e18});
  sol.choice("reduce", s.reduce);
  sol.boolean("exact_noise", s.exact_noise);
  if (!s.exact_noise && s.time != TimeMethod::brownian)
    sol.fail("exact_noise", sol.get("exact_noise"), "applies only to solver.time = \"brownian\"");
  if (s.dealias && s.space == SpaceMethod::fd4)
    sol.fail("dealias", sol.get("dealias"), "applies only to solver.space = \"spectral\" (found \"fd4\")");
  if (s.dt_min > s.dt)
    sol.fail("dt_min", sol.get("dt_min"),
             "found " + fmt_num(s.dt_min) + "; must not exceed solver.dt = " + fmt_num(s.dt));
}

std::string write_solver(const Scene& sc) {
  const SolverOptions& s = sc.solver;
  return "space = " + toml_str(to_string(s.space)) + "\ndealias = " + (s.dealias ? "true" : "false") +
         "\ntime = " + toml_str(to_string(s.time)) + "\nrtol = " + toml_num(s.rtol) +
         "\natol = " + toml_num(s.atol) + "\ndt = " + toml_num(s.dt) + "\ndt_min = " + toml_num(s.dt_min) +
         "\nmax_steps = " + std::to_string(s.max_steps) + "\nreduce = " + toml_str(to_string(s.reduce)) +
         "\n" +
         (s.time == TimeMethod::brownian
              ? std::string("exact_noise = ") + (s.exact_noise ? "true\n" : "false\n")
              : std::string());
}

// ---- [output]: the output times, the fields written, checkpoints.

const std::vector<std::string> kOutputFields = {"internal", "energy", "energy_parts", "centerline",
                                                "directors"};

void read_output(Section& out, SceneDraft& d) {
  OutputOptions& o = d.scene.output;
  out.number("t_end", o.t_end, positive());
  out.integer("frames", o.frames, Range{2, 1e8});
  if (auto n = out.get("fields")) {
    auto a = n->as_array();
    if (!a)
      out.fail("fields", n,
               "found " + describe(*n) + "; allowed: an array of strings from " + join(kOutputFields));
    o.internal = o.energy = o.energy_parts = false;
    o.centerline = o.directors = false;
    for (std::size_t i = 0; i < a->size(); ++i) {
      std::string f = out.string_of("fields[" + std::to_string(i) + "]", *a->get(i), kOutputFields);
      if (f == "internal") o.internal = true;
      if (f == "energy") o.energy = true;
      if (f == "energy_parts") o.energy_parts = true;
      if (f == "centerline") o.centerline = true;
      if (f == "directors") o.directors = true;
    }
  }
  out.number("checkpoint_interval_s", o.checkpoint_interval_s, Range{0.0, kInf, false, false});
}

std::string write_output(const Scene& sc) {
  const OutputOptions& out = sc.output;
  std::vector<std::string> fields;
  if (out.internal) fields.push_back("internal");
  if (out.energy) fields.push_back("energy");
  if (out.energy_parts) fields.push_back("energy_parts");
  if (out.centerline) fields.push_back("centerline");
  if (out.directors) fields.push_back("directors");
  return "t_end = " + toml_num(out.t_end) + "\nframes = " + std::to_string(out.frames) + "\nfields = [" +
         join(fields) + "]\ncheckpoint_interval_s = " + toml_num(out.checkpoint_interval_s) + "\n";
}

// ---- [checks]: bad numerics never pass silently (guards.hpp).

void read_checks(Section& chk, SceneDraft& d) {
  Checks& c = d.scene.checks;
  chk.number("max_energy_drift", c.max_energy_drift, positive());
  chk.number("max_director_norm_error", c.max_director_norm_error, positive());
  chk.boolean("stop_on_fold", c.stop_on_fold);
}

std::string write_checks(const Scene& sc) {
  const Checks& c = sc.checks;
  return "max_energy_drift = " + toml_num(c.max_energy_drift) +
         "\nmax_director_norm_error = " + toml_num(c.max_director_norm_error) +
         "\nstop_on_fold = " + (c.stop_on_fold ? "true" : "false") + "\n";
}

// ---- [thermal]: the rod at a temperature (docs/thermal.md). A "water"
// friction needs the rod's length: it is resolved with the checks across
// sections (scene_reader.cpp).

// A friction: one number (both directions), [along, across] or "water".
void friction(Section& th, const std::string& k, const std::string& pair, std::array<double, 2>& dst,
              bool& water) {
  const toml::node* n = th.get(k);
  if (!n) return;
  const std::string allowed = "a number >= 0 (" + pair + " alike), an array [" + pair +
                              "] of 2 numbers >= 0 (rod units, per length), or \"water\"";
  const Range r{0.0, kInf, false, true};
  if (n->is_string()) {
    th.string_of(k, *n, {"water"});
    water = true;
  } else if (auto a = n->as_array(); a && a->size() == 2) {
    for (std::size_t c = 0; c < 2; ++c)
      dst[c] = th.number_of(k + "[" + std::to_string(c) + "]", *a->get(c), r, "a number");
  } else if (n->is_number()) {
    dst[0] = dst[1] = th.number_of(k, *n, r, "a number");
  } else {
    th.fail(k, n, "found " + describe(*n) + "; allowed: " + allowed);
  }
}

void read_thermal(Section& th, SceneDraft& d) {
  Thermal& t = d.scene.thermal;
  t.on = th.present();
  const Range energy{0.0, kInf, false, true};
  const toml::node* kT = th.get("kT");
  const toml::node* T = th.get("temperature_K");
  if (kT) t.kT = th.number_of("kT", *kT, energy, "a number (energy in the material's units)");
  if (T) {
    t.temperature_K = th.number_of("temperature_K", *T, energy, "a number [K]");
    t.kT = kT_rod_of_kelvin(t.temperature_K);
  }
  if (kT && T)
    th.fail("temperature_K", T,
            "give either thermal.kT (energy in the material's units) or thermal.temperature_K (DNA units), "
            "not both");
  th.integer("seed", t.seed, Range{0, 9.2e18});
  th.boolean("sample_initial", t.sample_initial);
  friction(th, "friction_translational", "along, across", t.friction_translational, t.translational_water);
  friction(th, "friction_rotational", "about the axis, across", t.friction_rotational, t.rotational_water);
  th.number("viscosity_mPa_s", t.viscosity_mPa_s, positive());
  th.number("radius_nm", t.radius_nm, positive());
  th.number("friction_length_nm", t.friction_length_nm, positive());
  th.boolean("keep_closure", t.keep_closure);
  th.number("closure_interval", t.closure_interval, Range{0.0, kInf, false, true});
  if (!t.on) return;
  const bool water = t.translational_water || t.rotational_water;
  for (const char* k : {"viscosity_mPa_s", "radius_nm", "friction_length_nm"})
    if (th.has(k) && !water)
      th.fail(k, th.node(k),
              "is used only by a \"water\" friction (thermal.friction_translational or "
              "thermal.friction_rotational = \"water\")");
  if (!kT && !T) {
    const bool friction_given = th.has("friction_translational") || th.has("friction_rotational");
    const char* k = th.has("friction_translational") ? "friction_translational" : "friction_rotational";
    if (friction_given)
      th.fail(k, th.node(k),
              "a friction needs a temperature: give thermal.kT (energy in the material's units) or "
              "thermal.temperature_K (DNA units); 0 makes a damped rod without noise");
    th.fail("kT", nullptr,
            "[thermal] needs thermal.kT (energy in the material's units) or thermal.temperature_K (DNA "
            "units)");
  }
}

std::string write_thermal(const Scene& sc) {
  const Thermal& t = sc.thermal;
  if (!t.on) return "";
  std::string o = std::isnan(t.temperature_K)
                      ? "kT = " + toml_num(t.kT) + "\n"
                      : "temperature_K = " + toml_num(t.temperature_K) + "  # kT = " + toml_num(t.kT) + "\n";
  o += "seed = " + std::to_string(t.seed) + "\nsample_initial = " + (t.sample_initial ? "true" : "false") +
       "\n";
  auto pair = [](const std::array<double, 2>& z) {
    return "[" + toml_num(z[0]) + ", " + toml_num(z[1]) + "]";
  };
  o += "friction_translational = " +
       (t.translational_water ? "\"water\"  # [along, across] = " + pair(t.friction_translational)
                              : pair(t.friction_translational)) +
       "\n";
  o += "friction_rotational = " +
       (t.rotational_water ? "\"water\"  # [about the axis, across] = " + pair(t.friction_rotational)
                           : pair(t.friction_rotational)) +
       "\n";
  o += std::string("keep_closure = ") + (t.keep_closure ? "true" : "false") +
       "\nclosure_interval = " + toml_num(t.closure_interval) + "\n";
  if (t.translational_water || t.rotational_water)
    o += "viscosity_mPa_s = " + toml_num(t.viscosity_mPa_s) + "\nradius_nm = " + toml_num(t.radius_nm) +
         "\nfriction_length_nm = " + toml_num(t.friction_length_nm) + "\n";
  return o;
}

// ---- [contact]: self-contact (docs/topology.md, "Self-contact"). Read after
// [thermal], whose kT calibrates the potential.

// The effective diameter of DNA, about 5 nm near 0.15 M NaCl (Rybenkov, Cozzarelli &
// Vologodskii, PNAS 90:5307, 1993).
constexpr double kDefaultDiameter_nm = 5.0;
// The temperature of the calibration when the scene has no [thermal] kT.
constexpr double kCalibration_K = 300.0;

void read_contact(Section& ct, SceneDraft& d) {
  Contact& c = d.scene.contact;
  c.on = ct.present();
  const toml::node* dr = ct.get("diameter");
  const toml::node* dn = ct.get("diameter_nm");
  c.diameter_nm = kDefaultDiameter_nm;
  if (dn) c.diameter_nm = ct.number_of("diameter_nm", *dn, positive(), "a number [nm]");
  c.diameter = c.diameter_nm * 10.0 / dna_units::ell_A;
  if (dr) {
    c.diameter = ct.number_of("diameter", *dr, positive(), "a number (rod length units)");
    c.diameter_nm = std::numeric_limits<double>::quiet_NaN();
  }
  if (dr && dn)
    ct.fail("diameter_nm", dn,
            "give either contact.diameter (rod length units) or contact.diameter_nm (DNA units), not both");
  ct.number("barrier_kT", c.barrier_kT, Range{1.0, 1e6});
  ct.integer("stride", c.stride, Range{1, 1e6});
  const Thermal& t = d.scene.thermal;
  c.kT = t.on && t.kT > 0.0 ? t.kT : kT_rod_of_kelvin(kCalibration_K);
}

std::string write_contact(const Scene& sc) {
  const Contact& c = sc.contact;
  if (!c.on) return "";
  std::string o = std::isnan(c.diameter_nm) ? "diameter = " + toml_num(c.diameter) + "\n"
                                            : "diameter_nm = " + toml_num(c.diameter_nm) +
                                                  "  # diameter = " + toml_num(c.diameter) + "\n";
  o += "barrier_kT = " + toml_num(c.barrier_kT) + "  # kT = " + toml_num(c.kT) + "\n";
  o += "stride = " + std::to_string(c.stride) + "\n";
  return o;
}

}  // namespace

const std::vector<SectionReader>& scene_sections() {
  static const std::vector<SectionReader> sections = {
      {"rod", read_rod, write_rod},
      {"material", read_material, write_material},
      {"initial", read_initial, write_initial, /*read_last=*/true},
      {"solver", read_solver, write_solver},
      {"output", read_output, write_output},
      {"checks", read_checks, write_checks},
      {"thermal", read_thermal, write_thermal},
      {"contact", read_contact, write_contact},
  };
  return sections;
}

}  // namespace rodcore
