// Where brittle finds itself and its shipped scenes.
#include "paths.hpp"

#include <filesystem>

#include "error.hpp"

namespace fs = std::filesystem;

namespace brittle {

std::string self_executable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  BRITTLE_CHECK(!ec, "cannot find the brittle executable (/proc/self/exe)");
  return p.string();
}

std::string bundled_scenes_directory() {
  const fs::path installed =
      fs::path(self_executable()).parent_path().parent_path() / "share" / "brittle" / "scenes";
  const fs::path source = fs::path(BRITTLE_SOURCE_SCENES);
  for (const fs::path& dir : {installed, source})
    if (fs::is_regular_file(dir / "cm.ini")) return dir.string();
  throw Error(error_message("cannot find the shipped scenes (looked for cm.ini in '",
                            installed.string(), "' and '", source.string(),
                            "'); give the directory with --scenes DIR"));
}

}  // namespace brittle
