// What built this brittle: version, git commit, compiler, build type and flags (summary.json
// "build", `brittle --version`). Generated at every build by solver/build_info.cmake, so the
// commit is the one the binary was built from.
#pragma once

namespace brittle {

struct BuildInfo {
  const char* version;     ///< the project version (CMakeLists.txt)
  const char* commit;      ///< git commit, "+modified" when the tracked files differed from it
  const char* compiler;    ///< compiler id and version
  const char* build_type;  ///< CMAKE_BUILD_TYPE
  const char* flags;       ///< the C++ flags of that build type
};

const BuildInfo& build_info();

}  // namespace brittle
