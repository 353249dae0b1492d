// The checks between scene keys, made once every source has been applied (scene_options.cpp).
#pragma once

#include <cstddef>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene.hpp"

namespace brittle::scene_file {

/// Which source last set each key, for messages about keys that constrain each other.
struct Origins {
  std::map<std::string, std::pair<std::size_t, std::string>> by_key;  // key -> (order, label)
  /// The label of whichever of the keys was set last ("scene" if all are defaults).
  std::string latest(std::initializer_list<std::string> keys) const {
    std::optional<std::pair<std::size_t, std::string>> best;
    for (const auto& key : keys) {
      auto it = by_key.find(key);
      if (it != by_key.end() && (!best || it->second.first > best->first)) best = it->second;
    }
    return best ? best->second : "scene";
  }
};

/// Checks between keys, after every source has been applied: a conflict throws brittle::Error
/// naming the source that set one of the keys last. `files` are the scene files, for messages.
void check_scene(const Scene& s, const Origins& o, const std::vector<std::string>& files);

}  // namespace brittle::scene_file
