// H5Writer: the HDF5 output (h5_output.hpp) as an observer of a run.
#include "rodcore/h5_writer.hpp"

#include "rodcore/h5_output.hpp"
#include "rodcore/simulation.hpp"

namespace rodcore {

H5Writer::H5Writer(const std::string& path, const Simulation& sim, std::optional<int> resume_frames)
    : H5Writer(path, sim.scene(), sim.grid(), resume_frames) {}

H5Writer::H5Writer(const std::string& path, const Scene& scene, const std::vector<double>& s,
                   std::optional<int> resume_frames)
    : out_(resume_frames ? std::make_unique<H5Output>(path, scene, s, H5Output::Resume{*resume_frames})
                         : std::make_unique<H5Output>(path, scene, s)) {}

H5Writer::~H5Writer() = default;

void H5Writer::annotate(const std::string& name, const std::string& text) { out_->annotate(name, text); }
int H5Writer::frames_written() const { return out_->frames_written(); }
std::string H5Writer::partial_path() const { return out_->partial_path(); }
long H5Writer::topology_jumps() const { return out_->topology_jumps(); }

void H5Writer::frame(const Simulation&, const Frame& f) { out_->write_frame(f); }
void H5Writer::finished(const Simulation&, const RunSummary& summary) { out_->finish(summary); }
void H5Writer::failed(const Simulation&, const std::string& message) { out_->fail(message); }

}  // namespace rodcore
