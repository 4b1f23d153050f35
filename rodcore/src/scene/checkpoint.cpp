// Checkpoint files and the observer that writes them (checkpoint.hpp).
#include "rodcore/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "h5_handle.hpp"
#include "rodcore/scene_reader.hpp"
#include "rodcore/simulation.hpp"

namespace rodcore {
namespace {

// ------------------------------------------------------------ HDF5 helpers
void put_attr(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type, const void* v) {
  auto sp = h5::space(H5Screate(H5S_SCALAR));
  auto a = h5::attribute(H5Acreate2(loc, name.c_str(), file_type, sp, H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid() || H5Awrite(a, mem_type, v) < 0) throw Error("checkpoint: cannot write attribute " + name);
}
void put(hid_t loc, const std::string& name, double v) {
  put_attr(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
}
void put(hid_t loc, const std::string& name, long long v) {
  put_attr(loc, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &v);
}
void put(hid_t loc, const std::string& name, const std::string& v) {
  auto t = h5::type(H5Tcopy(H5T_C_S1));
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  const char* p = v.c_str();
  put_attr(loc, name, t, t, &p);
}
void put(hid_t loc, const std::string& name, const std::vector<double>& v) {
  hsize_t n = v.size();
  auto sp = h5::space(n == 0 ? H5Screate(H5S_NULL) : H5Screate_simple(1, &n, nullptr));
  auto d =
      h5::dataset(H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  if (!d.valid() || (n > 0 && H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0))
    throw Error("checkpoint: cannot write dataset " + name);
}

struct Reader {
  hid_t file;
  std::string path;
  [[noreturn]] void bad(const std::string& what) const {
    throw InputError("checkpoint '" + path + "': " + what +
                     " (the file is damaged or not a rodsim checkpoint; delete it and run without --resume)");
  }
  h5::Handle attribute(const std::string& name, H5T_class_t cls) const {
    if (H5Aexists(file, name.c_str()) <= 0) bad("missing attribute '" + name + "'");
    auto a = h5::attribute(H5Aopen(file, name.c_str(), H5P_DEFAULT));
    auto t = h5::type(H5Aget_type(a));
    auto sp = h5::space(H5Aget_space(a));
    if (!a.valid() || H5Tget_class(t) != cls || H5Sget_simple_extent_type(sp) != H5S_SCALAR)
      bad("attribute '" + name + "' has the wrong type");
    return a;
  }
  double number(const std::string& name) const {
    double v = 0.0;
    auto a = attribute(name, H5T_FLOAT);
    if (H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0) bad("attribute '" + name + "' cannot be read");
    return v;
  }
  long long integer(const std::string& name) const {
    long long v = 0;
    auto a = attribute(name, H5T_INTEGER);
    if (H5Aread(a, H5T_NATIVE_LLONG, &v) < 0) bad("attribute '" + name + "' cannot be read");
    return v;
  }
  std::string text(const std::string& name) const {
    auto a = attribute(name, H5T_STRING);
    auto t = h5::type(H5Aget_type(a));
    if (H5Tis_variable_str(t) <= 0) bad("attribute '" + name + "' is not a variable-length string");
    char* p = nullptr;
    auto mt = h5::type(H5Tcopy(H5T_C_S1));
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5T_CSET_UTF8);
    if (H5Aread(a, mt, &p) < 0 || !p) bad("attribute '" + name + "' cannot be read");
    std::string s(p);
    H5free_memory(p);
    return s;
  }
  std::vector<double> doubles(const std::string& name) const {
    if (!h5::exists(file, name)) bad("missing dataset '" + name + "'");
    auto d = h5::dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
    if (!d.valid()) bad("'" + name + "' is not a dataset");
    auto sp = h5::space(H5Dget_space(d));
    if (H5Sget_simple_extent_type(sp) == H5S_NULL) return {};
    if (H5Sget_simple_extent_ndims(sp) != 1) bad("dataset '" + name + "' is not one-dimensional");
    hsize_t n = 0;
    H5Sget_simple_extent_dims(sp, &n, nullptr);
    std::vector<double> v(n);
    if (n > 0 && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      bad("dataset '" + name + "' cannot be read");
    return v;
  }
};

// Make the bytes of `path` durable before the rename publishes them.
void sync_file(const std::string& path) {
  int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw Error("checkpoint: cannot reopen '" + path + "' to sync it");
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw Error("checkpoint: cannot sync '" + path + "' to disk");
}

}  // namespace

std::string checkpoint_path(const std::string& output_path) { return output_path + ".ckpt"; }

std::string checkpoint_scene_text(const Scene& scene) {
  Scene s = scene;
  s.output.checkpoint_interval_s = 0.0;
  return scene_to_toml(s);
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  h5::QuietErrors quiet;
  const std::string tmp = path + ".tmp";
  {
    auto f = h5::file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
    if (!f.valid()) throw Error("cannot create checkpoint file '" + tmp + "' (is the folder writable?)");
    put(f, "format", static_cast<long long>(kCheckpointFormat));
    put(f, "scene", c.scene);
    put(f, "method", to_string(c.method));
    put(f, "t", c.integrator.t);
    put(f, "dt_next", c.integrator.dt_next);
    put(f, "next_frame", static_cast<long long>(c.next_frame));
    put(f, "E0", c.E0);
    put(f, "energy_drift", c.energy_drift);
    put(f, "wall_seconds", c.wall_seconds);
    put(f, "reduced", c.reduced);
    put(f, "steps", static_cast<long long>(c.integrator.steps));
    put(f, "rejected", static_cast<long long>(c.integrator.rejected));
    put(f, "rhs_evaluations", static_cast<long long>(c.integrator.rhs_evaluations));
    put(f, "y", c.integrator.y);
    put(f, "f", c.integrator.f);
    put(f, "controller", c.integrator.controller);
    if (H5Fflush(f, H5F_SCOPE_GLOBAL) < 0) throw Error("checkpoint: cannot flush '" + tmp + "'");
  }
  sync_file(tmp);
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw Error("cannot rename checkpoint '" + tmp + "' to '" + path + "': " + ec.message());
}

Checkpoint read_checkpoint(const std::string& path) {
  h5::QuietErrors quiet;
  if (!std::filesystem::exists(path)) throw InputError("checkpoint '" + path + "' does not exist");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError("checkpoint '" + path +
                     "' is not an HDF5 file (damaged?); delete it and run without --resume");
  auto f = h5::file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) throw InputError("checkpoint '" + path + "' cannot be opened");
  Reader r{f, path};
  const long long format = r.integer("format");
  if (format != kCheckpointFormat)
    throw InputError("checkpoint '" + path + "' has format " + std::to_string(format) +
                     "; this rodsim reads format " + std::to_string(kCheckpointFormat) +
                     " (resume with the rodsim that wrote it)");
  Checkpoint c;
  c.scene = r.text("scene");
  const std::string method = r.text("method");
  const auto time = from_string<TimeMethod>(method);
  if (!time || *time == TimeMethod::automatic)
    r.bad("attribute 'method' = \"" + method + "\" is not a time integrator");
  c.method = *time;
  c.integrator.t = r.number("t");
  c.integrator.dt_next = r.number("dt_next");
  c.next_frame = static_cast<int>(r.integer("next_frame"));
  c.E0 = r.number("E0");
  c.energy_drift = r.number("energy_drift");
  c.wall_seconds = r.number("wall_seconds");
  // Written since the reduced planar system; absent = full system.
  if (H5Aexists(f, "reduced") > 0) c.reduced = r.text("reduced");
  if (c.reduced != "" && c.reduced != "omega2" && c.reduced != "omega1")
    r.bad("attribute 'reduced' must be \"\", \"omega2\" or \"omega1\"");
  c.integrator.steps = r.integer("steps");
  c.integrator.rejected = r.integer("rejected");
  c.integrator.rhs_evaluations = r.integer("rhs_evaluations");
  c.integrator.y = r.doubles("y");
  c.integrator.f = r.doubles("f");
  c.integrator.controller = r.doubles("controller");
  if (c.integrator.y.empty() || c.integrator.y.size() != c.integrator.f.size())
    r.bad("datasets 'y' and 'f' must be non-empty and of equal length");
  if (!std::isfinite(c.integrator.t) || !(c.integrator.dt_next > 0.0) || c.next_frame < 1 ||
      !std::isfinite(c.E0))
    r.bad("t, dt_next, next_frame or E0 out of range");
  for (double v : c.integrator.y)
    if (!std::isfinite(v)) r.bad("non-finite value in 'y'");
  return c;
}

void check_checkpoint_matches(const Checkpoint& c, const Scene& scene, const std::string& file) {
  const std::string now = checkpoint_scene_text(scene);
  if (now == c.scene) return;
  std::istringstream a(c.scene), b(now);
  std::string la, lb;
  int line = 0;
  while (true) {
    ++line;
    const bool ga = static_cast<bool>(std::getline(a, la)), gb = static_cast<bool>(std::getline(b, lb));
    if (!ga && !gb) break;
    if (!ga) la = "(end)";
    if (!gb) lb = "(end)";
    if (la != lb) break;
  }
  throw InputError("checkpoint '" + file + "' was written by a run of a different scene: resolved line " +
                   std::to_string(line) + " is '" + la + "' in the checkpoint but '" + lb +
                   "' now. Resume with the same scene and --set options, or run again without --resume.");
}

CheckpointObserver::CheckpointObserver(std::function<bool()> due, std::function<void(const Checkpoint&)> save)
    : due_(std::move(due)), save_(std::move(save)) {}

void CheckpointObserver::stepped(const Simulation& sim) {
  if (sim.frames_delivered() >= sim.scene().output.frames || !due_ || !due_()) return;
  save(sim.checkpoint());
}

void CheckpointObserver::save(const Checkpoint& c) {
  if (save_) save_(c);
}

CheckpointWriter::CheckpointWriter(std::string path, std::function<bool()> due,
                                   std::function<void(const Checkpoint&)> written)
    : CheckpointObserver(std::move(due), {}), path_(std::move(path)), written_(std::move(written)) {}

void CheckpointWriter::save(const Checkpoint& c) {
  write_checkpoint(path_, c);
  if (written_) written_(c);
}

void CheckpointWriter::finished(const Simulation&, const RunSummary&) {
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

void CheckpointWriter::failed(const Simulation&, const std::string&) {
  std::error_code ec;
  std::filesystem::remove(path_, ec);  // continuing would meet the same error
}

}  // namespace rodcore
