// Scene reader: every kind of bad input gives an InputError that names the
// file, the dotted key and what is allowed; good input gives the Scene the
// file describes (defaults filled), and a resolved scene reads back to the
// same Scene.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "rodcore/error.hpp"
#include "rodcore/h5_initial.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/scene_reader.hpp"
#include "rodcore/state.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace rodcore;

namespace {

const std::string kMinimal = "[rod]\nlength = 6.0\npoints = 16\n";

// Message of the InputError thrown by reading `text`; fails if none is thrown.
std::string error_of(const std::string& text, const std::vector<std::string>& sets = {},
                     const std::string& base_dir = ".") {
  try {
    read_scene_string(text, "scene.toml", base_dir, sets);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return "";
}

// A smooth state on the grid s_i = i L / N with a known value in every slot.
std::vector<double> known_state(std::size_t N, double L) {
  std::vector<double> y(kComponents * N);
  for (int r = 0; r < kComponents; ++r)
    for (std::size_t i = 0; i < N; ++i) y[r * N + i] = std::sin((r + 1) * 2 * M_PI * i / N) + 0.1 * r + L;
  return y;
}
std::vector<double> grid(std::size_t N, double L) {
  std::vector<double> s(N);
  for (std::size_t i = 0; i < N; ++i) s[i] = i * L / N;
  return s;
}

}  // namespace

TEST(IoSceneReader, EditDistanceIsLevenshtein) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);  // the textbook example
  EXPECT_EQ(edit_distance("", "abc"), 3);
  EXPECT_EQ(edit_distance("rtol", "RTOL"), 0);
  EXPECT_EQ(closest_match("rtoll", {"atol", "rtol", "dt"}), "rtol");
  EXPECT_EQ(closest_match("zzzzzz", {"atol", "rtol"}), "");
}

TEST(IoSceneReader, MinimalSceneGetsTheDocumentedDefaults) {
  Scene sc = read_scene_string(kMinimal, "scene.toml");
  Scene def;
  EXPECT_EQ(sc.rod.length, 6.0);
  EXPECT_EQ(sc.rod.points, 16);
  EXPECT_EQ(sc.rod.Gamma0, def.rod.Gamma0);
  EXPECT_EQ(sc.material.C, def.material.C);
  EXPECT_EQ(sc.material.D, def.material.D);
  EXPECT_EQ(sc.solver.space, SpaceMethod::automatic);  // resolved per scene by Simulation
  EXPECT_EQ(sc.solver.time, TimeMethod::automatic);
  EXPECT_EQ(sc.solver.time, def.solver.time);
  EXPECT_EQ(sc.solver.rtol, def.solver.rtol);
  EXPECT_EQ(sc.output.frames, def.output.frames);
  EXPECT_EQ(sc.initial.kind, InitialKind::rest);
  EXPECT_EQ(sc.source, "scene.toml");
  // Every declared parameter of the kind is filled in, and nothing else.
  const auto& kind = initial_kind_spec(InitialKind::rest);
  EXPECT_EQ(sc.initial.numbers.size(), kind.numbers.size());
  for (const auto& p : kind.numbers) EXPECT_EQ(sc.initial.numbers.at(p.name), p.default_value) << p.name;
}

TEST(IoSceneReader, IssueExampleWithFileInitialCondition) {
  TempDir dir;
  const std::size_t N = 48;
  const double L = 6.283185307179586;
  auto y = known_state(N, L);
  write_initial_fields((dir.path / "ic.h5").string(), grid(N, L), y);
  std::string path = dir.write("scene.toml", R"(
[rod]
length = 6.283185307179586   # fiducial length L (dimensionless)
points = 48                  # N
Gamma0 = [0.0, 0.0, 1.0]
Omega0 = [0.0, 0.0, 1.0]
[material]
C = [1.0, 1.0, 1.19]
D = [1.21, 1.21, 2.0207]
I = [1.0, 1.0, 2.0]
[initial]
kind = "file"
path = "ic.h5"
[solver]
space = "spectral"
time = "dop853"
rtol = 1e-11
atol = 1e-11
dt = 0.01
[output]
t_end = 2.0
frames = 3
fields = ["internal", "energy"]
)");
  Scene sc = read_scene_file(path);
  EXPECT_EQ(sc.rod.points, 48);
  EXPECT_EQ(sc.rod.Omega0, (Vec3{0, 0, 1}));
  EXPECT_EQ(sc.material.D, (Vec3{1.21, 1.21, 2.0207}));
  EXPECT_EQ(sc.initial.kind, InitialKind::file);
  EXPECT_EQ(fs::path(sc.initial.path), fs::absolute(dir.path / "ic.h5").lexically_normal());
  EXPECT_EQ(sc.solver.rtol, 1e-11);
  EXPECT_EQ(sc.output.frames, 3);
  EXPECT_TRUE(sc.output.internal);
  EXPECT_TRUE(sc.output.energy);
  EXPECT_FALSE(sc.output.energy_parts);
  EXPECT_FALSE(sc.output.centerline);
  // The file's fields come back exactly (the writer and reader agree on layout).
  std::vector<double> back;
  read_initial_fields(sc.initial.path, grid(N, L), back);
  EXPECT_EQ(back, y);
}

TEST(IoSceneReader, UnknownKeyNamesFileLineKeyAndSuggests) {
  std::string m = error_of(kMinimal + "[solver]\nrtoll = 1e-8\n");
  EXPECT_NE(m.find("scene.toml:5"), std::string::npos) << m;
  EXPECT_NE(m.find("solver.rtoll"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean solver.rtol?"), std::string::npos) << m;
  EXPECT_NE(m.find("Allowed keys:"), std::string::npos) << m;
}

TEST(IoSceneReader, KeyInTheWrongSectionSaysWhereItBelongs) {
  std::string m = error_of(kMinimal + "[output]\nspace = \"fd4\"\n");
  EXPECT_NE(m.find("output.space"), std::string::npos) << m;
  EXPECT_NE(m.find("belongs in [solver]"), std::string::npos) << m;
}

TEST(IoSceneReader, UnknownSectionSuggests) {
  std::string m = error_of(kMinimal + "[solvr]\nrtol = 1e-8\n");
  EXPECT_NE(m.find("solvr"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean [solver]?"), std::string::npos) << m;
}

TEST(IoSceneReader, WrongTypeSaysWhatWasFoundAndWhatIsAllowed) {
  std::string m = error_of(kMinimal + "[solver]\nrtol = \"small\"\n");
  EXPECT_NE(m.find("solver.rtol"), std::string::npos) << m;
  EXPECT_NE(m.find("found the string \"small\""), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: a number > 0 and < 1"), std::string::npos) << m;
  m = error_of("[rod]\nlength = 6.0\npoints = 16.5\n");
  EXPECT_NE(m.find("rod.points"), std::string::npos) << m;
  EXPECT_NE(m.find("an integer"), std::string::npos) << m;
  m = error_of(kMinimal + "[checks]\nstop_on_fold = 1\n");
  EXPECT_NE(m.find("checks.stop_on_fold"), std::string::npos) << m;
  EXPECT_NE(m.find("true or false"), std::string::npos) << m;
}

TEST(IoSceneReader, OutOfRangeValues) {
  std::string m = error_of(kMinimal + "[solver]\nrtol = -1\n");
  EXPECT_NE(m.find("solver.rtol: found -1; allowed: a number > 0 and < 1"), std::string::npos) << m;
  m = error_of("[rod]\nlength = 0\npoints = 16\n");
  EXPECT_NE(m.find("rod.length: found 0; allowed: a number > 0"), std::string::npos) << m;
  m = error_of(kMinimal + "[material]\nC = [1.0, -1.0, 1.19]\n");
  EXPECT_NE(m.find("material.C[1]: found -1"), std::string::npos) << m;
  m = error_of(kMinimal + "[output]\nframes = 1\n");
  EXPECT_NE(m.find("output.frames"), std::string::npos) << m;
  m = error_of(kMinimal + "[solver]\nspace = \"spectrl\"\n");
  EXPECT_NE(
      m.find("solver.space: found \"spectrl\"; allowed: one of \"auto\", \"fd4\", \"spectral\" (did you mean "
             "\"spectral\"?)"),
      std::string::npos)
      << m;
}

TEST(IoSceneReader, NaNIsRejected) {
  std::string m = error_of(kMinimal + "[solver]\natol = nan\n");
  EXPECT_NE(m.find("solver.atol: found nan"), std::string::npos) << m;
  m = error_of("[rod]\nlength = 6.0\npoints = 16\nGamma0 = [0.0, nan, 1.0]\n");
  EXPECT_NE(m.find("rod.Gamma0[1]: found nan"), std::string::npos) << m;
}

TEST(IoSceneReader, InconsistentLengths) {
  std::string m = error_of("[rod]\nlength = 6.0\npoints = 16\nGamma0 = [0.0, 1.0]\n");
  EXPECT_NE(m.find("rod.Gamma0"), std::string::npos) << m;
  EXPECT_NE(m.find("array of 3 numbers"), std::string::npos) << m;
  // A profile along s must have rod.points triples.
  m = error_of("[rod]\nlength = 6.0\npoints = 4\nOmega0 = [[0, 0, 1], [0, 0, 1], [0, 0, 1]]\n");
  EXPECT_NE(m.find("rod.Omega0: has 3 points"), std::string::npos) << m;
  EXPECT_NE(m.find("rod.points = 4"), std::string::npos) << m;
  Scene sc = read_scene_string(
      "[rod]\nlength = 6.0\npoints = 4\nOmega0 = [[0, 0, 1], [0, 0, 2], [0, 0, 3], [0, 1, 4]]\n");
  EXPECT_EQ(sc.rod.Omega0_s, (std::vector<double>{0, 0, 0, 0, 0, 0, 0, 1, 1, 2, 3, 4}));  // component-major
}

TEST(IoSceneReader, TooFewPointsForTheOperator) {
  std::string m = error_of("[rod]\nlength = 6.0\npoints = 4\n[solver]\nspace = \"fd4\"\n");
  EXPECT_NE(m.find("rod.points: found 4; solver.space = \"fd4\" needs at least 5 points"), std::string::npos)
      << m;
  EXPECT_NO_THROW(read_scene_string("[rod]\nlength = 6.0\npoints = 5\n[solver]\nspace = \"fd4\"\n"));
  m = error_of("[rod]\nlength = 6.0\npoints = 3\n");
  EXPECT_NE(m.find("solver.space = \"spectral\" needs at least 4 points"), std::string::npos) << m;
  EXPECT_NO_THROW(read_scene_string("[rod]\nlength = 6.0\npoints = 4\n"));
}

TEST(IoSceneReader, RequiredRodKeys) {
  std::string m = error_of("[rod]\npoints = 16\n");
  EXPECT_NE(m.find("rod.length: is required"), std::string::npos) << m;
  m = error_of("[rod]\nlength = 2.0\n");
  EXPECT_NE(m.find("rod.points: is required"), std::string::npos) << m;
}

TEST(IoSceneReader, TomlSyntaxErrorNamesFileAndLine) {
  std::string m = error_of(kMinimal + "[solver\n");
  EXPECT_NE(m.find("scene.toml:4:"), std::string::npos) << m;
  EXPECT_NE(m.find("not valid TOML"), std::string::npos) << m;
}

TEST(IoSceneReader, MissingICFile) {
  TempDir dir;
  std::string m =
      error_of(kMinimal + "[initial]\nkind = \"file\"\npath = \"nope.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("initial.path"), std::string::npos) << m;
  EXPECT_NE(m.find("nope.h5' does not exist"), std::string::npos) << m;
  m = error_of(kMinimal + "[initial]\nkind = \"file\"\n");
  EXPECT_NE(m.find("initial.path: is required"), std::string::npos) << m;
  m = error_of(kMinimal + "[initial]\nkind = \"rest\"\npath = \"x.h5\"\n");
  EXPECT_NE(m.find("initial.path: is only used by initial.kind = \"file\""), std::string::npos) << m;
}

TEST(IoSceneReader, ICFileWithNaNNamesDatasetAndIndex) {
  TempDir dir;
  auto y = known_state(16, 6.0);
  y[row(Gamma, 1) * 16 + 7] = std::numeric_limits<double>::quiet_NaN();
  write_initial_fields((dir.path / "ic.h5").string(), grid(16, 6.0), y);
  std::string m =
      error_of(kMinimal + "[initial]\nkind = \"file\"\npath = \"ic.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("initial.path"), std::string::npos) << m;
  EXPECT_NE(m.find("dataset 'fields/Gamma' has a non-finite value (nan) at index [7, 1]"), std::string::npos)
      << m;
}

TEST(IoSceneReader, MisShapedICFile) {
  TempDir dir;
  // 12 points in the file, 16 in the scene.
  write_initial_fields((dir.path / "ic.h5").string(), grid(12, 6.0), known_state(12, 6.0));
  std::string m =
      error_of(kMinimal + "[initial]\nkind = \"file\"\npath = \"ic.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("dataset 's' has shape 12, expected 16 values"), std::string::npos) << m;
  // Right N, but a grid for another length.
  write_initial_fields((dir.path / "ic2.h5").string(), grid(16, 5.0), known_state(16, 5.0));
  m = error_of(kMinimal + "[initial]\nkind = \"file\"\npath = \"ic2.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("does not match the scene's grid"), std::string::npos) << m;
  EXPECT_NE(m.find("s[1] = 0.3125, expected 0.375"), std::string::npos) << m;
}

TEST(IoSceneReader, ICFileMissingDatasetOrWrongFieldShape) {
  TempDir dir;
  std::string path = (dir.path / "bad.h5").string();
  // A file with s and an N x 2 fields/gamma, written with the raw HDF5 API.
  hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  auto s = grid(16, 6.0);
  hsize_t n = 16, d2[2] = {16, 2};
  hid_t sp = H5Screate_simple(1, &n, nullptr);
  hid_t d = H5Dcreate2(f, "s", H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data());
  H5Dclose(d);
  H5Sclose(sp);
  std::string m = [&] {
    H5Fflush(f, H5F_SCOPE_GLOBAL);
    try {
      std::vector<double> y;
      read_initial_fields(path, s, y);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_NE(m.find("missing dataset 'fields/gamma'"), std::string::npos) << m;
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  sp = H5Screate_simple(2, d2, nullptr);
  std::vector<double> zeros(32, 0.0);
  d = H5Dcreate2(f, "fields/gamma", H5T_IEEE_F64LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data());
  H5Dclose(d);
  H5Sclose(sp);
  H5Pclose(lcpl);
  H5Fclose(f);
  m = error_of(kMinimal + "[initial]\nkind = \"file\"\npath = \"bad.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("dataset 'fields/gamma' has shape 16 x 2, expected 16 x 3"), std::string::npos) << m;
  // Not HDF5 at all.
  dir.write("text.h5", "hello");
  m = error_of(kMinimal + "[initial]\nkind = \"file\"\npath = \"text.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("is not an HDF5 file"), std::string::npos) << m;
}

TEST(IoSceneReader, IntrinsicFileIsReadAndChecked) {
  TempDir dir;
  std::string path = (dir.path / "shape.h5").string();
  // Reuse the field writer's layout: Gamma0/Omega0 are N x 3 datasets.
  hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hsize_t dims[2] = {16, 3};
  std::vector<double> G(48), O(48);
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) G[3 * i + c] = (c == 2) ? 1.0 : 0.0, O[3 * i + c] = c * 0.1 + i;
  for (auto [name, v] : {std::pair{"Gamma0", &G}, std::pair{"Omega0", &O}}) {
    hid_t sp = H5Screate_simple(2, dims, nullptr);
    hid_t d = H5Dcreate2(f, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v->data());
    H5Dclose(d);
    H5Sclose(sp);
  }
  H5Fclose(f);
  Scene sc = read_scene_string(kMinimal + "intrinsic_file = \"shape.h5\"\n", "scene.toml", dir.path.string());
  ASSERT_EQ(sc.rod.Omega0_s.size(), 48u);
  EXPECT_EQ(sc.rod.Omega0_s[1 * 16 + 5], 0.1 + 5);  // component 1 at point 5
  std::string m =
      error_of("[rod]\nlength = 6.0\npoints = 20\nintrinsic_file = \"shape.h5\"\n", {}, dir.path.string());
  EXPECT_NE(m.find("rod.intrinsic_file"), std::string::npos) << m;
  EXPECT_NE(m.find("expected 20 x 3"), std::string::npos) << m;
  m = error_of(kMinimal + "intrinsic_file = \"shape.h5\"\nGamma0 = [0.0, 0.0, 1.0]\n", {}, dir.path.string());
  EXPECT_NE(m.find("not both"), std::string::npos) << m;
}

TEST(IoSceneReader, InitialParametersFollowTheRegistry) {
  // Validated against each kind's own ParamSpec table, whatever it holds.
  for (const auto& kind : initial_kinds()) {
    if (kind.name == "file") continue;
    std::string base =
        "[rod]\nlength = 6.283185307179586\npoints = 32\n[initial]\nkind = \"" + kind.name + "\"\n";
    std::string required;
    for (const auto& p : kind.numbers)
      if (std::isnan(p.default_value)) {
        double v = std::isfinite(p.min) ? p.min : (std::isfinite(p.max) ? p.max : 0.5);
        required += p.name + " = " + std::to_string(v) + "\n";
      }
    for (const auto& p : kind.numbers) {
      if (std::isnan(p.default_value)) {
        std::string m = error_of(base);  // nothing given: the first required one is named
        EXPECT_NE(m.find("is required for initial.kind = \"" + kind.name + "\""), std::string::npos) << m;
      }
      if (std::isfinite(p.min)) {
        std::string text = base + required;
        // Replace or add the parameter with a value below its minimum.
        std::string below = p.name + " = " + std::to_string(p.min - 1.0 - std::abs(p.min)) + "\n";
        std::string without;
        std::istringstream lines(text);
        for (std::string line; std::getline(lines, line);)
          if (line.rfind(p.name + " = ", 0) != 0) without += line + "\n";
        std::string m = error_of(without + below);
        EXPECT_NE(m.find("initial." + p.name + ": found"), std::string::npos) << kind.name << ": " << m;
        EXPECT_NE(m.find(">= "), std::string::npos) << m;
      }
    }
    for (const auto& c : kind.strings) {
      std::string m = error_of(base + required + c.name + " = \"no-such-choice\"\n");
      EXPECT_NE(m.find("initial." + c.name + ": found \"no-such-choice\""), std::string::npos) << m;
    }
    std::string m = error_of(base + required + "no_such_parameter = 1\n");
    EXPECT_NE(m.find("initial.no_such_parameter"), std::string::npos) << m;
  }
  std::string m = error_of(kMinimal + "[initial]\nkind = \"twisted_wav\"\n");
  EXPECT_NE(m.find("initial.kind: found \"twisted_wav\""), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean \"twisted_wave\"?"), std::string::npos) << m;
}

TEST(IoSceneReader, OverridesAreAppliedAndValidated) {
  Scene sc = read_scene_string(
      kMinimal, "scene.toml", ".",
      {"solver.rtol=1e-8", "solver.space=fd4", "output.fields=[\"energy\"]", "rod.points=20"});
  EXPECT_EQ(sc.solver.rtol, 1e-8);
  EXPECT_EQ(sc.solver.space, SpaceMethod::fd4);
  EXPECT_TRUE(sc.output.energy);
  EXPECT_FALSE(sc.output.internal);
  EXPECT_EQ(sc.rod.points, 20);
  std::string m = error_of(kMinimal, {"solver.rtoll=1e-8"});
  EXPECT_NE(m.find("solver.rtoll"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean solver.rtol?"), std::string::npos) << m;
  m = error_of(kMinimal, {"solver.rtol=2"});
  EXPECT_NE(m.find("--set solver.rtol: found 2"), std::string::npos) << m;
  m = error_of(kMinimal, {"rtol=1e-8"});
  EXPECT_NE(m.find("expected section.key=value"), std::string::npos) << m;
  m = error_of(kMinimal, {"solvr.rtol=1e-8"});
  EXPECT_NE(m.find("did you mean [solver]?"), std::string::npos) << m;
}

TEST(IoSceneReader, ResolvedSceneReadsBackIdentically) {
  std::string text =
      "[rod]\nlength = 6.283185307179586\npoints = 5\nOmega0 = [[0, 0, 0.1], [0, 0, 0.2], [0, 0, 0.3], [0, "
      "0, "
      "0.4], [0, 0, 0.7]]\n[material]\nD = [1.21, 1.21, 2.0207]\n[solver]\nspace = \"fd4\"\nrtol = 3e-9\n"
      "[output]\nt_end = 0.1\nframes = 7\nfields = [\"centerline\", \"energy_parts\"]\n"
      "[checks]\nmax_energy_drift = 1e-6\n";
  Scene a = read_scene_string(text);
  Scene b = read_scene_string(scene_to_toml(a));
  EXPECT_EQ(a.rod.length, b.rod.length);
  EXPECT_EQ(a.rod.points, b.rod.points);
  EXPECT_EQ(a.rod.Omega0_s, b.rod.Omega0_s);
  EXPECT_EQ(a.rod.Gamma0, b.rod.Gamma0);
  EXPECT_EQ(a.material.C, b.material.C);
  EXPECT_EQ(a.material.D, b.material.D);
  EXPECT_EQ(a.material.I, b.material.I);
  EXPECT_EQ(a.initial.kind, b.initial.kind);
  EXPECT_EQ(a.initial.numbers, b.initial.numbers);
  EXPECT_EQ(a.initial.strings, b.initial.strings);
  EXPECT_EQ(a.solver.space, b.solver.space);
  EXPECT_EQ(a.solver.rtol, b.solver.rtol);
  EXPECT_EQ(a.solver.atol, b.solver.atol);
  EXPECT_EQ(a.solver.dt_min, b.solver.dt_min);
  EXPECT_EQ(a.solver.max_steps, b.solver.max_steps);
  EXPECT_EQ(a.output.frames, b.output.frames);
  EXPECT_EQ(a.output.t_end, b.output.t_end);
  EXPECT_EQ(a.output.centerline, b.output.centerline);
  EXPECT_EQ(a.output.energy_parts, b.output.energy_parts);
  EXPECT_EQ(a.output.internal, b.output.internal);
  EXPECT_EQ(a.checks.max_energy_drift, b.checks.max_energy_drift);
  EXPECT_EQ(a.checks.max_director_norm_error, b.checks.max_director_norm_error);
  EXPECT_EQ(a.checks.stop_on_fold, b.checks.stop_on_fold);
  // Default (infinite) drift bound round-trips too.
  Scene c = read_scene_string(scene_to_toml(read_scene_string(kMinimal)));
  EXPECT_TRUE(std::isinf(c.checks.max_energy_drift));
}

TEST(IoSceneReader, ThermalSectionErrorsNameTheKey) {
  auto expect = [](const std::string& text, const std::string& want) {
    const std::string m = error_of(kMinimal + text);
    EXPECT_NE(m.find(want), std::string::npos) << m;
  };
  expect("[thermal]\nkT = -1\n",
         "scene.toml:5: thermal.kT: found -1; allowed: a number (energy in the material's "
         "units) >= 0");
  expect("[thermal]\ntemperature_K = -300\n",
         "thermal.temperature_K: found -300; allowed: a number [K] >= 0");
  expect("[thermal]\nkT = 1e-3\ntemperature_K = 300\n",
         "thermal.temperature_K: give either thermal.kT (energy in the material's units) or "
         "thermal.temperature_K (DNA units), not both");
  expect("[thermal]\nfriction_translational = 1.0\n",
         "thermal.friction_translational: a friction needs a temperature: give thermal.kT");
  expect("[thermal]\nseed = 3\n", "thermal.kT: [thermal] needs thermal.kT");
  expect("[thermal]\nkT = 1e-3\nfriction_rotational = [1.0]\n",
         "thermal.friction_rotational: found an array of 1 value(s); allowed: a number >= 0 (about the axis, "
         "across alike), an array [about the axis, across]");
  expect("[thermal]\nkT = 1e-3\nfriction_translational = \"oil\"\n",
         "thermal.friction_translational: found \"oil\"; allowed: one of \"water\"");
  expect("[thermal]\nkT = 1e-3\nviscosity_mPa_s = 1.0\n",
         "thermal.viscosity_mPa_s: is used only by a \"water\"");
  // noise with an integrator that cannot carry it; langevin without [thermal]; energy drift
  expect("[solver]\ntime = \"dop853\"\n[thermal]\nkT = 1e-3\nfriction_translational = 1.0\n",
         "scene.toml:5: solver.time: \"dop853\" cannot carry the friction and noise of [thermal]");
  expect("[solver]\ntime = \"langevin\"\n",
         "solver.time: \"langevin\" is the Langevin rod of a [thermal] section");
  expect("[checks]\nmax_energy_drift = 1e-6\n[thermal]\nkT = 1e-3\nfriction_translational = 1.0\n",
         "checks.max_energy_drift: the Langevin rod exchanges energy with its bath");
  expect("[solver]\ndt = 0.3\n[thermal]\nkT = 1e-3\nfriction_translational = 1.0\n",
         "solver.dt: the Langevin rod steps with a fixed solver.dt = 0.3, which must divide the output "
         "interval");
  // "water" needs a rod at least 4 radii long (6 rod lengths = 3 nm)
  expect("[thermal]\nkT = 1e-3\nfriction_translational = \"water\"\nradius_nm = 1.0\n",
         "thermal.friction_translational: the \"water\" friction needs a rod at least 4 radii long");
  // the key in the wrong section is placed
  expect("[solver]\nseed = 3\n", "seed belongs in [thermal]");
}

TEST(IoSceneReader, ThermalSectionResolvesAndReadsBack) {
  const Scene plain = read_scene_string(kMinimal, "scene.toml", ".", {});
  EXPECT_FALSE(plain.thermal.on);
  EXPECT_EQ(scene_to_toml(plain).find("[thermal]"), std::string::npos);  // a cold scene is as before
  const Scene sc = read_scene_string(
      "[rod]\nlength = 30.0\npoints = 16\n[solver]\ndt = 0.05\n[thermal]\ntemperature_K = 300\n"
      "friction_translational = \"water\"\nfriction_rotational = [2.0, 1.0]\nseed = 9\n",
      "scene.toml", ".", {});
  EXPECT_TRUE(sc.thermal.on);
  EXPECT_NEAR(sc.thermal.kT, 0.009123, 1e-6);  // k_B 300 K / (C l), notes-science.md
  EXPECT_TRUE(sc.thermal.translational_water);
  EXPECT_GT(sc.thermal.friction_translational[1], sc.thermal.friction_translational[0]);
  EXPECT_EQ(sc.thermal.friction_rotational[0], 2.0);
  EXPECT_EQ(sc.thermal.seed, 9u);
  const Scene again = read_scene_string(scene_to_toml(sc), "resolved.toml", ".", {});
  auto body = [](const std::string& t) { return t.substr(t.find('\n')); };  // without the "from" line
  EXPECT_EQ(body(scene_to_toml(again)), body(scene_to_toml(sc)));
  EXPECT_EQ(again.thermal.friction_translational, sc.thermal.friction_translational);
}
