// HDF5 output: what is written is what the frames held (in the documented
// layout), the attributes describe the run, and frames already flushed stay
// readable when the writer dies (process killed) or the run fails.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/h5_output.hpp"
#include "rodcore/state.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace rodcore;

namespace {

Scene small_scene(bool everything) {
  Scene sc;
  sc.source = "test";
  sc.rod.length = 2.5;
  sc.rod.points = 6;
  sc.rod.Omega0 = {0.0, 0.0, 0.75};
  sc.material.C = {1.0, 1.0, 1.19};
  sc.solver.rtol = 1e-9;
  sc.output.t_end = 1.0;
  sc.output.frames = 3;
  sc.output.internal = true;
  sc.output.energy = everything;
  sc.output.energy_parts = everything;
  sc.output.centerline = everything;
  sc.output.directors = everything;
  sc.initial.kind = InitialKind::rest;
  sc.initial.numbers["v1"] = 0.25;
  return sc;
}

// Synthetic frame k: every value encodes (k, row, point, ...) so any
// transposition or off-by-one shows.
struct FakeFrame {
  std::vector<double> y, centerline, directors;
  Frame frame;
  FakeFrame(int k, std::size_t N) : y(12 * N), centerline(3 * N), directors(9 * N) {
    for (int r = 0; r < 12; ++r)
      for (std::size_t i = 0; i < N; ++i) y[r * N + i] = 1000.0 * k + 10.0 * r + 0.01 * i;
    for (std::size_t q = 0; q < 3 * N; ++q) centerline[q] = -1000.0 * k - q;
    for (std::size_t q = 0; q < 9 * N; ++q) directors[q] = 0.5 * k + 0.001 * q;
    frame.index = k;
    frame.t = 0.5 * k;
    frame.N = N;
    frame.y = y.data();
    frame.energy = 3.0 + k;
    frame.energy_parts = {{"bend", 1.0 + k}, {"shear", 2.0 * k}};
    frame.centerline = centerline.data();
    frame.directors = directors.data();
  }
};

std::vector<double> grid(std::size_t N, double L) {
  std::vector<double> s(N);
  for (std::size_t i = 0; i < N; ++i) s[i] = i * L / N;
  return s;
}

// Reads a whole dataset (any rank) as doubles, with its shape.
std::vector<double> read(hid_t f, const std::string& name, std::vector<hsize_t>& dims) {
  hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  hid_t sp = H5Dget_space(d);
  dims.resize(H5Sget_simple_extent_ndims(sp));
  H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<double> v(n);
  if (n) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(sp);
  H5Dclose(d);
  return v;
}
std::vector<double> attr_doubles(hid_t f, const std::string& name) {
  hid_t a = H5Aopen(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(a, 0) << name;
  hid_t sp = H5Aget_space(a);
  hssize_t n = H5Sget_simple_extent_npoints(sp);
  std::vector<double> v(n);
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Sclose(sp);
  H5Aclose(a);
  return v;
}
std::string attr_string(hid_t f, const std::string& name) {
  hid_t a = H5Aopen(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(a, 0) << name;
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char* p = nullptr;
  H5Aread(a, t, &p);
  std::string s = p ? p : "";
  H5free_memory(p);
  H5Tclose(t);
  H5Aclose(a);
  return s;
}

void expect_frames(hid_t f, int T, std::size_t N, bool everything) {
  std::vector<hsize_t> dims;
  auto time = read(f, "time", dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{hsize_t(T)}));
  for (int k = 0; k < T; ++k) EXPECT_EQ(time[k], 0.5 * k);
  for (int fi = 0; fi < 4; ++fi) {
    auto v = read(f, std::string("fields/") + kFieldNames[fi], dims);
    ASSERT_EQ(dims, (std::vector<hsize_t>{hsize_t(T), N, 3}));
    for (int k = 0; k < T; ++k)
      for (std::size_t i = 0; i < N; ++i)
        for (int c = 0; c < 3; ++c)  // (T x N x 3)[k][i][c] = component c of field fi at point i
          ASSERT_EQ(v[(k * N + i) * 3 + c], 1000.0 * k + 10.0 * (3 * fi + c) + 0.01 * i);
  }
  if (!everything) return;
  auto e = read(f, "energy", dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{hsize_t(T)}));
  for (int k = 0; k < T; ++k) EXPECT_EQ(e[k], 3.0 + k);
  auto bend = read(f, "energy_parts/bend", dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{hsize_t(T)}));
  for (int k = 0; k < T; ++k) EXPECT_EQ(bend[k], 1.0 + k);
  auto cl = read(f, "centerline", dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{hsize_t(T), N, 3}));
  for (int k = 0; k < T; ++k)
    for (std::size_t q = 0; q < 3 * N; ++q) ASSERT_EQ(cl[k * 3 * N + q], -1000.0 * k - q);
  auto dr = read(f, "directors", dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{hsize_t(T), N, 3, 3}));
  for (int k = 0; k < T; ++k)
    for (std::size_t q = 0; q < 9 * N; ++q) ASSERT_EQ(dr[k * 9 * N + q], 0.5 * k + 0.001 * q);
}

}  // namespace

TEST(IoH5Output, RoundTripLayoutAndAttributes) {
  TempDir dir;
  std::string out = (dir.path / "run.h5").string();
  Scene sc = small_scene(true);
  const std::size_t N = 6;
  {
    H5Output w(out, sc, grid(N, sc.rod.length));
    EXPECT_TRUE(fs::exists(out + ".partial"));
    EXPECT_FALSE(fs::exists(out));
    for (int k = 0; k < 3; ++k) w.write_frame(FakeFrame(k, N).frame);
    RunSummary sum;
    sum.steps = 42;
    sum.rejected = 3;
    sum.rhs_evaluations = 555;
    sum.energy_drift = 1.5e-14;
    sum.method = "spectral+dop853";
    w.finish(sum);
  }
  EXPECT_FALSE(fs::exists(out + ".partial"));
  hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  expect_frames(f, 3, N, true);
  std::vector<hsize_t> dims;
  EXPECT_EQ(read(f, "s", dims), grid(N, 2.5));
  EXPECT_EQ(attr_doubles(f, "complete"), std::vector<double>{1});
  EXPECT_EQ(attr_doubles(f, "tau_ps")[0], dna_units::tau_ps);
  EXPECT_EQ(attr_doubles(f, "ell_A")[0], dna_units::ell_A);
  EXPECT_EQ(attr_doubles(f, "velocity_A_per_ps")[0], dna_units::velocity_A_per_ps);
  EXPECT_EQ(attr_doubles(f, "rod.length")[0], 2.5);
  EXPECT_EQ(attr_doubles(f, "rod.points")[0], 6);
  EXPECT_EQ(attr_doubles(f, "rod.Omega0"), (std::vector<double>{0, 0, 0.75}));
  EXPECT_EQ(attr_doubles(f, "material.C"), (std::vector<double>{1, 1, 1.19}));
  EXPECT_EQ(attr_doubles(f, "solver.rtol")[0], 1e-9);
  EXPECT_EQ(attr_string(f, "solver.space"),
            "auto");  // as given to H5Output (rodsim gives the resolved scene)
  EXPECT_EQ(attr_string(f, "initial.kind"), "rest");
  EXPECT_EQ(attr_doubles(f, "initial.v1")[0], 0.25);
  EXPECT_EQ(attr_doubles(f, "summary.steps")[0], 42);
  EXPECT_EQ(attr_doubles(f, "summary.rejected")[0], 3);
  EXPECT_EQ(attr_doubles(f, "summary.rhs_evaluations")[0], 555);
  EXPECT_EQ(attr_doubles(f, "summary.energy_drift")[0], 1.5e-14);
  EXPECT_EQ(attr_string(f, "git_revision"), git_revision());
  EXPECT_NE(attr_string(f, "scene").find("[solver]"), std::string::npos);
  EXPECT_EQ(attr_string(f, "rodcore_version"), kRodcoreVersion);
  H5Fclose(f);
}

TEST(IoH5Output, OnlyRequestedDatasetsExist) {
  TempDir dir;
  std::string out = (dir.path / "run.h5").string();
  Scene sc = small_scene(false);
  {
    H5Output w(out, sc, grid(6, sc.rod.length));
    w.write_frame(FakeFrame(0, 6).frame);
    w.finish(RunSummary{});
  }
  hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  expect_frames(f, 1, 6, false);
  for (const char* name : {"energy", "energy_parts", "centerline", "directors"})
    EXPECT_EQ(H5Lexists(f, name, H5P_DEFAULT), 0) << name;
  H5Fclose(f);
}

TEST(IoH5Output, KilledWriterLeavesFlushedFramesReadable) {
  TempDir dir;
  std::string out = (dir.path / "run.h5").string();
  Scene sc = small_scene(true);
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // The child writes two frames and dies without closing anything.
    H5Output w(out, sc, grid(6, sc.rod.length));
    w.write_frame(FakeFrame(0, 6).frame);
    w.write_frame(FakeFrame(1, 6).frame);
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(out + ".partial"));
  hid_t f = H5Fopen((out + ".partial").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  expect_frames(f, 2, 6, true);
  EXPECT_EQ(attr_doubles(f, "complete"), std::vector<double>{0});
  H5Fclose(f);
}

TEST(IoH5Output, FramesAreReadableWhileTheWriterIsOpen) {
  TempDir dir;
  std::string out = (dir.path / "run.h5").string();
  Scene sc = small_scene(false);
  H5Output w(out, sc, grid(6, sc.rod.length));
  w.write_frame(FakeFrame(0, 6).frame);
  w.write_frame(FakeFrame(1, 6).frame);
  // A second reader of the same file (no locking), while the writer is open.
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_file_locking(fapl, 0, 1);
  hid_t f = H5Fopen((out + ".partial").c_str(), H5F_ACC_RDONLY, fapl);
  ASSERT_GE(f, 0);
  expect_frames(f, 2, 6, false);
  H5Fclose(f);
  H5Pclose(fapl);
  w.write_frame(FakeFrame(2, 6).frame);
  w.finish(RunSummary{});
  f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  expect_frames(f, 3, 6, false);
  H5Fclose(f);
}

TEST(IoH5Output, FailureKeepsFramesAndRecordsTheError) {
  TempDir dir;
  std::string out = (dir.path / "run.h5").string();
  Scene sc = small_scene(true);
  {
    H5Output w(out, sc, grid(6, sc.rod.length));
    w.write_frame(FakeFrame(0, 6).frame);
    w.fail("NaN in gamma at s = 1, t = 0.7");
  }
  EXPECT_FALSE(fs::exists(out + ".partial"));
  hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  expect_frames(f, 1, 6, true);
  EXPECT_EQ(attr_doubles(f, "complete"), std::vector<double>{0});
  EXPECT_EQ(attr_string(f, "error"), "NaN in gamma at s = 1, t = 0.7");
  H5Fclose(f);
}

TEST(IoH5Output, LongTextGoesToADataset) {
  TempDir dir;
  std::string out = (dir.path / "run.h5").string();
  Scene sc = small_scene(false);
  std::string big(100000, 'x');  // beyond the 64 KiB an attribute can hold
  {
    H5Output w(out, sc, grid(6, sc.rod.length));
    w.annotate("short_note", "hello");
    w.annotate("scene_file", big);
    w.finish(RunSummary{});
  }
  hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_EQ(attr_string(f, "short_note"), "hello");
  EXPECT_NE(attr_string(f, "scene_file").find("see the string dataset /scene_file"), std::string::npos);
  hid_t d = H5Dopen2(f, "scene_file", H5P_DEFAULT);
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char* p = nullptr;
  H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p);
  EXPECT_EQ(std::string(p), big);
  H5free_memory(p);
  H5Tclose(t);
  H5Dclose(d);
  H5Fclose(f);
}

TEST(IoH5Output, UnwritableFolderIsAnInputError) {
  Scene sc = small_scene(false);
  try {
    H5Output w("/nonexistent-folder-xyz/run.h5", sc, grid(6, sc.rod.length));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder-xyz/run.h5.partial"), std::string::npos)
        << e.what();
  }
}
