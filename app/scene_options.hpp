// Scene files: INI parsed with Boost.Program_options into one typed, validated Scene.
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "scene.hpp"

namespace brittle {

/// Reads the INI files in order, then applies "section.key=value" overrides; later ones win.
/// Every problem (unreadable file, unknown key, malformed or out-of-range value, conflicting
/// keys) throws brittle::Error with one line naming the file (or --set) and the key.
Scene load_scene(const std::vector<std::string>& files, const std::vector<std::string>& overrides);

/// The scene as one INI text: every key with its value (numbers in the shortest form that reads
/// back as the same double), the named sections as their sources gave them, and the sources in
/// comments. load_scene of it gives the same scene (the run's scene.ini; --show-scene).
std::string scene_ini(const Scene& scene);
/// The same as ("section.key" or "kind.NAME.key", value text) pairs.
std::vector<std::pair<std::string, std::string>> scene_entries(const Scene& scene);

/// Prints every scene key as "[section] key = default  unit  meaning", for `brittle run --help`.
void print_scene_keys(std::ostream& out);

}  // namespace brittle
