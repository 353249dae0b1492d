// Where brittle finds itself and the scenes it ships, from any working directory.
#pragma once

#include <string>

namespace brittle {

/// This executable's path (/proc/self/exe), to start more of it (sweeps).
std::string self_executable();

/// The directory of the shipped scenes: <prefix>/share/brittle/scenes next to an installed
/// executable (cmake --install), else the source tree's scenes/ this build came from. Throws
/// brittle::Error when neither exists (e.g. a build whose sources were moved).
std::string bundled_scenes_directory();

}  // namespace brittle
