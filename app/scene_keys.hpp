// The scene keys' table and what reading a scene file shares between app/scene_*.cpp: one
// Key per "section.key" (its type, default, unit, meaning, valid range, how it is checked and
// written back). Internal to app/; the interface is scene_options.hpp.
#pragma once

#include <boost/program_options.hpp>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scene.hpp"

namespace brittle::scene_file {

namespace po = boost::program_options;

/// Where a value came from: one scene file or one --set override.
struct Source {
  std::string label;  ///< "scene file 'x.ini'" or "--set"; starts every error message
  std::filesystem::path dir;       ///< relative mesh.file paths are resolved against this
};

/// The outcome of checking one value.
enum class Verdict { ok, malformed, out_of_range };

/// One scene key: its type lives in `declare` (po::value<T>) and `apply` (as<T>()).
struct Key {
  std::string name;          ///< "section.key", as in the INI file and in --set
  std::string unit;          ///< SI unit, empty if dimensionless
  std::string meaning;       ///< what it is, in the paper's words
  std::string range;         ///< valid values, e.g. "> 0"
  std::string type_word;     ///< "a number", "an integer", ...: for "is not ..." messages
  std::string default_text;  ///< shown by --help
  bool allow_empty = false;  ///< may the value be an empty string?
  std::function<void(po::options_description_easy_init&, const Key&)> declare;
  /// Checks the value (already converted by Boost) and assigns it to the scene.
  std::function<Verdict(const po::variable_value&, const Source&, Scene&)> apply;
  /// The scene's value as the text that reads back as it (nothing: the key is left out of a
  /// resolved scene, e.g. the load kind not in use). scene_ini() writes every key with it.
  std::function<std::optional<std::string>(const Scene&)> get;
  /// For keys that take words: the words (matched without regard to case), for the message.
  std::vector<std::string> choices;

  std::string section() const { return name.substr(0, name.find('.')); }
  /// "Young's modulus in Pa, > 0"
  std::string expected() const {
    std::string s = meaning;
    if (!unit.empty()) s += " in " + unit;
    if (!range.empty()) s += ", " + range;
    return s;
  }
};

/// THE table: every scene key, in the order --help and docs/scenes.md list them.
const std::vector<Key>& scene_keys();
/// The sections that have keys, in table order.
const std::vector<std::string>& known_sections();
bool is_known_section(const std::string& section);
/// The key named "section.key", or nullptr.
const Key* find_key(const std::string& name);
/// Every key declared for Boost's parser.
const po::options_description& description();

/// Shortest text that reads back as v, fixed for moderate magnitudes: 1180, 0.0005, 3.09e+09.
std::string format_double(double v);
/// ASCII lower case (words match without regard to case).
std::string lower(std::string s);

}  // namespace brittle::scene_file
