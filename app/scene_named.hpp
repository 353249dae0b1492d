// Named sections of a scene: [boundary.NAME], [initial.NAME], [notch.NAME], [sensor.NAME],
// any number of each; their keys, and reading them into the Scene once every source is in.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene.hpp"

namespace brittle::scene_file {

/// One key of a named section: what it expects and how it is read into the section's struct.
struct NamedKey {
  std::string kind;  ///< "boundary", "initial", "notch"
  std::string key;   ///< "traction"
  std::string unit, expected;
};

/// Every key of the named sections, in the order --help lists them.
const std::vector<NamedKey>& named_keys();
const NamedKey* find_named_key(const std::string& kind, const std::string& key);

struct NamedValue {
  std::string value, label;  ///< the text and the source that set it last
};
struct NamedSection {
  std::string kind, name;
  std::map<std::string, NamedValue> keys;
};

/// "boundary.top.traction" -> its kind, name and key, if it is a named-section key.
std::optional<std::array<std::string, 3>> split_named(const std::string& full);

/// Reads the named sections into the scene, checking every value and the keys each type needs;
/// a problem throws brittle::Error naming the source, the section and the key.
void read_named_sections(const std::vector<NamedSection>& sections, Scene& scene);

}  // namespace brittle::scene_file
