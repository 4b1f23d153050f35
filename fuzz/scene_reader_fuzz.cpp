// libFuzzer target: the TOML scene reader must never crash, never hit
// undefined behaviour (ASan/UBSan are on) and never throw anything but
// InputError, whatever bytes it is given. A scene it accepts must also
// survive its own round trip: scene_to_toml(read(x)) reads back to the same
// resolved text (the property rodsim relies on when it writes the resolved
// scene into every output file and checkpoint).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/scene_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Keep inputs to scene size: huge arrays only test the allocator.
  if (size > 4096) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  rodcore::Scene scene;
  try {
    // A base folder that does not exist: relative IC paths fail cleanly.
    scene = rodcore::read_scene_string(text, "<fuzz>", "/nonexistent-dnarod-fuzz-dir");
  } catch (const rodcore::InputError&) {
    return 0;  // the only allowed way to refuse
  }
  const std::string resolved = rodcore::scene_to_toml(scene);
  std::string again;
  try {
    again = rodcore::scene_to_toml(
        rodcore::read_scene_string(resolved, "<fuzz>", "/nonexistent-dnarod-fuzz-dir"));
  } catch (const rodcore::InputError& e) {
    std::fprintf(stderr, "accepted scene does not read back: %s\n--- resolved:\n%s\n", e.what(),
                 resolved.c_str());
    std::abort();
  }
  if (again != resolved) {
    std::fprintf(stderr, "resolved scene changes on a second round trip:\n%s\n--- vs ---\n%s\n",
                 resolved.c_str(), again.c_str());
    std::abort();
  }
  return 0;
}
