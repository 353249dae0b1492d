// Fuzzes the scene parser: the input is a scene file; after a line "--set" its following lines
// are --set overrides, as `brittle run` passes them. Any outcome but a brittle::Error (one
// line) or a scene is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "error.hpp"
#include "scene_options.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string file = "/tmp/brittle_fuzz_scene_" + std::to_string(getpid()) + ".ini";
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> sets;
  if (const auto at = text.find("\n--set\n"); at != std::string::npos) {
    std::string rest = text.substr(at + 7);
    text.resize(at);
    for (std::size_t begin = 0; begin <= rest.size();) {
      const std::size_t end = std::min(rest.find('\n', begin), rest.size());
      sets.push_back(rest.substr(begin, end - begin));
      begin = end + 1;
    }
  }
  std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
  try {
    brittle::Scene scene = brittle::load_scene({file}, sets);
    (void)scene;
  } catch (const brittle::Error& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) std::abort();  // one line only
  }
  return 0;
}
