// Internal part of the scene reader (scene_io.hpp is the public part): the
// TOML-table entry point for the Python module, and the "did you mean" helpers.
#pragma once
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "rodcore/scene.hpp"
#include "rodcore/scene_io.hpp"

namespace rodcore {

// Reads a scene from an already parsed TOML table (the Python module builds
// one from a dict).
Scene read_scene_table(toml::table table, const std::string& source, const std::string& base_dir,
                       const std::vector<std::string>& overrides = {});

// Levenshtein distance, case-insensitive (for "did you mean" suggestions).
int edit_distance(const std::string& a, const std::string& b);

// The closest of `candidates` to `word` if it is close enough to be a
// plausible misspelling, else "".
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace rodcore
