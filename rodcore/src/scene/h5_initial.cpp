// Reading (and, for round trips, writing) initial fields in HDF5.
#include "rodcore/h5_initial.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "h5_handle.hpp"
#include "rodcore/error.hpp"
#include "rodcore/material.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/state.hpp"

namespace rodcore {
namespace {

h5::Handle open_for_reading(const std::string& path, const std::string& what) {
  if (!std::filesystem::exists(path)) throw InputError(what + " file '" + path + "' does not exist");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError(what + " file '" + path + "' is not an HDF5 file (or cannot be read)");
  auto f = h5::file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) throw InputError(what + " file '" + path + "' cannot be opened for reading");
  return f;
}

// Reads dataset `name` as doubles, checking its shape against `expected`
// (all dimensions), and that every value is finite.
std::vector<double> read_dataset(hid_t file, const std::string& path, const std::string& name,
                                 const std::vector<hsize_t>& expected, const std::string& shape_doc) {
  if (!h5::exists(file, name))
    throw InputError("file '" + path + "': missing dataset '" + name + "' (expected " + shape_doc + ")");
  auto d = h5::dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
  if (!d.valid()) throw InputError("file '" + path + "': '" + name + "' is not a dataset");
  auto sp = h5::space(H5Dget_space(d));
  int rank = H5Sget_simple_extent_ndims(sp);
  std::vector<hsize_t> dims(rank > 0 ? rank : 0);
  if (rank > 0) H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
  if (dims != expected) {
    std::string found;
    for (std::size_t k = 0; k < dims.size(); ++k) found += (k ? " x " : "") + std::to_string(dims[k]);
    if (dims.empty()) found = "a scalar";
    throw InputError("file '" + path + "': dataset '" + name + "' has shape " + found + ", expected " +
                     shape_doc);
  }
  auto t = h5::type(H5Dget_type(d));
  H5T_class_t cls = H5Tget_class(t);
  if (cls != H5T_FLOAT && cls != H5T_INTEGER)
    throw InputError("file '" + path + "': dataset '" + name + "' must hold numbers");
  std::size_t n = 1;
  for (auto e : expected) n *= e;
  std::vector<double> v(n);
  if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    throw InputError("file '" + path + "': dataset '" + name + "' cannot be read as numbers");
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(v[k])) {
      std::ostringstream where;  // (ostringstream: GCC 12 warns falsely on "[" + to_string)
      std::vector<std::size_t> idx(expected.size());
      std::size_t rest = k;
      for (std::size_t d = expected.size(); d-- > 0;) {
        idx[d] = rest % expected[d];
        rest /= expected[d];
      }
      where << '[';
      for (std::size_t d = 0; d < idx.size(); ++d) where << (d ? ", " : "") << idx[d];
      where << ']';
      throw InputError("file '" + path + "': dataset '" + name + "' has a non-finite value (" +
                       message_number(v[k], 17) + ") at index " + where.str());
    }
  }
  return v;
}

std::string nx3(std::size_t N) { return std::to_string(N) + " x 3 (N x 3 with N = rod.points)"; }

}  // namespace

void read_initial_fields(const std::string& path, const std::vector<double>& s, std::vector<double>& y) {
  h5::QuietErrors quiet;
  const std::size_t N = s.size();
  auto f = open_for_reading(path, "initial-condition");
  auto s_file = read_dataset(f, path, "s", {N}, std::to_string(N) + " values (N = rod.points)");
  // The grid must be the scene's: i L / N. Tolerance relative to the rod length.
  double L = N > 0 ? s.back() + (N > 1 ? s[1] - s[0] : 0.0) : 0.0;
  double tol = 1e-9 * std::max(1.0, std::abs(L));
  for (std::size_t i = 0; i < N; ++i) {
    if (std::abs(s_file[i] - s[i]) > tol)
      throw InputError("file '" + path + "': dataset 's' does not match the scene's grid s_i = i L / N: s[" +
                       std::to_string(i) + "] = " + message_number(s_file[i], 17) + ", expected " +
                       message_number(s[i], 17) + " (tolerance " + message_number(tol, 17) +
                       "); check rod.length and rod.points");
  }
  y.assign(kComponents * N, 0.0);
  for (int fi = 0; fi < kFields; ++fi) {
    std::string name = std::string("fields/") + kFieldNames[fi];
    auto v = read_dataset(f, path, name, {N, 3}, nx3(N));
    for (int c = 0; c < 3; ++c) {
      double* dst = component(y.data(), N, static_cast<Field>(fi), c);
      for (std::size_t i = 0; i < N; ++i) dst[i] = v[3 * i + c];
    }
  }
}

void read_intrinsic_shape(const std::string& path, int N, std::vector<double>& Gamma0_s,
                          std::vector<double>& Omega0_s) {
  h5::QuietErrors quiet;
  const auto n = static_cast<std::size_t>(N);
  auto f = open_for_reading(path, "intrinsic-shape");
  for (auto [name, dst] : {std::pair{"Gamma0", &Gamma0_s}, std::pair{"Omega0", &Omega0_s}}) {
    auto v = read_dataset(f, path, name, {n, 3}, nx3(n));
    dst->assign(3 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) (*dst)[c * n + i] = v[3 * i + c];
  }
}

namespace {

// The string attribute `name` of the file's root group, or empty if absent.
std::string string_attribute(hid_t file, const std::string& name) {
  if (H5Aexists(file, name.c_str()) <= 0) return {};
  auto a = h5::attribute(H5Aopen(file, name.c_str(), H5P_DEFAULT));
  auto t = h5::type(H5Aget_type(a));
  if (!a.valid() || H5Tget_class(t) != H5T_STRING) return "(not a string)";
  if (H5Tis_variable_str(t) > 0) {
    char* buf = nullptr;
    auto mem = h5::type(H5Tcopy(H5T_C_S1));
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5Tget_cset(t));  // h5py writes UTF-8
    if (H5Aread(a, mem, &buf) < 0 || !buf) return "(unreadable)";
    std::string out(buf);
    H5free_memory(buf);
    return out;
  }
  std::string out(H5Tget_size(t), '\0');
  if (H5Aread(a, t, out.data()) < 0) return "(unreadable)";
  return out.substr(0, out.find('\0'));
}

}  // namespace

void read_material_file(const std::string& path, int N, Material& m, std::vector<double>& Gamma0_s,
                        std::vector<double>& Omega0_s) {
  h5::QuietErrors quiet;
  const auto n = static_cast<std::size_t>(N);
  auto f = open_for_reading(path, "material");
  const std::string format = string_attribute(f, "format");
  if (format != kMaterialFormat)
    throw InputError("file '" + path + "': attribute 'format' is " +
                     (format.empty() ? std::string("missing") : "\"" + format + "\"") + "; allowed: \"" +
                     kMaterialFormat + "\" (a per-point rod material file, docs/scenes.md)");
  const std::string Ns = std::to_string(n);
  m.K_s = read_dataset(f, path, "K", {n, 6, 6}, Ns + " x 6 x 6 (N x 6 x 6 with N = rod.points)");
  m.I_s = read_dataset(f, path, "I", {n, 3, 3}, Ns + " x 3 x 3 (N x 3 x 3 with N = rod.points)");
  m.rho_s = read_dataset(f, path, "rho", {n}, Ns + " values (N = rod.points)");
  m.file = path;
  Gamma0_s.clear();
  Omega0_s.clear();
  for (auto [name, dst] : {std::pair{"Gamma0", &Gamma0_s}, std::pair{"Omega0", &Omega0_s}}) {
    if (!h5::exists(f, name)) continue;
    auto v = read_dataset(f, path, name, {n, 3}, nx3(n));
    dst->assign(3 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) (*dst)[c * n + i] = v[3 * i + c];
  }
  if (Gamma0_s.empty() != Omega0_s.empty())
    throw InputError("file '" + path + "': has dataset '" + (Gamma0_s.empty() ? "Omega0" : "Gamma0") +
                     "' but not '" + (Gamma0_s.empty() ? "Gamma0" : "Omega0") +
                     "'; the intrinsic shape needs both (N x 3 each) or neither");
  // Validate now, so that the error names this file and the point.
  (void)resolve_material(m, n);
}

void write_initial_fields(const std::string& path, const std::vector<double>& s,
                          const std::vector<double>& y) {
  h5::QuietErrors quiet;
  const std::size_t N = s.size();
  if (y.size() != kComponents * N)
    throw Error("write_initial_fields: state has " + std::to_string(y.size()) +
                " values, expected 12 N = " + std::to_string(kComponents * N));
  auto f = h5::file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  if (!f.valid()) throw Error("cannot create HDF5 file '" + path + "'");
  auto write = [&](const std::string& name, const std::vector<hsize_t>& dims, const double* data) {
    auto lcpl = h5::plist(H5Pcreate(H5P_LINK_CREATE));
    H5Pset_create_intermediate_group(lcpl, 1);
    auto sp = h5::space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
    auto d = h5::dataset(H5Dcreate2(f, name.c_str(), H5T_IEEE_F64LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT));
    if (!d.valid() || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      throw Error("cannot write dataset '" + name + "' to '" + path + "'");
  };
  write("s", {N}, s.data());
  std::vector<double> buf(3 * N);
  for (int fi = 0; fi < kFields; ++fi) {
    for (int c = 0; c < 3; ++c) {
      const double* src = component(y.data(), N, static_cast<Field>(fi), c);
      for (std::size_t i = 0; i < N; ++i) buf[3 * i + c] = src[i];
    }
    write(std::string("fields/") + kFieldNames[fi], {N, 3}, buf.data());
  }
}

}  // namespace rodcore
