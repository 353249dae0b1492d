// Scene files: INI parsed with Boost.Program_options into one typed, validated Scene.
// One table (scene_keys.cpp) gives every key its type, default, unit, meaning and valid range;
// the options_description, the `--help` text and the validation are all built from it. Reading
// a source is here; the named sections are in scene_named.cpp, the checks between keys in
// scene_check.cpp.
#include "scene_options.hpp"

#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "build_info.hpp"
#include "error.hpp"
#include "scene_check.hpp"
#include "scene_keys.hpp"
#include "scene_named.hpp"

namespace brittle {

using namespace scene_file;

namespace {

namespace fs = std::filesystem;

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diag = up;
    }
  }
  return row[b.size()];
}

[[noreturn]] void unknown_key(const Source& src, const std::string& name) {
  std::string msg = error_message(src.label, ": unknown key '", name, "'");
  const auto dot = name.find('.');
  const std::string section = dot == std::string::npos ? std::string() : name.substr(0, dot);
  if (dot == std::string::npos) {
    msg += " (keys belong in a [section] or are written section.key)";
  } else if (section == "boundary" || section == "notch" || section == "sensor" ||
             (section == "initial" && !find_key(name) && name != "initial.state")) {
    msg += " (keys of [" + section + ".NAME] go in a named section, e.g. [" + section +
           ".a], i.e. " + section + ".a." + name.substr(dot + 1) + ")";
  } else if (!is_known_section(section)) {
    msg += " (no section [" + section + "]; sections are";
    for (const auto& s : known_sections()) msg += " [" + s + "]";
    msg += " [boundary.NAME] [initial.NAME] [notch.NAME] [sensor.NAME])";
  } else {
    // Only a trivial suggestion: same section, one typo away or differing in case.
    const std::string key = name.substr(dot + 1);
    for (const Key& k : scene_keys()) {
      if (k.section() != section) continue;
      const std::string candidate = k.name.substr(dot + 1);
      if (lower(candidate) == lower(key) || edit_distance(candidate, key) <= 1) {
        msg += " (did you mean '" + k.name + "'?)";
        break;
      }
    }
  }
  throw Error(msg);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// Boost's config parser reports a bad line without its number; find it ourselves first.
void check_syntax(std::istream& in, const Source& src) {
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    const std::string s = trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (s.empty()) continue;
    const bool section = s.front() == '[' && s.back() == ']';
    BRITTLE_CHECK(section || s.find('=') != std::string::npos, src.label, ", line ", number, ": '",
                  s, "' is neither 'key = value' nor '[section]'");
    BRITTLE_CHECK(section || !trim(s.substr(0, s.find('='))).empty(), src.label, ", line ", number,
                  ": '", s, "' has no key before '='");
  }
}

/// Stores one source's options into its own variables_map (so later sources can override
/// earlier ones, which a shared map would not allow) and applies them onto the scene.
void apply_options(const std::vector<po::option>& options, const Source& src, std::size_t order,
                   Scene& scene, Origins& origins, std::vector<NamedSection>& named) {
  const po::options_description& desc = description();
  po::variables_map vm;
  std::map<std::string, std::string> raw;
  std::set<std::string> named_seen;
  for (const po::option& opt : options) {
    const std::string& name = opt.string_key;
    if (const auto parts = split_named(name); parts && (opt.unregistered || !find_key(name))) {
      const auto& [kind, section, key] = *parts;
      if (!find_named_key(kind, key)) {
        std::string msg =
            error_message(src.label, ": unknown key '", name, "' (keys of [", kind, ".NAME] are");
        for (const NamedKey& k : named_keys())
          if (k.kind == kind) msg += " " + k.key;
        throw Error(msg + ")");
      }
      BRITTLE_CHECK(
          std::all_of(section.begin(), section.end(),
                      [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; }),
          src.label, ": [", kind, ".", section,
          "]: a section name has letters, digits, "
          "'_' or '-' only");
      BRITTLE_CHECK(named_seen.insert(name).second, src.label, ": ", name,
                    " is given more than once");
      auto it = std::find_if(named.begin(), named.end(), [&, &k = kind, &s = section](
                                                              const NamedSection& n) {
        return n.kind == k && n.name == s;  // (clang 14 cannot capture structured bindings)
      });
      if (it == named.end()) it = named.insert(named.end(), NamedSection{kind, section, {}});
      it->keys[key] = {opt.value.empty() ? std::string() : opt.value.front(), src.label};
      continue;
    }
    if (opt.unregistered || !find_key(name)) unknown_key(src, name);
    BRITTLE_CHECK(!raw.count(name), src.label, ": ", name, " is given more than once");
    const std::string value = opt.value.empty() ? std::string() : opt.value.front();
    raw[name] = value;
    const Key& key = *find_key(name);
    const std::string not_a = error_message(src.label, ": ", name, " = '", value, "' is not ",
                                            key.type_word, " (expected ", key.expected(), ")");
    BRITTLE_CHECK(key.allow_empty || !value.empty(), not_a);
    // One option per store() call so that a conversion error is pinned to its key.
    po::parsed_options one(&desc);
    one.options.push_back(opt);
    try {
      po::store(one, vm);
    } catch (const po::error&) {
      throw Error(not_a);
    }
  }
  // Apply in table order; within one source at most one loading key may appear.
  BRITTLE_CHECK(!(raw.count("loading.sigma") && raw.count("loading.sigma_over_sigmac")), src.label,
                ": loading.sigma_over_sigmac and loading.sigma are both given (expected exactly "
                "one)");
  for (const Key& key : scene_keys()) {
    auto it = raw.find(key.name);
    if (it == raw.end()) continue;
    switch (key.apply(vm[key.name], src, scene)) {
      case Verdict::ok:
        break;
      case Verdict::malformed:
        throw Error(error_message(src.label, ": ", key.name, " = '", it->second, "' is not ",
                                  key.type_word, " (expected ", key.expected(), ")"));
      case Verdict::out_of_range:
        if (!key.choices.empty()) {  // words: say which
          std::string words;
          for (const std::string& w : key.choices) words += (words.empty() ? "" : ", ") + w;
          throw Error(error_message(src.label, ": ", key.name, " = '", it->second,
                                    "' is not one of: ", words, " (expected ", key.expected(),
                                    "; case does not matter)"));
        }
        throw Error(error_message(src.label, ": ", key.name, " = ", it->second,
                                  " is out of range (expected ", key.expected(), ")"));
    }
    origins.by_key[key.name] = {order, src.label};
    if (key.name == "loading.sigma") origins.by_key.erase("loading.sigma_over_sigmac");
    if (key.name == "loading.sigma_over_sigmac") origins.by_key.erase("loading.sigma");
  }
}

}  // namespace

Scene load_scene(const std::vector<std::string>& files, const std::vector<std::string>& overrides) {
  Scene scene;
  Origins origins;
  std::vector<NamedSection> named;
  std::size_t order = 0;

  for (const std::string& file : files) {
    const Source src{"scene file '" + file + "'", fs::path(file).parent_path()};
    std::error_code ec;
    BRITTLE_CHECK(!fs::is_directory(file, ec), src.label, ": cannot be opened (it is a directory)");
    std::ifstream in(file);
    BRITTLE_CHECK(in.good(), src.label, ": cannot be opened");
    check_syntax(in, src);
    in.clear();
    in.seekg(0);
    std::vector<po::option> options;
    try {
      options = po::parse_config_file(in, description(), /*allow_unregistered=*/true).options;
    } catch (const po::error& e) {
      throw Error(error_message(src.label, ": ", e.what()));
    }
    apply_options(options, src, order++, scene, origins, named);
    scene.sources.push_back(file);
  }

  for (const std::string& text : overrides) {
    const Source src{"--set", {}};  // relative mesh.file: relative to the working directory
    const auto eq = text.find('=');
    const std::string name = eq == std::string::npos ? std::string() : trim(text.substr(0, eq));
    BRITTLE_CHECK(!name.empty(), "--set '", text, "': expected section.key=value");
    po::option opt(name, {trim(text.substr(eq + 1))});
    opt.original_tokens = {text};
    opt.unregistered = find_key(name) == nullptr;
    apply_options({opt}, src, order++, scene, origins, named);
    scene.sources.push_back("--set " + text);
  }

  read_named_sections(named, scene);
  check_scene(scene, origins, files);
  for (const NamedSection& s : named) {  // their text as given reads back as the same numbers
    Scene::NamedText t{s.kind, s.name, {}};
    for (const auto& [key, v] : s.keys) t.keys.emplace_back(key, v.value);
    scene.named_sections.push_back(std::move(t));
  }
  return scene;
}

std::vector<std::pair<std::string, std::string>> scene_entries(const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> entries;
  for (const Key& k : scene_keys()) {
    BRITTLE_CHECK(k.get != nullptr, "scene key ", k.name, " has no getter");
    // [notch.NAME] sections replace the paper's notch: both may not be given
    if (!scene.geometry.notches.empty() &&
        (k.name == "geometry.notch_depth" || k.name == "geometry.notch_base"))
      continue;
    if (const std::optional<std::string> value = k.get(scene))  // (unset: left out)
      entries.emplace_back(k.name, *value);
  }
  for (const Scene::NamedText& s : scene.named_sections)
    for (const auto& [key, value] : s.keys) entries.emplace_back(s.kind + "." + s.name + "." + key, value);
  return entries;
}

std::string scene_ini(const Scene& scene) {
  std::ostringstream out;
  out << "# The resolved scene of a run: every key, after the scene files and --set overrides\n"
         "# below, in the order of `brittle run --help`. `brittle run` on this file repeats the "
         "run.\n# brittle "
      << build_info().version << " (commit " << build_info().commit << ", "
      << build_info().compiler << ", " << build_info().build_type << ")\n";
  for (const std::string& s : scene.sources) out << "# source: " << s << "\n";
  std::string section;
  for (const auto& [name, value] : scene_entries(scene)) {
    // section.key, or kind.NAME.key for a named section
    const std::size_t dot = name.rfind('.');
    if (name.substr(0, dot) != section) {
      section = name.substr(0, dot);
      out << "\n[" << section << "]\n";
    }
    out << name.substr(dot + 1) << " = " << value << "\n";
  }
  return out.str();
}

void print_scene_keys(std::ostream& out) {
  std::size_t name_w = 0, default_w = 0, unit_w = 0;
  for (const Key& k : scene_keys()) {
    name_w = std::max(name_w, k.name.size());
    default_w = std::max(default_w, k.default_text.size());
    unit_w = std::max(unit_w, k.unit.size() + 2);
  }
  auto pad = [](const std::string& s, std::size_t w) {
    return s + std::string(w > s.size() ? w - s.size() : 0, ' ');
  };
  // Meaning and range word-wrapped into the last column; the range is never broken.
  const std::size_t indent = 2 + name_w + 3 + default_w + 2 + unit_w + 2;
  const std::size_t width = std::max<std::size_t>(40, 104 > indent ? 104 - indent : 0);
  auto wrap = [&](const Key& k) {
    std::vector<std::string> chunks;
    std::istringstream words(k.meaning);
    for (std::string word; words >> word;) chunks.push_back(word);
    for (std::size_t b = 0, e = 0; b < k.range.size(); b = e + 2) {  // clauses split at "; "
      e = std::min(k.range.find("; ", b), k.range.size());
      chunks.back() += ";";
      chunks.push_back(k.range.substr(b, e - b));
    }
    std::string result, line;
    for (const std::string& chunk : chunks) {
      if (!line.empty() && line.size() + 1 + chunk.size() > width) {
        result += line + "\n" + std::string(indent, ' ');
        line.clear();
      }
      line += (line.empty() ? "" : " ") + chunk;
    }
    return result + line;
  };
  out << "Later files and --set override earlier ones; SI units; '#' starts a comment.\n";
  std::string section;
  for (const Key& k : scene_keys()) {
    if (k.section() != section) {
      section = k.section();
      out << "\n[" << section << "]\n";
    }
    out << "  " << pad(k.name, name_w) << " = " << pad(k.default_text, default_w) << "  "
        << pad(k.unit.empty() ? "" : "[" + k.unit + "]", unit_w) << "  " << wrap(k) << '\n';
  }
  out << "\nNamed sections, any number of each (NAME: letters, digits, _ or -; docs/scenes.md):\n";
  std::string kind;
  for (const NamedKey& k : named_keys()) {
    if (k.kind != kind) {
      kind = k.kind;
      out << "\n[" << kind << ".NAME]\n";
    }
    out << "  " << pad(k.key, 12) << "  " << pad(k.unit.empty() ? "" : "[" + k.unit + "]", 7)
        << "  " << k.expected << '\n';
  }
}

}  // namespace brittle
