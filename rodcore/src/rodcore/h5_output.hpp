// HDF5 output of a run (internal; the public face is the observer H5Writer, h5_writer.hpp) (design.md "Public
// contracts"; docs/scenes.md "Output file"):
//   time                 (T)            output times (dimensionless)
//   s                    (N)            grid s_i = i L / N
//   fields/<name>        (T x N x 3)    gamma, omega, Gamma, Omega (internal frame)
//   energy               (T)            when output.fields has "energy"
//   energy_parts/<name>  (T)            when "energy_parts"
//   kinetic_kT           (T)            a thermal scene: 2 KE / (6 N) (docs/thermal.md)
//   centerline           (T x N x 3)    when "centerline" (lab frame)
//   directors            (T x N x 3 x 3) when "directors"; [t][i][xyz][k] = component xyz of d_k
//   topology/<Lk,Tw,Wr>  (T)            a closed rod (docs/topology.md); the attribute
//                                       topology_jumps counts the frames whose Lk differs
//                                       from the frame before
// Datasets are chunked with unlimited T; each frame is written and flushed
// (H5Fflush) as it arrives, `time` last, so len(time) is the number of
// complete frames even if the process is killed. The file is written as
// OUT.h5.partial and renamed to OUT.h5 by finish() (complete = 1) or by
// fail() (complete = 0, error = message). A process that is killed leaves
// OUT.h5.partial, readable up to its last flushed frame.
#pragma once
#include <hdf5.h>

#include <string>
#include <vector>

#include "rodcore/scene.hpp"
#include "rodcore/simulation.hpp"
#include "rodcore/version.hpp"

namespace rodcore {

class H5Output {
 public:
  // Creates `path`.partial and writes the grid and the attributes that
  // describe the run (scales, material, rod, method, initial condition,
  // the resolved scene as TOML, git revision, version). Throws InputError if
  // the file cannot be created.
  H5Output(const std::string& path, const Scene& scene, const std::vector<double>& s);
  // Resume (checkpoint.hpp): reopens `path`.partial left by an interrupted or
  // killed run, keeps its first `frames` frames (drops any written after the
  // checkpoint) and appends from there. Throws InputError if the file is
  // missing, damaged, has a different grid, or holds fewer frames.
  struct Resume {
    int frames;
  };
  H5Output(const std::string& path, const Scene& scene, const std::vector<double>& s, Resume resume);
  ~H5Output();  // without finish()/fail(): closes and leaves `path`.partial
  H5Output(const H5Output&) = delete;
  H5Output& operator=(const H5Output&) = delete;

  void write_frame(const Frame& frame);
  // Writes the summary attributes and complete = 1, closes, renames to `path`.
  void finish(const RunSummary& summary);
  // A text attribute on the file (e.g. the scene file as the user wrote it);
  // text too long for an attribute goes to a string dataset of that name.
  void annotate(const std::string& name, const std::string& text);
  // Writes complete = 0 and error = message, closes, renames to `path`.
  void fail(const std::string& message);

  int frames_written() const { return frames_; }
  // Frames whose Lk differs from the frame before (a closed rod), or -1 (no topology).
  long topology_jumps() const { return has_topology_ ? jumps_ : -1; }
  const std::string& path() const { return path_; }
  std::string partial_path() const { return path_ + ".partial"; }

 private:
  void close_and_rename();
  hid_t extendible(const std::string& name, std::vector<hsize_t> row_dims);
  hid_t reopen(const std::string& name, int frames);
  void append(hid_t dataset, const double* row);

  std::string path_;
  OutputOptions want_;
  bool thermal_ = false;  // the scene has [thermal]: kinetic_kT
  std::size_t N_;
  hid_t file_ = H5I_INVALID_HID;
  std::vector<hid_t> fields_;  // 4 datasets or empty
  hid_t time_ = H5I_INVALID_HID, energy_ = H5I_INVALID_HID, kinetic_kT_ = H5I_INVALID_HID;
  hid_t centerline_ = H5I_INVALID_HID, directors_ = H5I_INVALID_HID;
  std::vector<std::pair<std::string, hid_t>> energy_parts_;
  std::vector<hid_t> topology_;  // Lk, Tw, Wr, or empty
  bool has_topology_ = false;
  double last_Lk_ = 0.0;
  long jumps_ = 0;
  std::vector<double> row_;  // N x 3 scratch
  int frames_ = 0;
};

}  // namespace rodcore
