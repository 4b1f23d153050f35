// The "did you mean" of the scene reader's messages: the known word closest to a
// misspelt one (scene_reader.cpp, scene_section.cpp).
#pragma once
#include <string>
#include <vector>

namespace rodcore {

// Levenshtein distance, case-insensitive.
int edit_distance(const std::string& a, const std::string& b);

// The closest of `candidates` to `word` if it is close enough to be a
// plausible misspelling, else "".
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace rodcore
