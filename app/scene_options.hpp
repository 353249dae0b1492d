// Scene files: INI parsed with Boost.Program_options into one typed, validated Scene.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "scene.hpp"

namespace brittle {

/// Reads the INI files in order, then applies "section.key=value" overrides; later ones win.
/// Every problem (unreadable file, unknown key, malformed or out-of-range value, conflicting
/// keys) throws brittle::Error with one line naming the file (or --set) and the key.
Scene load_scene(const std::vector<std::string>& files, const std::vector<std::string>& overrides);

/// Prints every scene key as "[section] key = default  unit  meaning", for `brittle run --help`.
void print_scene_keys(std::ostream& out);

}  // namespace brittle
