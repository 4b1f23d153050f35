// The sections of a scene file, one reader and one writer each, in the order
// of the file (docs/scenes.md): [rod], [material], [initial], [solver],
// [output], [checks]. The scene reader (scene_reader.cpp) runs the readers in
// this order (those marked read_last after the others), rejects unknown keys
// in the same order, then checks what spans several sections (the kind's rod
// values, the grid against solver.space, the files that need the grid);
// scene_to_toml() writes the sections in file order.
//
// A new section: its struct in scene.hpp (a member of Scene), its read_ and
// write_ functions in scene_sections.cpp and one row of scene_sections();
// checks that need another section go to check_across_sections()
// (scene_reader.cpp). docs/architecture.md, "Where to add things".
#pragma once
#include <set>
#include <string>
#include <vector>

#include "rodcore/scene.hpp"
#include "rodcore/scene_section.hpp"

namespace rodcore {

// A scene while it is read: the Scene so far and what the readers leave for
// the checks across sections.
struct SceneDraft {
  Scene scene;
  // Rod and material keys the scene gives explicitly, by bare name: a kind's
  // derive_rod fills only the others and checks these for consistency.
  std::set<std::string> set_keys;
  // Absolute paths, read once the grid is known ("" when not given).
  std::string intrinsic_file, material_file;
};

struct SectionReader {
  std::string name;  // [name] in the file, and --set name.key
  void (*read)(Section& section, SceneDraft& draft);
  // The section's lines of the resolved scene (every key, TOML, ending in a
  // newline); "" leaves the section out of the resolved scene.
  std::string (*write)(const Scene& scene);
  // Read and checked for unknown keys after the other sections: the allowed
  // keys of [initial] depend on its kind, so when the kind is misplaced
  // (written in [solver], say) that is the error reported, not the kind's
  // parameters that then look unknown in [initial].
  bool read_last = false;
};

// Every section, in file order.
const std::vector<SectionReader>& scene_sections();

}  // namespace rodcore
