// Internal part of the scene reader (scene_io.hpp is the public part): the
// TOML-table entry point for the Python module (with the "did you mean" helpers,
// did_you_mean.hpp).
#pragma once
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "rodcore/did_you_mean.hpp"
#include "rodcore/scene.hpp"
#include "rodcore/scene_io.hpp"

namespace rodcore {

// Reads a scene from an already parsed TOML table (the Python module builds
// one from a dict).
Scene read_scene_table(toml::table table, const std::string& source, const std::string& base_dir,
                       const std::vector<std::string>& overrides = {});

}  // namespace rodcore
