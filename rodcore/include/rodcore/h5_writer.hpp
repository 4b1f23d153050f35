// The observer that writes a run to HDF5 (layout: docs/scenes.md "Output
// file"): time, s, fields/<name>, energy, energy_parts/<name>, centerline,
// directors, as the scene's output asks, with the scales (tau_ps, ell_A,
// velocity_A_per_ps), the material, the method, the resolved scene, the git
// revision and rodcore_version as attributes. Each frame is flushed as it is
// written; the file is OUT.h5.partial until the run finishes (complete = 1)
// or fails numerically (complete = 0, attribute error), then renamed to
// OUT.h5. A run stopped otherwise (killed, interrupted) leaves OUT.h5.partial,
// readable up to its last frame, which a resumed run appends to.
// Scene layer (library rodcore_scene).
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/observer.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

class H5Output;

class H5Writer : public Observer {
 public:
  // Creates `path`.partial for a run of `sim` (its resolved scene and grid).
  // With `resume_frames`, reopens the .partial of an interrupted run, keeps
  // its first `resume_frames` frames and appends. Throws InputError if the
  // file cannot be created, or (resume) is missing, damaged or of another grid.
  H5Writer(const std::string& path, const Simulation& sim, std::optional<int> resume_frames = {});
  // The same for a scene and grid given explicitly.
  H5Writer(const std::string& path, const Scene& scene, const std::vector<double>& s,
           std::optional<int> resume_frames = {});
  ~H5Writer() override;

  // A text attribute on the file (e.g. the scene file as the user wrote it).
  void annotate(const std::string& name, const std::string& text);
  int frames_written() const;
  std::string partial_path() const;
  // A closed rod: the frames written whose Lk differs from the frame before (the
  // attribute topology_jumps); -1 for a rod without per-frame topology.
  long topology_jumps() const;

  void frame(const Simulation& sim, const Frame& frame) override;
  void finished(const Simulation& sim, const RunSummary& summary) override;
  void failed(const Simulation& sim, const std::string& message) override;

 private:
  std::unique_ptr<H5Output> out_;
};

}  // namespace rodcore
