// The option conventions every brittle command shares (docs/cli.md).
#include "command_line.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>

#include "error.hpp"

namespace brittle {

void print_command_help(std::ostream& out, const std::string& usage, const std::string& about,
                        const boost::program_options::options_description& options) {
  out << usage << "\n\n";
  std::size_t column = 0;
  for (std::size_t at = 0; at < about.size();) {
    const std::size_t end = std::min(about.find(' ', at), about.size());
    const std::size_t length = end - at;
    if (column > 0 && column + 1 + length > 80) out << '\n', column = 0;
    if (column > 0) out << ' ', ++column;
    out << about.substr(at, length);
    column += length;
    at = end + 1;
  }
  out << "\n\n" << options;
}

bool parse_switch(const std::string& option, const std::string& word) {
  std::string w = word;
  std::transform(w.begin(), w.end(), w.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* yes : {"yes", "true", "on", "1"})
    if (w == yes) return true;
  for (const char* no : {"no", "false", "off", "0"})
    if (w == no) return false;
  throw Error(error_message(option, " '", word, "' is not one of: yes, no (also true/false, on/off)"));
}

void check_out_directory(const std::string& command, const std::string& out,
                         const std::string& written) {
  std::string extension = std::filesystem::path(out).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  constexpr std::array<const char*, 7> files = {".png", ".csv", ".json", ".vtu", ".pvd", ".ini", ".txt"};
  BRITTLE_CHECK(std::find(files.begin(), files.end(), extension) == files.end(), "brittle ",
                command, " --out '", out, "': --out is a directory for every command (this one "
                "writes ", written, " in it; expected a directory, e.g. --out ",
                std::filesystem::path(out).parent_path().empty()
                    ? std::string("figs")
                    : std::filesystem::path(out).parent_path().string(),
                ")");
}

}  // namespace brittle
