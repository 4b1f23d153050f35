// Writing a run to HDF5, frame by frame, so that a crash or a numerical
// error mid-run still leaves every frame written so far readable.
#include "rodcore/h5_output.hpp"

#include <cmath>
#include <filesystem>

#include "h5_handle.hpp"
#include "rodcore/contact.hpp"
#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/scene_reader.hpp"
#include "rodcore/scene_section.hpp"
#include "rodcore/state.hpp"

#ifndef DNAROD_GIT_REVISION
#define DNAROD_GIT_REVISION "unknown"
#endif

namespace rodcore {

const char* git_revision() { return DNAROD_GIT_REVISION; }

namespace {

// Attributes larger than this do not fit an HDF5 object header (64 KiB).
constexpr std::size_t kMaxAttributeBytes = 60000;

void attr_doubles(hid_t loc, const std::string& name, const double* v, hsize_t n, bool scalar = false) {
  auto sp = h5::space(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr));
  if (H5Aexists(loc, name.c_str()) > 0) H5Adelete(loc, name.c_str());
  auto a = h5::attribute(H5Acreate2(loc, name.c_str(), H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid() || H5Awrite(a, H5T_NATIVE_DOUBLE, v) < 0)
    throw Error("HDF5: cannot write attribute " + name);
}
void attr(hid_t loc, const std::string& name, double v) { attr_doubles(loc, name, &v, 1, true); }
void attr(hid_t loc, const std::string& name, const Vec3& v) { attr_doubles(loc, name, v.data(), 3); }
void attr_int(hid_t loc, const std::string& name, long long v) {
  auto sp = h5::space(H5Screate(H5S_SCALAR));
  if (H5Aexists(loc, name.c_str()) > 0) H5Adelete(loc, name.c_str());
  auto a = h5::attribute(H5Acreate2(loc, name.c_str(), H5T_STD_I64LE, sp, H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid() || H5Awrite(a, H5T_NATIVE_LLONG, &v) < 0)
    throw Error("HDF5: cannot write attribute " + name);
}
// Variable-length UTF-8 strings: h5py reads them as Python str.
h5::Handle vlen_string_type() {
  auto t = h5::type(H5Tcopy(H5T_C_S1));
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}
void attr(hid_t loc, const std::string& name, const std::string& v) {
  auto t = vlen_string_type();
  auto sp = h5::space(H5Screate(H5S_SCALAR));
  if (H5Aexists(loc, name.c_str()) > 0) H5Adelete(loc, name.c_str());
  auto a = h5::attribute(H5Acreate2(loc, name.c_str(), t, sp, H5P_DEFAULT, H5P_DEFAULT));
  const char* p = v.c_str();
  if (!a.valid() || H5Awrite(a, t, &p) < 0) throw Error("HDF5: cannot write attribute " + name);
}
void string_dataset(hid_t loc, const std::string& name, const std::string& v) {
  auto t = vlen_string_type();
  auto sp = h5::space(H5Screate(H5S_SCALAR));
  auto d = h5::dataset(H5Dcreate2(loc, name.c_str(), t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  const char* p = v.c_str();
  if (!d.valid() || H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0)
    throw Error("HDF5: cannot write dataset " + name);
}
void fixed_dataset(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims, const double* v) {
  auto lcpl = h5::plist(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl, 1);
  auto sp = h5::space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  auto d = h5::dataset(H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT));
  if (!d.valid() || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) < 0)
    throw Error("HDF5: cannot write dataset " + name);
}

void write_scene_attributes(hid_t f, const Scene& sc) {
  attr(f, "tau_ps", dna_units::tau_ps);
  attr(f, "ell_A", dna_units::ell_A);
  attr(f, "velocity_A_per_ps", dna_units::velocity_A_per_ps);
  attr(f, "units",
       std::string("dimensionless (paper Sec 2.2): time in tau_ps ps, length in ell_A Angstrom, "
                   "velocity in velocity_A_per_ps Angstrom/ps"));
  attr(f, "rod.length", sc.rod.length);
  attr_int(f, "rod.points", sc.rod.points);
  attr(f, "rod.Gamma0", sc.rod.Gamma0);
  attr(f, "rod.Omega0", sc.rod.Omega0);
  attr(f, "rod.intrinsic",
       std::string(sc.rod.Gamma0_s.empty() && sc.rod.Omega0_s.empty()
                       ? "uniform"
                       : "varying along s: datasets intrinsic/Gamma0, intrinsic/Omega0"));
  const auto N = static_cast<std::size_t>(sc.rod.points);
  for (auto [name, prof, uni] : {std::tuple{"intrinsic/Gamma0", &sc.rod.Gamma0_s, sc.rod.Gamma0},
                                 std::tuple{"intrinsic/Omega0", &sc.rod.Omega0_s, sc.rod.Omega0}}) {
    if (sc.rod.Gamma0_s.empty() && sc.rod.Omega0_s.empty()) break;
    std::vector<double> rows(3 * N);
    for (std::size_t i = 0; i < N; ++i)
      for (int c = 0; c < 3; ++c) rows[3 * i + c] = prof->empty() ? uni[c] : (*prof)[c * N + i];
    fixed_dataset(f, name, {N, 3}, rows.data());
  }
  attr(f, "material.C", sc.material.C);
  attr(f, "material.D", sc.material.D);
  attr(f, "material.I", sc.material.I);
  attr(f, "material.rho", sc.material.rho);
  // The general material (material.hpp): a full K / I row-major (36 / 9
  // values), or the per-point file (its path; the data stay in that file).
  if (!sc.material.K.empty()) attr_doubles(f, "material.K", sc.material.K.data(), 36);
  if (!sc.material.I_full.empty()) attr_doubles(f, "material.I_full", sc.material.I_full.data(), 9);
  if (!sc.material.file.empty()) attr(f, "material.material_file", sc.material.file);
  attr(f, "solver.space", to_string(sc.solver.space));
  attr_int(f, "solver.dealias", sc.solver.dealias);
  attr(f, "solver.time", to_string(sc.solver.time));
  attr(f, "solver.rtol", sc.solver.rtol);
  attr(f, "solver.atol", sc.solver.atol);
  attr(f, "solver.dt", sc.solver.dt);
  attr(f, "solver.reduce", to_string(sc.solver.reduce));
  attr(f, "output.t_end", sc.output.t_end);
  attr_int(f, "output.frames", sc.output.frames);
  if (sc.thermal.on) {  // docs/thermal.md; absent from a scene without [thermal]
    const Thermal& t = sc.thermal;
    attr(f, "kT", t.kT);
    if (!std::isnan(t.temperature_K)) attr(f, "temperature_K", t.temperature_K);
    attr_int(f, "thermal.seed", static_cast<long long>(t.seed));
    attr_int(f, "thermal.sample_initial", t.sample_initial);
    attr_int(f, "thermal.keep_closure", t.keep_closure);
    attr(f, "thermal.closure_interval", t.closure_interval);
    attr_doubles(f, "thermal.friction_translational", t.friction_translational.data(), 2);
    attr_doubles(f, "thermal.friction_rotational", t.friction_rotational.data(), 2);
    attr(f, "thermal.friction_model",
         std::string(t.translational_water || t.rotational_water
                         ? "water: viscosity " + toml_num(t.viscosity_mPa_s) + " mPa s, radius " +
                               toml_num(t.radius_nm) + " nm, length of the motion " +
                               toml_num(t.friction_length_nm) + " nm (docs/thermal.md)"
                         : "given"));
  }
  if (sc.contact.on) {  // docs/topology.md, "Self-contact"; absent from a scene without [contact]
    const Contact& c = sc.contact;
    const ContactPotential p = contact_potential(c);
    attr(f, "contact.diameter", c.diameter);
    if (!std::isnan(c.diameter_nm)) attr(f, "contact.diameter_nm", c.diameter_nm);
    attr(f, "contact.barrier_kT", c.barrier_kT);
    attr(f, "contact.kT", c.kT);
    attr_int(f, "contact.stride", c.stride);
    attr(f, "contact.cutoff", p.cutoff);
    attr(f, "contact.psi0", p.psi0);
    attr(f, "contact.exclude", p.exclude);
  }
  attr(f, "initial.kind", to_string(sc.initial.kind));
  for (const auto& [k, v] : sc.initial.numbers) attr(f, "initial." + k, v);
  for (const auto& [k, v] : sc.initial.strings) attr(f, "initial." + k, v);
  if (!sc.initial.path.empty()) attr(f, "initial.path", sc.initial.path);
  std::string text = scene_to_toml(sc);
  if (text.size() <= kMaxAttributeBytes) {
    attr(f, "scene", text);
  } else {
    string_dataset(f, "scene", text);
    attr(f, "scene", std::string("(too long for an attribute: see the string dataset /scene)"));
  }
  attr(f, "scene_source", sc.source);
  attr(f, "git_revision", std::string(git_revision()));
  attr(f, "rodcore_version", std::string(kRodcoreVersion));
  attr_int(f, "complete", 0);
}

// The per-frame topology of a closed rod, and what counts as an Lk jump: a change of
// the integer, or a frame whose Lk could not be resolved (NaN) after one that was.
constexpr const char* kTopology[3] = {"Lk", "Tw", "Wr"};
long is_jump(double before, double after) {
  if (std::isnan(before) && std::isnan(after)) return 0;
  return before != after ? 1 : 0;
}

}  // namespace

H5Output::H5Output(const std::string& path, const Scene& scene, const std::vector<double>& s)
    : path_(path), want_(scene.output), thermal_(scene.thermal.on), N_(s.size()), row_(9 * s.size()) {
  h5::QuietErrors quiet;
  // No file locking: a second process (h5py) may read the frames while we write.
  auto fapl = h5::plist(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_file_locking(fapl, 0, 1);
  file_ = H5Fcreate(partial_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  if (file_ < 0)
    throw InputError("cannot create output file '" + partial_path() +
                     "' (does the folder exist, is it writable?)");
  try {
    write_scene_attributes(file_, scene);
    fixed_dataset(file_, "s", {N_}, s.data());
    time_ = extendible("time", {});
    if (want_.internal)
      for (const char* name : kFieldNames)
        fields_.push_back(extendible(std::string("fields/") + name, {N_, 3}));
    if (want_.energy) energy_ = extendible("energy", {});
    if (thermal_) kinetic_kT_ = extendible("kinetic_kT", {});
    if (want_.centerline) centerline_ = extendible("centerline", {N_, 3});
    if (want_.directors) directors_ = extendible("directors", {N_, 3, 3});
    H5Fflush(file_, H5F_SCOPE_GLOBAL);
  } catch (...) {
    H5Fclose(file_);
    file_ = H5I_INVALID_HID;
    throw;
  }
}

H5Output::H5Output(const std::string& path, const Scene& scene, const std::vector<double>& s, Resume resume)
    : path_(path), want_(scene.output), thermal_(scene.thermal.on), N_(s.size()), row_(9 * s.size()) {
  h5::QuietErrors quiet;
  const std::string p = partial_path();
  if (!std::filesystem::exists(p))
    throw InputError("cannot resume: '" + p + "' (the output of the interrupted run) does not exist");
  auto fapl = h5::plist(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_file_locking(fapl, 0, 1);
  file_ = H5Fopen(p.c_str(), H5F_ACC_RDWR, fapl);
  if (file_ < 0)
    throw InputError("cannot resume: '" + p +
                     "' cannot be opened as HDF5 (damaged by the kill?); "
                     "delete it and its .ckpt and run again without --resume");
  try {
    {
      auto d = h5::dataset(H5Dopen2(file_, "s", H5P_DEFAULT));
      auto sp = h5::space(d.valid() ? H5Dget_space(d) : H5I_INVALID_HID);
      hsize_t n = 0;
      if (sp.valid() && H5Sget_simple_extent_ndims(sp) == 1) H5Sget_simple_extent_dims(sp, &n, nullptr);
      if (n != N_)
        throw InputError("cannot resume: '" + p + "' has no grid 's' of " + std::to_string(N_) + " points");
    }
    time_ = reopen("time", resume.frames);
    if (want_.internal)
      for (const char* name : kFieldNames)
        fields_.push_back(reopen(std::string("fields/") + name, resume.frames));
    if (want_.energy) energy_ = reopen("energy", resume.frames);
    if (thermal_) kinetic_kT_ = reopen("kinetic_kT", resume.frames);
    if (want_.energy_parts) {
      auto g = h5::group(H5Gopen2(file_, "energy_parts", H5P_DEFAULT));
      H5G_info_t info{};
      if (!g.valid() || H5Gget_info(g, &info) < 0)
        throw InputError("cannot resume: '" + p + "' has no group 'energy_parts'");
      for (hsize_t k = 0; k < info.nlinks; ++k) {
        char name[256];
        if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT) < 0)
          throw InputError("cannot resume: '" + p + "': unreadable group 'energy_parts'");
        energy_parts_.emplace_back(name, reopen(std::string("energy_parts/") + name, resume.frames));
      }
    }
    if (want_.centerline) centerline_ = reopen("centerline", resume.frames);
    if (want_.directors) directors_ = reopen("directors", resume.frames);
    if (h5::exists(file_, "topology/Lk")) {
      for (const char* k : kTopology)
        topology_.push_back(reopen(std::string("topology/") + k, resume.frames));
      has_topology_ = true;
      std::vector<double> Lk(static_cast<std::size_t>(resume.frames));
      if (resume.frames > 0 &&
          H5Dread(topology_[0], H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, Lk.data()) < 0)
        throw InputError("cannot resume: '" + p + "': unreadable dataset 'topology/Lk'");
      for (std::size_t f = 1; f < Lk.size(); ++f) jumps_ += is_jump(Lk[f - 1], Lk[f]);
      if (!Lk.empty()) last_Lk_ = Lk.back();
    }
    frames_ = resume.frames;
    attr_int(file_, "complete", 0);
    H5Fflush(file_, H5F_SCOPE_GLOBAL);
  } catch (...) {
    for (hid_t d : fields_) H5Dclose(d);
    for (auto& [n, d] : energy_parts_) H5Dclose(d);
    for (hid_t d : topology_) H5Dclose(d);
    for (hid_t d : {time_, energy_, kinetic_kT_, centerline_, directors_})
      if (d >= 0) H5Dclose(d);
    H5Fclose(file_);
    file_ = H5I_INVALID_HID;
    throw;
  }
}

// Opens dataset `name` of a file being resumed and cuts it to `frames` rows.
hid_t H5Output::reopen(const std::string& name, int frames) {
  hid_t d = h5::exists(file_, name) ? H5Dopen2(file_, name.c_str(), H5P_DEFAULT) : H5I_INVALID_HID;
  if (d < 0) throw InputError("cannot resume: '" + partial_path() + "' has no dataset '" + name + "'");
  auto sp = h5::space(H5Dget_space(d));
  const int rank = H5Sget_simple_extent_ndims(sp);
  std::vector<hsize_t> dims(rank > 0 ? rank : 1, 0);
  if (rank > 0) H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
  if (rank < 1 || dims[0] < static_cast<hsize_t>(frames)) {
    H5Dclose(d);
    throw InputError("cannot resume: dataset '" + name + "' of '" + partial_path() + "' holds " +
                     std::to_string(rank < 1 ? 0 : dims[0]) + " frames, the checkpoint needs " +
                     std::to_string(frames));
  }
  dims[0] = static_cast<hsize_t>(frames);
  if (H5Dset_extent(d, dims.data()) < 0) {
    H5Dclose(d);
    throw Error("HDF5: cannot cut dataset '" + name + "' of '" + partial_path() + "' to " +
                std::to_string(frames) + " frames");
  }
  return d;
}

H5Output::~H5Output() {
  if (file_ >= 0) {
    for (hid_t d : fields_) H5Dclose(d);
    for (auto& [n, d] : energy_parts_) H5Dclose(d);
    for (hid_t d : topology_) H5Dclose(d);
    for (hid_t d : {time_, energy_, kinetic_kT_, centerline_, directors_})
      if (d >= 0) H5Dclose(d);
    H5Fclose(file_);
  }
}

// A dataset of rows of shape `row_dims`, growing along a first, unlimited axis.
hid_t H5Output::extendible(const std::string& name, std::vector<hsize_t> row_dims) {
  std::vector<hsize_t> dims{0}, maxdims{H5S_UNLIMITED}, chunk{1};
  hsize_t row = 1;
  for (auto d : row_dims) dims.push_back(d), maxdims.push_back(d), chunk.push_back(d), row *= d;
  // Scalars per frame: chunks of 1024 frames keep small series compact.
  if (row_dims.empty()) chunk[0] = 1024;
  auto sp = h5::space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data()));
  auto dcpl = h5::plist(H5Pcreate(H5P_DATASET_CREATE));
  H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
  auto lcpl = h5::plist(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t d = H5Dcreate2(file_, name.c_str(), H5T_IEEE_F64LE, sp, lcpl, dcpl, H5P_DEFAULT);
  if (d < 0) throw Error("HDF5: cannot create dataset " + name + " in '" + partial_path() + "'");
  return d;
}

// Grows `dataset` by one row and writes `row` there.
void H5Output::append(hid_t dataset, const double* row) {
  auto sp = h5::space(H5Dget_space(dataset));
  int rank = H5Sget_simple_extent_ndims(sp);
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = dims[0];
  count[0] = 1;
  dims[0] += 1;
  if (H5Dset_extent(dataset, dims.data()) < 0)
    throw Error("HDF5: cannot extend a dataset in '" + partial_path() + "'");
  auto fsp = h5::space(H5Dget_space(dataset));
  H5Sselect_hyperslab(fsp, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
  auto msp = h5::space(H5Screate_simple(rank, count.data(), nullptr));
  if (H5Dwrite(dataset, H5T_NATIVE_DOUBLE, msp, fsp, H5P_DEFAULT, row) < 0)
    throw Error("HDF5: cannot write a frame to '" + partial_path() + "'");
}

void H5Output::write_frame(const Frame& fr) {
  h5::QuietErrors quiet;
  if (fr.N != N_)
    throw Error("H5Output: frame has N = " + std::to_string(fr.N) + ", file has N = " + std::to_string(N_));
  if (want_.internal) {
    for (int f = 0; f < kFields; ++f) {
      for (int c = 0; c < 3; ++c) {
        const double* src = component(fr.y, N_, static_cast<Field>(f), c);
        for (std::size_t i = 0; i < N_; ++i) row_[3 * i + c] = src[i];
      }
      append(fields_[f], row_.data());
    }
  }
  if (want_.energy) {
    if (!fr.energy) throw Error("H5Output: the scene asks for energy but the frame has none");
    double e = *fr.energy;
    append(energy_, &e);
  }
  if (want_.energy_parts) {
    if (frames_ == 0)
      for (const auto& [name, v] : fr.energy_parts)
        energy_parts_.emplace_back(name, extendible("energy_parts/" + name, {}));
    for (auto& [name, d] : energy_parts_) {
      auto it = fr.energy_parts.find(name);
      if (it == fr.energy_parts.end()) throw Error("H5Output: frame lacks energy part " + name);
      append(d, &it->second);
    }
  }
  if (thermal_) {
    if (!fr.kinetic_kT) throw Error("H5Output: a thermal scene's frame has no kinetic_kT");
    double k = *fr.kinetic_kT;
    append(kinetic_kT_, &k);
  }
  if (want_.centerline) {
    if (!fr.centerline) throw Error("H5Output: the scene asks for the centerline but the frame has none");
    append(centerline_, fr.centerline);
  }
  if (want_.directors) {
    if (!fr.directors) throw Error("H5Output: the scene asks for directors but the frame has none");
    append(directors_, fr.directors);
  }
  if (fr.topology) {
    if (frames_ == 0)
      for (const char* k : kTopology) topology_.push_back(extendible(std::string("topology/") + k, {}));
    has_topology_ = true;
    if (topology_.empty()) throw Error("H5Output: a frame has topology, the first frame had none");
    const double v[3] = {fr.topology->Lk, fr.topology->Tw, fr.topology->Wr};
    for (int k = 0; k < 3; ++k) append(topology_[k], &v[k]);
    if (frames_ > 0) jumps_ += is_jump(last_Lk_, v[0]);
    last_Lk_ = v[0];
  }
  // Time last: len(time) counts only complete frames.
  append(time_, &fr.t);
  ++frames_;
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
}

void H5Output::close_and_rename() {
  for (hid_t d : fields_) H5Dclose(d);
  for (auto& [n, d] : energy_parts_) H5Dclose(d);
  for (hid_t d : topology_) H5Dclose(d);
  topology_.clear();
  for (hid_t d : {time_, energy_, kinetic_kT_, centerline_, directors_})
    if (d >= 0) H5Dclose(d);
  fields_.clear();
  energy_parts_.clear();
  time_ = energy_ = kinetic_kT_ = centerline_ = directors_ = H5I_INVALID_HID;
  H5Fclose(file_);
  file_ = H5I_INVALID_HID;
  std::error_code ec;
  std::filesystem::rename(partial_path(), path_, ec);
  if (ec) throw Error("cannot rename '" + partial_path() + "' to '" + path_ + "': " + ec.message());
}

void H5Output::finish(const RunSummary& sum) {
  h5::QuietErrors quiet;
  attr_int(file_, "summary.steps", sum.steps);
  attr_int(file_, "summary.rejected", sum.rejected);
  attr_int(file_, "summary.rhs_evaluations", sum.rhs_evaluations);
  attr(file_, "summary.wall_seconds", sum.wall_seconds);
  attr(file_, "summary.energy_drift", sum.energy_drift);
  attr(file_, "summary.method", sum.method);
  attr_int(file_, "summary.reduced", sum.reduced);
  attr(file_, "summary.reduce_note", sum.reduce_note);
  attr(file_, "summary.method_note", sum.method_note);
  if (!sum.thermal_note.empty()) attr(file_, "summary.thermal_note", sum.thermal_note);
  if (has_topology_) attr_int(file_, "topology_jumps", jumps_);
  attr_int(file_, "complete", 1);
  close_and_rename();
}

void H5Output::annotate(const std::string& name, const std::string& text) {
  h5::QuietErrors quiet;
  if (text.size() <= kMaxAttributeBytes) {
    attr(file_, name, text);
  } else {
    if (!h5::exists(file_, name)) string_dataset(file_, name, text);
    attr(file_, name, "(too long for an attribute: see the string dataset /" + name + ")");
  }
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
}

void H5Output::fail(const std::string& message) {
  h5::QuietErrors quiet;
  if (has_topology_) attr_int(file_, "topology_jumps", jumps_);
  attr_int(file_, "complete", 0);
  attr(file_, "error", message);
  close_and_rename();
}

}  // namespace rodcore
