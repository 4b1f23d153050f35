// Scene files (TOML) -> validated Scene, and back. Every key, its units,
// default and allowed range are documented in docs/scenes.md. Every mistake
// is an InputError that names the file (and line), the dotted key (e.g.
// `solver.rtol`), what was found and what is allowed; a misspelt key gets a
// "did you mean" suggestion. Scene layer (library rodcore_scene).
#pragma once
#include <string>
#include <vector>

#include "rodcore/scene.hpp"

namespace rodcore {

// Reads a scene file. `overrides` are "section.key=value" strings (rodsim's
// --set); the value is TOML (a bare word that is not TOML is taken as a
// string, so `solver.space=fd4` works) and is validated like the file.
// Relative paths in the scene (initial.path, rod.intrinsic_file) are
// relative to the scene file's folder.
Scene read_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});

// Reads a scene from TOML text. `source` names it in messages (e.g. "<string>");
// relative paths are relative to `base_dir`.
Scene read_scene_string(const std::string& text, const std::string& source = "<string>",
                        const std::string& base_dir = ".", const std::vector<std::string>& overrides = {});

// The fully resolved scene (every key, defaults filled, derived rod values,
// absolute paths, doubles to 17 digits) as TOML text: reading it back gives
// the same Scene. Written into every output file so a run can be repeated.
std::string scene_to_toml(const Scene& scene);

}  // namespace rodcore
