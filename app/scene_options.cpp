// Scene files: INI parsed with Boost.Program_options into one typed, validated Scene.
// One table (scene_keys) gives every key its type, default, unit, meaning and valid range;
// the options_description, the `--help` text and the validation are all built from it.
#include "scene_options.hpp"

#include <cstdio>
#include <algorithm>
#include <array>
#include <boost/program_options.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "build_info.hpp"
#include "error.hpp"
#include "lists.hpp"

namespace brittle {
namespace {

namespace po = boost::program_options;
namespace fs = std::filesystem;

/// Where a value came from: one scene file or one --set override.
struct Source {
  std::string label;  ///< "scene file 'x.ini'" or "--set"; starts every error message
  fs::path dir;       ///< relative mesh.file paths are resolved against this
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

/// Shortest text that reads back as v, fixed for moderate magnitudes: 1180, 0.0005, 3.09e+09.
std::string format_double(double v) {
  char buf[64];
  const double magnitude = v == 0 ? 0 : std::floor(std::log10(std::abs(v)));
  const auto style = (v == 0 || (magnitude >= -4 && magnitude < 7)) ? std::chars_format::fixed
                                                                    : std::chars_format::scientific;
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, style);
  return ec == std::errc() ? std::string(buf, end) : std::to_string(v);
}

template <class T>
std::string type_word() {
  if constexpr (std::is_same_v<T, double>)
    return "a number";
  else if constexpr (std::is_same_v<T, int>)
    return "an integer";
  else if constexpr (std::is_same_v<T, bool>)
    return "true or false";
  else
    return "a string";
}

template <class T>
std::string show(const T& v) {
  if constexpr (std::is_same_v<T, double>)
    return format_double(v);
  else if constexpr (std::is_same_v<T, bool>)
    return v ? "true" : "false";
  else if constexpr (std::is_same_v<T, int>)
    return std::to_string(v);
  else
    return v.empty() ? "\"\"" : v;
}

/// A key of type T whose checked value is handed to `set`. `def` is the Boost default (none for
/// keys that are "unset" by default); `shown` is the default as --help prints it.
template <class T>
Key typed(std::string name, std::string unit, std::string meaning, std::string range,
          std::optional<T> def, std::string shown,
          std::function<Verdict(const T&, const Source&, Scene&)> set) {
  Key k;
  k.name = std::move(name);
  k.unit = std::move(unit);
  k.meaning = std::move(meaning);
  k.range = std::move(range);
  k.type_word = type_word<T>();
  k.default_text = std::move(shown);
  k.allow_empty = std::is_same_v<T, std::string>;
  k.declare = [def](po::options_description_easy_init& add, const Key& key) {
    const std::string help = key.expected();
    if (def)
      add(key.name.c_str(), po::value<T>()->default_value(*def, key.default_text), help.c_str());
    else
      add(key.name.c_str(), po::value<T>(), help.c_str());
  };
  k.apply = [set](const po::variable_value& v, const Source& src, Scene& scene) {
    const T value = v.as<T>();
    if constexpr (std::is_same_v<T, double>) {
      if (!std::isfinite(value)) return Verdict::malformed;  // "nan", "inf"
    }
    return set(value, src, scene);
  };
  return k;
}

/// A value as INI text that reads back as it (an empty string stays empty).
template <class T>
std::string ini_text(const T& v) {
  if constexpr (std::is_same_v<T, std::string>)
    return v;
  else
    return show(v);
}

/// Numbers as a comma separated list that reads back as them.
std::string number_list_text(const std::vector<double>& values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : ", ") + format_double(v);
  return s;
}

/// A key bound to a Scene member, valid when `ok(value)` holds.
template <class Section, class T>
Key field(std::string name, Section Scene::*section, T Section::*member, std::string unit,
          std::string meaning, std::string range,
          std::type_identity_t<std::function<bool(const T&)>> ok) {
  const T def = Scene{}.*section.*member;
  Key k = typed<T>(std::move(name), std::move(unit), std::move(meaning), std::move(range), def,
                   show(def), [section, member, ok](const T& v, const Source&, Scene& scene) {
                     if (!ok(v)) return Verdict::out_of_range;
                     scene.*section.*member = v;
                     return Verdict::ok;
                   });
  k.get = [section, member](const Scene& s) -> std::optional<std::string> {
    return ini_text(s.*section.*member);
  };
  return k;
}

bool positive(const double& v) {
  return v > 0;
}
bool non_negative(const double& v) {
  return v >= 0;
}

/// A list of times in s: comma/space separated, each >= 0, strictly ascending; empty = none.
Key time_list(const std::string& name, const std::string& meaning,
              std::vector<double>& (*target)(Scene&)) {
  Key k = typed<std::string>(name, "s", meaning, "each >= 0, strictly ascending; empty = none",
                             std::string(), "\"\"",
                             [target](const std::string& v, const Source&, Scene& scene) {
                               NumberList list = parse_number_list(v);
                               if (list.bad) return Verdict::malformed;
                               const std::vector<double>& t = list.values;
                               for (std::size_t i = 0; i < t.size(); ++i)
                                 if (t[i] < 0 || (i > 0 && t[i] <= t[i - 1]))
                                   return Verdict::out_of_range;
                               target(scene) = std::move(list.values);
                               return Verdict::ok;
                             });
  k.type_word = "a list of numbers";
  k.get = [target](const Scene& s) -> std::optional<std::string> {
    return number_list_text(target(const_cast<Scene&>(s)));
  };
  return k;
}

using MP = MaterialParams;
using GP = GeometryParams;
using MeP = MeshParams;
using RP = RunParams;
using FP = FractureParams;
using DP = DamageParams;
using OP = OutputParams;
using ReP = RenderParams;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// A word key bound to an enum member of Scene: `words` in the order --help lists them, matched
/// without regard to case; the default is the word of Scene{}'s value.
template <class Section, class E>
Key word(std::string name, Section Scene::*section, E Section::*member, std::string meaning,
         std::string range, std::vector<std::pair<std::string, E>> words) {
  const auto word_of = [words](E v) {
    for (const auto& [w, e] : words)
      if (e == v) return w;
    return words.front().first;
  };
  const std::string def = word_of(Scene{}.*section.*member);
  Key k = typed<std::string>(std::move(name), "", std::move(meaning), std::move(range), def, def,
                             [section, member, words](const std::string& text, const Source&,
                                                      Scene& scene) {
                               const std::string v = lower(text);
                               for (const auto& [w, e] : words)
                                 if (v == w) {
                                   scene.*section.*member = e;
                                   return Verdict::ok;
                                 }
                               return Verdict::out_of_range;
                             });
  k.get = [section, member, word_of](const Scene& s) -> std::optional<std::string> {
    return word_of(s.*section.*member);
  };
  for (const auto& [w, e] : words) k.choices.push_back(w);
  return k;
}

/// THE table: every scene key, in the order --help and docs/scenes.md list them.
const std::vector<Key>& scene_keys() {
  static const std::vector<Key> keys = [] {
    std::vector<Key> k;
    // [material] — PMMA (SPEC 8, paper 6.2)
    k.push_back(field("material.rho0", &Scene::material, &MP::rho0, "kg/m^3", "reference density",
                      "> 0", positive));
    k.push_back(
        field("material.E", &Scene::material, &MP::E, "Pa", "Young's modulus", "> 0", positive));
    k.push_back(field("material.nu", &Scene::material, &MP::nu, "", "Poisson's ratio",
                      "-1 < nu < 0.5", [](const double& v) { return v > -1 && v < 0.5; }));
    k.push_back(field("material.sigma_c", &Scene::material, &MP::sigma_c, "Pa",
                      "tensile strength (node-splitting threshold)", "> 0", positive));
    k.push_back(field("material.gamma", &Scene::material, &MP::gamma, "N/m",
                      "surface energy per unit reference area", "> 0", positive));
    k.push_back(field("material.zeta1", &Scene::material, &MP::zeta1, "",
                      "normalized dilatational damping (B.5)", ">= 0", non_negative));
    k.push_back(field("material.zeta2", &Scene::material, &MP::zeta2, "",
                      "normalized distortional damping (B.5)", ">= 0", non_negative));
    k.push_back(field("material.weibull_modulus", &Scene::material, &MP::weibull_modulus, "",
                      "Weibull modulus m of the nodes' strengths (mean sigma_c; "
                      "docs/branching.md); 0 = every node at sigma_c (the paper)",
                      "0 or 1 <= m <= 100",
                      [](const double& v) { return v == 0 || (v >= 1 && v <= 100); }));
    k.push_back(field("material.strength_seed", &Scene::material, &MP::strength_seed, "",
                      "seed of the nodes' Weibull strengths (the same seed, the same strengths "
                      "for any thread or rank count)",
                      ">= 0", [](const int& v) { return v >= 0; }));
    // [geometry] — the notched plate (SPEC 1)
    k.push_back(field("geometry.L", &Scene::geometry, &GP::L, "m",
                      "plate length along x (crack direction)", "> 0", positive));
    k.push_back(field("geometry.H", &Scene::geometry, &GP::H, "m",
                      "plate height along y (loading direction)", "> 0", positive));
    k.push_back(field("geometry.T", &Scene::geometry, &GP::T, "m", "plate thickness along z", "> 0",
                      positive));
    k.push_back(field("geometry.notch_depth", &Scene::geometry, &GP::notch_depth, "m",
                      "notch depth a, tip at (a, 0); 0 = no notch", "0 <= a < geometry.L",
                      non_negative));
    k.push_back(field("geometry.notch_base", &Scene::geometry, &GP::notch_base, "m",
                      "notch opening b at x = 0", "0 <= b < geometry.H", non_negative));
    // [mesh]
    k.push_back(typed<std::string>(
        "mesh.file", "", "Gmsh .msh or VTK .vtu tet mesh to read instead of generating",
        "empty = generate; relative to the scene file's directory", std::string(), "\"\"",
        [](const std::string& v, const Source& src, Scene& scene) {
          if (v.empty()) {
            scene.mesh.file.clear();
          } else {
            const fs::path p(v);
            scene.mesh.file =
                (p.is_relative() && !src.dir.empty() ? src.dir / p : p).lexically_normal().string();
          }
          return Verdict::ok;
        }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> { return s.mesh.file; };
    k.push_back(typed<std::string>(
        "mesh.parts", "",
        "directory of the scene's mesh cut into parts (the partition command's --out, "
        "parts_N): each of N MPI ranks reads only its part (docs/parallel.md)",
        "empty = every rank gets the whole mesh; relative to the scene file's directory",
        std::string(), "\"\"", [](const std::string& v, const Source& src, Scene& scene) {
          const fs::path p(v);
          scene.mesh.parts = v.empty() ? std::string()
                                       : (p.is_relative() && !src.dir.empty() ? src.dir / p : p)
                                             .lexically_normal()
                                             .string();
          return Verdict::ok;
        }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> { return s.mesh.parts; };
    k.push_back(field("mesh.size", &Scene::mesh, &MeP::size, "m",
                      "target element size h away from the band", "> 0", positive));
    k.push_back(field("mesh.band", &Scene::mesh, &MeP::band, "m",
                      "half-width of the refined band |y| < band (0 = none)", ">= 0",
                      non_negative));
    k.push_back(field("mesh.band_size", &Scene::mesh, &MeP::band_size, "m",
                      "element size inside the band (0 = mesh.size)", ">= 0", non_negative));
    k.push_back(field("mesh.layers", &Scene::mesh, &MeP::layers, "",
                      "element layers through the thickness", ">= 1",
                      [](const int& v) { return v >= 1; }));
    k.push_back(field("mesh.perturb", &Scene::mesh, &MeP::perturb, "",
                      "nodal perturbation: nodes off the lateral boundary move in x-y by up to "
                      "this fraction of their shortest in-plane edge (against mesh-aligned crack "
                      "paths; 0 = none)",
                      ">= 0 and <= 0.3", [](const double& v) { return v >= 0 && v <= 0.3; }));
    k.push_back(field("mesh.perturb_seed", &Scene::mesh, &MeP::perturb_seed, "",
                      "seed of the nodal perturbation (the same seed, the same mesh)", ">= 0",
                      [](const int& v) { return v >= 0; }));
    k.push_back(word("mesh.algorithm", &Scene::mesh, &MeP::algorithm,
                     "Gmsh's 2D algorithm for the generated plate (docs/mesh.md)",
                     "frontal-delaunay (Gmsh's default: rows of near-equilateral triangles) | "
                     "delaunay (less regular: cracks on faces follow no rows) | meshadapt",
                     {{"frontal-delaunay", MeP::Algorithm::frontal_delaunay},
                      {"delaunay", MeP::Algorithm::delaunay},
                      {"meshadapt", MeP::Algorithm::meshadapt}}));
    k.push_back(field("mesh.max_elements", &Scene::mesh, &MeP::max_elements, "",
                      "refuse a generated plate estimated to have more tets than this (about "
                      "0.7 kB each)",
                      "> 0", positive));
    // [loading] — exactly one of the two; a later source's choice clears the earlier one
    k.push_back(typed<double>("loading.sigma_over_sigmac", "",
                              "uniaxial pre-stress along y as a fraction of sigma_c",
                              "0 < s < 3; give this or loading.sigma", std::nullopt, "(unset)",
                              [](const double& v, const Source&, Scene& scene) {
                                if (!(v > 0 && v < 3)) return Verdict::out_of_range;
                                scene.loading.sigma_over_sigmac = v;
                                scene.loading.sigma = std::numeric_limits<double>::quiet_NaN();
                                return Verdict::ok;
                              }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> {
      if (std::isnan(s.loading.sigma_over_sigmac)) return std::nullopt;
      return format_double(s.loading.sigma_over_sigmac);
    };
    k.push_back(
        typed<double>("loading.sigma", "Pa", "uniaxial pre-stress along y",
                      "> 0 and < 3K = E/(1-2nu); give this or loading.sigma_over_sigmac",
                      std::nullopt, "(unset)", [](const double& v, const Source&, Scene& scene) {
                        if (!(v > 0)) return Verdict::out_of_range;
                        scene.loading.sigma = v;
                        scene.loading.sigma_over_sigmac = std::numeric_limits<double>::quiet_NaN();
                        return Verdict::ok;
                      }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> {
      if (std::isnan(s.loading.sigma)) return std::nullopt;
      return format_double(s.loading.sigma);
    };
    // [initial] — the state at t = 0 (initial velocities: [initial.NAME] sections)
    k.push_back(word("initial.state", &Scene::initial, &InitialParams::state, "state at t = 0",
                     "prestress (the uniaxial pre-stress of [loading], (B.6)-(B.9)) | rest",
                     {{"prestress", InitialParams::State::prestress},
                      {"rest", InitialParams::State::rest}}));
    // [fracture] — node splitting and nodal cohesive forces (SPEC 5)
    k.push_back(word(
        "fracture.mode", &Scene::fracture, &FP::mode, "which nodes may split",
        "none | straight (only y = 0, x >= a, normal stress (6.7)) | branching (any node)",
        {{"none", FP::Mode::none}, {"straight", FP::Mode::straight}, {"branching", FP::Mode::branching}}));
    k.push_back(
        word("fracture.criterion", &Scene::fracture, &FP::criterion,
             "how a node fails (docs/fracture-criteria.md)",
             "nodal-stress (the paper's (2.10)-(2.12): sigma1 of the nodal average "
             "reaches sigma_c) | energy (the energy of a plane's tractions within "
             "fracture.epsilon reaches 2 gamma per unit crack area; branching mode) | facet "
             "(element faces open when their traction reaches the strength; nodes split where "
             "open faces cut their cells apart; branching mode)",
             {{"nodal-stress", FP::Criterion::nodal_stress},
              {"energy", FP::Criterion::energy},
              {"facet", FP::Criterion::facet}}));
    k.push_back(field("fracture.epsilon", &Scene::fracture, &FP::epsilon, "m",
                      "the energy criterion's length: the radius of the ball whose energy a "
                      "split releases (0 = 3 x the median element size)",
                      ">= 0", non_negative));
    k.push_back(field("fracture.beta", &Scene::fracture, &FP::beta, "",
                      "the facet criterion's shear weight: a face's effective traction is "
                      "sqrt(<t_n>^2 + t_s^2 / beta^2); 0 = the normal traction alone",
                      ">= 0", non_negative));
    k.push_back(word("fracture.facet_link", &Scene::fracture, &FP::facet_link,
                     "the facet criterion's link strength f0 (docs/fracture-criteria.md)",
                     "traction (Akantu's extrinsic insertion: the effective traction each crack "
                     "face reached when it opened, times a third of its area; delta_c = 2 A_c "
                     "gamma / f0) | imbalance (the paper's (2.6): the force that holds the "
                     "daughters together at the split)",
                     {{"traction", FP::FacetLink::traction},
                      {"imbalance", FP::FacetLink::imbalance}}));
    k.push_back(field("fracture.alpha", &Scene::fracture, &FP::alpha, "s",
                      "rate parameter of the degradation law (4.4); 0 = rate-independent (3.5), "
                      "paper RD: 9.35e-8",
                      ">= 0", non_negative));
    k.push_back(field("fracture.n", &Scene::fracture, &FP::n, "", "exponent of (4.4)", ">= 0",
                      non_negative));
    k.push_back(field("fracture.speed_window_start", &Scene::fracture, &FP::speed_window_start, "s",
                      "steady crack speed is fitted from this time on", ">= 0", non_negative));
    k.push_back(field("fracture.speed_edge_margin", &Scene::fracture, &FP::speed_edge_margin, "m",
                      "... until the tip is this close to x = L", ">= 0", non_negative));
    k.push_back(typed<std::string>(
        "fracture.region", "m",
        "where nodes may break: x_min, x_max, y_min, y_max of the reference position",
        "four numbers, x_min < x_max, y_min < y_max; empty = anywhere", std::string(), "\"\"",
        [](const std::string& v, const Source&, Scene& scene) {
          NumberList list = parse_number_list(v);
          if (list.bad) return Verdict::malformed;
          const std::vector<double>& r = list.values;
          if (!r.empty() && (r.size() != 4 || r[0] >= r[1] || r[2] >= r[3]))
            return Verdict::out_of_range;
          scene.fracture.region = std::move(list.values);
          return Verdict::ok;
        }));
    k.back().type_word = "a list of numbers";
    k.back().get = [](const Scene& s) -> std::optional<std::string> {
      return number_list_text(s.fracture.region);
    };
    k.push_back(field("fracture.min_branch_length", &Scene::fracture, &FP::min_branch_length, "m",
                      "crack pattern (branches.csv): crack tracks shorter than this are spurs, "
                      "not branches (0 = the tracker's join distance, 4 element sizes)",
                      ">= 0", non_negative));
    k.push_back(field("fracture.track_join", &Scene::fracture, &FP::track_join, "m",
                      "crack tracker: a split within this distance of a crack's tip or path "
                      "belongs to that crack, and two arms are a branching once twice this apart "
                      "(0 = 4 element sizes; wider for cracks with side cracks, docs/crack_fronts.md)",
                      ">= 0", non_negative));
    // [damage] — continuum damage (SPEC 6, paper section 5)
    k.push_back(field("damage.beta1", &Scene::damage, &DP::beta1, "1/s",
                      "damage rate (5.2); 0 = no damage, paper: 5e6", ">= 0", non_negative));
    k.push_back(field("damage.beta2", &Scene::damage, &DP::beta2, "", "(5.3); paper: 10", ">= 0",
                      non_negative));
    k.push_back(field("damage.beta3", &Scene::damage, &DP::beta3, "",
                      "damage threshold as a fraction of sigma_c (5.3); paper: 0.95", "0 < b3 < 1",
                      [](const double& v) { return v > 0 && v < 1; }));
    k.push_back(typed<double>("damage.Omega_d0", "", "largest damage (5.3)",
                              "0 <= Omega_d0 < 1; unset = 1 - (v_inf/v_R)^2 (6.6) = 0.445",
                              std::nullopt, "(from v_inf, v_R)",
                              [](const double& v, const Source&, Scene& scene) {
                                if (!(v >= 0 && v < 1)) return Verdict::out_of_range;
                                scene.damage.Omega_d0 = v;
                                return Verdict::ok;
                              }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> {
      if (std::isnan(s.damage.Omega_d0)) return std::nullopt;
      return format_double(s.damage.Omega_d0);
    };
    k.push_back(field("damage.v_inf", &Scene::damage, &DP::v_inf, "m/s",
                      "limiting crack speed of the Zhou fit, for Omega_d0 (6.6)", "> 0", positive));
    k.push_back(field("damage.v_R", &Scene::damage, &DP::v_R, "m/s",
                      "Rayleigh speed, for Omega_d0 (6.6)", "> damage.v_inf", positive));
    // [run]
    k.push_back(
        field("run.end_time", &Scene::run, &RP::end_time, "s", "simulated time", "> 0", positive));
    k.push_back(field("run.cfl", &Scene::run, &RP::cfl, "", "fraction of the stable time step",
                      "0 < cfl <= 1", [](const double& v) { return v > 0 && v <= 1; }));
    k.push_back(word("run.step_bound", &Scene::run, &RP::step_bound,
                     "what the stable time step bounds (docs/model.md, \"Stable step\")",
                     "altitude (each element's smallest altitude over c_p; cfl 0.5 keeps it "
                     "under the element's own limit) | nodal (the grid's largest frequency, "
                     "node by node from the elements' exact stiffness; cfl 1 is the limit, "
                     "follows node splits)",
                     {{"altitude", RP::StepBound::altitude}, {"nodal", RP::StepBound::nodal}}));
    k.push_back(field("run.threads", &Scene::run, &RP::threads, "",
                      "OpenMP threads (0 = all cores)", "0 <= threads <= 1024",
                      [](const int& v) { return v >= 0 && v <= 1024; }));
    k.push_back(field("run.stop_when_cut_through", &Scene::run, &RP::stop_when_cut_through, "",
                      "stop once a crack from a notch has reached the plate's outer boundary "
                      "(the summary's cut_through)",
                      "true/false (also yes/no, on/off, 1/0)", [](const bool&) { return true; }));
    // [output]
    k.push_back(
        typed<std::string>("output.directory", "", "where frames, CSV files and the summary go",
                           "not empty; relative to the working directory; --out overrides it",
                           Scene{}.output.directory, show(Scene{}.output.directory),
                           [](const std::string& v, const Source&, Scene& scene) {
                             if (v.empty()) return Verdict::out_of_range;
                             scene.output.directory = v;
                             return Verdict::ok;
                           }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> { return s.output.directory; };
    k.push_back(field("output.frame_interval", &Scene::output, &OP::frame_interval, "s",
                      "VTU frame every this much simulated time (0 = none)", ">= 0", non_negative));
    k.push_back(time_list("output.frame_times",
                          "explicit frame times, comma/space separated; override "
                          "output.frame_interval",
                          [](Scene& s) -> std::vector<double>& { return s.output.frame_times; }));
    k.push_back(field("output.vtu", &Scene::output, &OP::vtu, "",
                      "write VTU frames + a PVD collection",
                      "true/false (also yes/no, on/off, 1/0)", [](const bool&) { return true; }));
    k.push_back(field("output.energy_interval", &Scene::output, &OP::energy_interval, "s",
                      "energies.csv row every this much simulated time", "> 0", positive));
    k.push_back(field("output.imbalance_warning", &Scene::output, &OP::imbalance_warning, "",
                      "warn once when the energy budget is off by more than this fraction of "
                      "the initial energy",
                      "> 0", positive));
    k.push_back(field("output.checkpoint_interval", &Scene::output, &OP::checkpoint_interval, "s",
                      "write checkpoint.bin (the whole state, for brittle run --resume) every this "
                      "much simulated time and at the end (0 = only when the run is stopped)",
                      ">= 0", non_negative));
    // [render] — PNG frames through off-screen VTK (docs/rendering.md)
    k.push_back(time_list("render.times",
                          "render PNG frames during the run at these times (also written as VTU)",
                          [](Scene& s) -> std::vector<double>& { return s.render.times; }));
    k.push_back(typed<std::string>(
        "render.fields", "", "which fields to render, comma/space separated",
        "sigma1 (sigma1/sigma_c), damage (Omega) and/or crack (cracked faces and tips)",
        std::string("sigma1, damage"), "sigma1, damage",
        [](const std::string& v, const Source&, Scene& scene) {
          std::vector<std::string> fields = list_words(lower(v));
          for (const std::string& f : fields)
            if (f != "sigma1" && f != "damage" && f != "crack") return Verdict::out_of_range;
          if (fields.empty()) return Verdict::out_of_range;
          scene.render.fields = std::move(fields);
          return Verdict::ok;
        }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> {
      std::string text;
      for (const std::string& f : s.render.fields) text += (text.empty() ? "" : ", ") + f;
      return text;
    };
    k.back().choices = {"sigma1", "damage", "crack"};
    k.push_back(field("render.width", &Scene::render, &ReP::width, "px", "PNG frame width",
                      "16 ... 8192", [](const int& v) { return v >= 16 && v <= 8192; }));
    k.push_back(field("render.height", &Scene::render, &ReP::height, "px", "PNG frame height",
                      "16 ... 8192", [](const int& v) { return v >= 16 && v <= 8192; }));
    k.push_back(field("render.sigma1_min", &Scene::render, &ReP::sigma1_min, "",
                      "sigma1/sigma_c at the bottom of the colour bar", "< render.sigma1_max",
                      [](const double&) { return true; }));
    k.push_back(field("render.sigma1_max", &Scene::render, &ReP::sigma1_max, "",
                      "sigma1/sigma_c at the top of the colour bar", "> render.sigma1_min",
                      [](const double&) { return true; }));
    k.push_back(field("render.damage_min", &Scene::render, &ReP::damage_min, "",
                      "Omega at the bottom of the colour bar", "< render.damage_max",
                      [](const double&) { return true; }));
    k.push_back(field("render.damage_max", &Scene::render, &ReP::damage_max, "",
                      "Omega at the top of the colour bar", "> render.damage_min",
                      [](const double&) { return true; }));
    k.push_back(field("render.magnification", &Scene::render, &ReP::magnification, "",
                      "displacement magnification (1 = true deformed shape, 0 = reference)", ">= 0",
                      non_negative));
    k.push_back(field("render.zoom", &Scene::render, &ReP::zoom, "",
                      "camera zoom about the plate centre (1 = whole plate)", "> 0", positive));
    k.push_back(word("render.colormap", &Scene::render, &ReP::colormap,
                     "colour ramp of sigma1 and Omega frames",
                     "jet (blue -> red, the paper's) | viridis (perceptually uniform)",
                     {{"jet", ReP::Colormap::jet}, {"viridis", ReP::Colormap::viridis}}));
    k.push_back(typed<std::string>("render.directory", "", "where PNG frames go",
                                   "empty = <output.directory>/render", std::string(), "\"\"",
                                   [](const std::string& v, const Source&, Scene& scene) {
                                     scene.render.directory = v;
                                     return Verdict::ok;
                                   }));
    k.back().get = [](const Scene& s) -> std::optional<std::string> { return s.render.directory; };
    return k;
  }();
  return keys;
}

/// The sections that have keys, in table order.
const std::vector<std::string>& known_sections() {
  static const std::vector<std::string> sections = [] {
    std::vector<std::string> s;
    for (const Key& k : scene_keys())
      if (s.empty() || s.back() != k.section()) s.push_back(k.section());
    return s;
  }();
  return sections;
}

bool is_known_section(const std::string& section) {
  const auto& s = known_sections();
  return std::find(s.begin(), s.end(), section) != s.end();
}

const Key* find_key(const std::string& name) {
  for (const Key& k : scene_keys())
    if (k.name == name) return &k;
  return nullptr;
}

const po::options_description& description() {
  static const po::options_description desc = [] {
    po::options_description d("Scene keys");
    auto add = d.add_options();
    for (const Key& k : scene_keys()) k.declare(add, k);
    return d;
  }();
  return desc;
}

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

// ---------------------------------------------------------------------------------------------
// Named sections: [boundary.NAME], [initial.NAME], [notch.NAME], any number of each.

/// One key of a named section: what it expects and how it is read into the section's struct.
struct NamedKey {
  std::string kind;  ///< "boundary", "initial", "notch"
  std::string key;   ///< "traction"
  std::string unit, expected;
};

const std::vector<NamedKey>& named_keys() {
  static const std::vector<NamedKey> keys = {
      {"notch", "start", "m", "x, y of the notch mouth, on the plate's outline"},
      {"notch", "direction", "", "dx, dy: direction from the mouth to the tip (normalised)"},
      {"notch", "length", "m", "> 0: distance from the mouth to the tip"},
      {"notch", "opening", "m", "> 0: width at the mouth"},
      {"notch", "shape", "", "wedge (closes to a point at the tip) | slot (constant width)"},
      {"boundary", "type", "", "fixed | velocity | traction"},
      {"boundary", "box", "m",
       "x_min, x_max, y_min, y_max, z_min, z_max of the reference position (inf allowed)"},
      {"boundary", "group", "", "name of a physical group of the .msh mesh (instead of box)"},
      {"boundary", "components", "", "fixed / velocity: which of x, y, z (default all)"},
      {"boundary", "velocity", "m/s", "vx, vy, vz (type = velocity)"},
      {"boundary", "traction", "Pa", "tx, ty, tz per unit reference area (type = traction)"},
      {"boundary", "history", "", "constant | ramp | table (default constant)"},
      {"boundary", "start", "s", ">= 0: the load is zero before this time (default 0)"},
      {"boundary", "ramp_time", "s", "> 0: history = ramp rises from 0 to 1 over this time"},
      {"boundary", "table", "", "history = table: t0, f0, t1, f1, ... with t ascending"},
      {"initial", "box", "m", "as boundary.box"},
      {"initial", "group", "", "as boundary.group"},
      {"initial", "velocity", "m/s", "vx, vy, vz at t = 0"},
      {"sensor", "position", "m", "x, y, z: the node nearest to it records (put it on a surface)"},
      {"sensor", "direction", "", "nx, ny, nz: the velocity component recorded (normalised)"},
  };
  return keys;
}

struct NamedValue {
  std::string value, label;  ///< the text and the source that set it last
};
struct NamedSection {
  std::string kind, name;
  std::map<std::string, NamedValue> keys;
};

/// "boundary.top.traction" -> its kind, name and key, if it is a named-section key.
std::optional<std::array<std::string, 3>> split_named(const std::string& full) {
  const auto a = full.find('.');
  const auto b = full.rfind('.');
  if (a == std::string::npos || a == b || a == 0 || b == a + 1 || b + 1 == full.size())
    return std::nullopt;
  const std::string kind = full.substr(0, a);
  if (kind != "boundary" && kind != "initial" && kind != "notch" && kind != "sensor")
    return std::nullopt;
  return std::array<std::string, 3>{kind, full.substr(a + 1, b - a - 1), full.substr(b + 1)};
}

const NamedKey* find_named_key(const std::string& kind, const std::string& key) {
  for (const NamedKey& k : named_keys())
    if (k.kind == kind && k.key == key) return &k;
  return nullptr;
}

/// Reads named sections into the scene, checking every value and the keys each type needs.
class NamedReader {
 public:
  explicit NamedReader(const NamedSection& s) : s_(s) {}
  bool has(const std::string& key) const { return s_.keys.count(key) > 0; }
  std::string where(const std::string& key) const {
    auto it = s_.keys.find(key);
    return (it == s_.keys.end() ? std::string("scene") : it->second.label) + ": " + s_.kind + "." +
           s_.name + "." + key;
  }
  [[noreturn]] void bad(const std::string& key, const std::string& why = "") const {
    const NamedKey* k = find_named_key(s_.kind, key);
    throw Error(error_message(where(key), " = '", s_.keys.at(key).value, "' ",
                              why.empty() ? "is not valid" : why, " (expected ",
                              k->unit.empty() ? "" : "in " + k->unit + ", ", k->expected, ")"));
  }
  void require(const std::string& key, const std::string& because) const {
    if (has(key)) return;
    const NamedKey* k = find_named_key(s_.kind, key);
    const std::string label = s_.keys.empty() ? "scene" : s_.keys.begin()->second.label;
    throw Error(error_message(label, ": [", s_.kind, ".", s_.name, "] needs ", key, " ", because,
                              " (expected ", k->expected, ")"));
  }
  std::string word(const std::string& key, std::initializer_list<const char*> allowed) const {
    const std::string v = lower(s_.keys.at(key).value);
    std::string words;
    for (const char* a : allowed) {
      if (v == a) return v;
      words += (words.empty() ? "" : ", ") + std::string(a);
    }
    bad(key, "is not one of: " + words + " (case does not matter)");
  }
  /// Numbers; `infinite` allows inf / -inf.
  std::vector<double> numbers(const std::string& key, std::size_t count,
                              bool infinite = false) const {
    std::vector<double> out;
    for (const std::string& t : list_words(s_.keys.at(key).value)) {
      if (infinite && (t == "inf" || t == "+inf" || t == "-inf")) {
        out.push_back(t == "-inf" ? -std::numeric_limits<double>::infinity()
                                  : std::numeric_limits<double>::infinity());
        continue;
      }
      const std::optional<double> v = parse_number(t);
      if (!v) bad(key, "is not a list of numbers");
      out.push_back(*v);
    }
    if (count > 0 && out.size() != count)
      bad(key, error_message("has ", out.size(), " numbers, not ", count));
    return out;
  }
  double number(const std::string& key) const { return numbers(key, 1)[0]; }
  RegionParams region() const {
    RegionParams r;
    if (has("box") && has("group"))
      throw Error(error_message(where("group"), ": give box or group, not both"));
    if (has("box")) {
      r.box = numbers("box", 6, true);
      for (int d = 0; d < 3; ++d)
        if (!(r.box[2 * d] <= r.box[2 * d + 1])) bad("box", "has a minimum above its maximum");
    } else if (has("group")) {
      r.group = s_.keys.at("group").value;
      if (r.group.empty()) bad("group", "is empty");
    } else {
      require("box", "or group: the region it acts on");
    }
    return r;
  }

 private:
  const NamedSection& s_;
};

void read_named_sections(const std::vector<NamedSection>& sections, Scene& scene) {
  for (const NamedSection& s : sections) {
    NamedReader r(s);
    if (s.kind == "notch") {
      NotchParams n;
      n.name = s.name;
      for (const char* key : {"start", "direction", "length", "opening"})
        r.require(key, "(every notch has start, direction, length and opening)");
      const std::vector<double> start = r.numbers("start", 2), dir = r.numbers("direction", 2);
      const double norm = std::hypot(dir[0], dir[1]);
      if (!(norm > 0)) r.bad("direction", "is the zero vector");
      n.start[0] = start[0], n.start[1] = start[1];
      n.direction[0] = dir[0] / norm, n.direction[1] = dir[1] / norm;
      n.length = r.number("length");
      if (!(n.length > 0)) r.bad("length", "is out of range");
      n.opening = r.number("opening");
      if (!(n.opening > 0)) r.bad("opening", "is out of range");
      if (r.has("shape"))
        n.shape = r.word("shape", {"wedge", "slot"}) == "slot" ? NotchParams::Shape::slot
                                                               : NotchParams::Shape::wedge;
      scene.geometry.notches.push_back(n);
    } else if (s.kind == "sensor") {
      SensorParams p;
      p.name = s.name;
      for (const char* key : {"position", "direction"})
        r.require(key, "(a sensor has a position and a direction)");
      const std::vector<double> x = r.numbers("position", 3), n = r.numbers("direction", 3);
      const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(norm > 0) || !std::isfinite(norm)) r.bad("direction", "is not a direction");
      for (int d = 0; d < 3; ++d) p.position[d] = x[d], p.direction[d] = n[d] / norm;
      scene.sensors.push_back(p);
    } else if (s.kind == "initial") {
      InitialVelocityParams v;
      v.name = s.name;
      v.region = r.region();
      r.require("velocity", "(an [initial.NAME] section sets an initial velocity)");
      const std::vector<double> vel = r.numbers("velocity", 3);
      std::copy(vel.begin(), vel.end(), v.velocity);
      for (const char* key :
           {"type", "components", "traction", "history", "start", "ramp_time", "table"})
        if (r.has(key)) r.bad(key, "is not a key of [initial.NAME]");
      scene.initial.velocities.push_back(v);
    } else {
      BoundaryParams b;
      b.name = s.name;
      r.require("type", "");
      const std::string type = r.word("type", {"fixed", "velocity", "traction"});
      b.type = type == "fixed"      ? BoundaryParams::Type::fixed
               : type == "velocity" ? BoundaryParams::Type::velocity
                                    : BoundaryParams::Type::traction;
      b.region = r.region();
      if (b.type != BoundaryParams::Type::traction && r.has("components")) {
        std::fill(b.components, b.components + 3, false);
        const std::vector<std::string> words = list_words(s.keys.at("components").value);
        if (words.empty()) r.bad("components", "is empty");
        for (const std::string& w : words) {
          if (w != "x" && w != "y" && w != "z") r.bad("components", "names an unknown component");
          b.components[w[0] - 'x'] = true;
        }
      } else if (r.has("components")) {
        r.bad("components", "is not a key of a traction (the traction vector has all three)");
      }
      const std::string value_key = type == "traction" ? "traction" : "velocity";
      const std::string other_key = type == "traction" ? "velocity" : "traction";
      if (r.has(other_key)) r.bad(other_key, "does not go with type = " + type);
      if (type == "fixed") {
        if (r.has("velocity")) r.bad("velocity", "does not go with type = fixed");
        for (const char* key : {"history", "start", "ramp_time", "table"})
          if (r.has(key)) r.bad(key, "does not go with type = fixed");
      } else {
        r.require(value_key, "for type = " + type);
        const std::vector<double> v = r.numbers(value_key, 3);
        std::copy(v.begin(), v.end(), b.value);
        const std::string history =
            r.has("history") ? r.word("history", {"constant", "ramp", "table"}) : "constant";
        if (r.has("start")) {
          b.history.start = r.number("start");
          if (!(b.history.start >= 0)) r.bad("start", "is out of range");
        }
        if (history == "ramp") {
          b.history.kind = TimeHistory::Kind::ramp;
          r.require("ramp_time", "for history = ramp");
          b.history.ramp_time = r.number("ramp_time");
          if (!(b.history.ramp_time > 0)) r.bad("ramp_time", "is out of range");
        } else if (r.has("ramp_time")) {
          r.bad("ramp_time", "needs history = ramp");
        }
        if (history == "table") {
          b.history.kind = TimeHistory::Kind::table;
          r.require("table", "for history = table");
          b.history.table = r.numbers("table", 0);
          const auto& t = b.history.table;
          if (t.size() < 2 || t.size() % 2) r.bad("table", "is not a list of (t, value) pairs");
          for (std::size_t i = 2; i < t.size(); i += 2)
            if (!(t[i] > t[i - 2])) r.bad("table", "has times that do not ascend");
          if (r.has("start")) r.bad("start", "does not go with history = table (give t in it)");
        } else if (r.has("table")) {
          r.bad("table", "needs history = table");
        }
      }
      scene.boundaries.push_back(b);
    }
  }
}

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

/// Checks between keys, after every source has been applied.
void check_scene(const Scene& s, const Origins& o, const std::vector<std::string>& files) {
  const GeometryParams& g = s.geometry;
  BRITTLE_CHECK(g.notch_depth < g.L, o.latest({"geometry.notch_depth", "geometry.L"}),
                ": geometry.notch_depth = ", format_double(g.notch_depth),
                " is out of range (expected 0 <= notch_depth < geometry.L = ", format_double(g.L),
                ")");
  BRITTLE_CHECK(g.notch_base < g.H, o.latest({"geometry.notch_base", "geometry.H"}),
                ": geometry.notch_base = ", format_double(g.notch_base),
                " is out of range (expected 0 <= notch_base < geometry.H = ", format_double(g.H),
                ")");

  if (!g.notches.empty()) {
    BRITTLE_CHECK(!o.by_key.count("geometry.notch_depth") && !o.by_key.count("geometry.notch_base"),
                  o.latest({"geometry.notch_depth", "geometry.notch_base"}),
                  ": geometry.notch_depth/notch_base and [notch.NAME] sections are both given "
                  "(expected one or the other: [notch.*] sections replace the paper's notch)");
    BRITTLE_CHECK(s.mesh.file.empty(), o.latest({"mesh.file"}),
                  ": [notch.NAME] sections shape the generated plate, but mesh.file = '",
                  s.mesh.file, "' is read instead (expected one or the other)");
    BRITTLE_CHECK(s.fracture.mode != FractureParams::Mode::straight, o.latest({"fracture.mode"}),
                  ": fracture.mode = straight follows the paper's notch (y = 0, x >= a) and "
                  "cannot be used with [notch.NAME] sections (expected branching or none)");
  }
  BRITTLE_CHECK(s.mesh.perturb == 0 || s.fracture.mode != FractureParams::Mode::straight,
                o.latest({"mesh.perturb", "fracture.mode"}),
                ": mesh.perturb moves the nodes of the paper's crack plane, which fracture.mode = "
                "straight splits (expected mesh.perturb = 0, or fracture.mode = branching)");
  if (s.fracture.criterion == FractureParams::Criterion::energy) {
    BRITTLE_CHECK(s.fracture.mode == FractureParams::Mode::branching,
                  o.latest({"fracture.criterion", "fracture.mode"}),
                  ": fracture.criterion = energy needs fracture.mode = branching (straight splits "
                  "the paper's plane by its normal stress (6.7))");
    BRITTLE_CHECK(s.material.weibull_modulus == 0,
                  o.latest({"fracture.criterion", "material.weibull_modulus"}),
                  ": fracture.criterion = energy has no per-node strengths (expected "
                  "material.weibull_modulus = 0)");
  }
  BRITTLE_CHECK(s.fracture.criterion != FractureParams::Criterion::facet ||
                    s.fracture.mode == FractureParams::Mode::branching,
                o.latest({"fracture.criterion", "fracture.mode"}),
                ": fracture.criterion = facet needs fracture.mode = branching (straight splits "
                "the paper's plane by its normal stress (6.7))");
  for (const BoundaryParams& b : s.boundaries)
    BRITTLE_CHECK(
        b.region.group.empty() || lower(fs::path(s.mesh.file).extension().string()) == ".msh",
        "[boundary.", b.name, "]: group = '", b.region.group,
        "' needs mesh.file to be a Gmsh .msh file with that physical group");
  for (const InitialVelocityParams& v : s.initial.velocities)
    BRITTLE_CHECK(
        v.region.group.empty() || lower(fs::path(s.mesh.file).extension().string()) == ".msh",
        "[initial.", v.name, "]: group = '", v.region.group,
        "' needs mesh.file to be a Gmsh .msh file with that physical group");

  const LoadingParams& l = s.loading;
  if (s.initial.state == InitialParams::State::prestress && std::isnan(l.sigma) &&
      std::isnan(l.sigma_over_sigmac)) {
    std::string where = "scene";
    if (!files.empty()) {
      where = files.size() == 1 ? "scene file" : "scene files";
      for (std::size_t i = 0; i < files.size(); ++i) where += (i ? ", '" : " '") + files[i] + "'";
    }
    throw Error(where +
                ": no load given (expected loading.sigma_over_sigmac or loading.sigma in "
                "[loading], or initial.state = rest with [boundary.NAME] loads)");
  }
  // The uniaxial pre-stress (SPEC 3) needs J = 1/(1 - sigma/(3K)) > 0.
  const double three_K = s.material.E / (1 - 2 * s.material.nu);
  const double sigma = l.stress(s.material);
  const bool by_ratio = std::isnan(l.sigma);
  BRITTLE_CHECK(s.initial.state != InitialParams::State::prestress || sigma < three_K,
                o.latest({by_ratio ? "loading.sigma_over_sigmac" : "loading.sigma", "material.E",
                          "material.nu", "material.sigma_c"}),
                ": load sigma = ", format_double(sigma),
                " Pa is out of range (expected < 3K = E/(1-2nu) = ", format_double(three_K),
                " Pa, else the uniaxial pre-stress has no solution)");

  // Guards: inputs that are each allowed but together would take the machine down.
  auto approx = [](double v) {  // 3 significant digits for estimates
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return std::string(text);
  };
  if (s.mesh.file.empty()) {
    // Shapes Gmsh meshes for minutes or forever (the tet estimate does not see them).
    const double longest = std::max(g.L, g.H), shortest = std::min(g.L, g.H);
    BRITTLE_CHECK(longest <= 1e3 * shortest, o.latest({"geometry.L", "geometry.H"}),
                  ": geometry.L x H = ", format_double(g.L), " x ", format_double(g.H),
                  " m (expected sides within a factor 1000 of each other)");
    BRITTLE_CHECK(s.mesh.size <= shortest, o.latest({"mesh.size", "geometry.L", "geometry.H"}),
                  ": mesh.size = ", format_double(s.mesh.size),
                  " m is larger than the plate's shorter side ", format_double(shortest),
                  " m (expected at most that)");
    const double tets = estimated_tets(g, s.mesh);
    BRITTLE_CHECK(tets <= s.mesh.max_elements,
                  o.latest({"mesh.size", "mesh.band", "mesh.band_size", "mesh.layers",
                            "geometry.L", "geometry.H", "mesh.max_elements"}),
                  ": the generated plate would have about ", approx(tets),
                  " tets (geometry.L x H = ", format_double(g.L), " x ", format_double(g.H),
                  " m, mesh.size = ", format_double(s.mesh.size), " m, mesh.layers = ",
                  s.mesh.layers, "), more than mesh.max_elements = ",
                  format_double(s.mesh.max_elements),
                  " (expected fewer; about 0.7 kB of memory per tet: raise mesh.max_elements if "
                  "the machine has it)");
  }
  constexpr double kMaxEnergyRows = 1e7, kMaxFrames = 1e5;
  const double rows = s.run.end_time / s.output.energy_interval;
  BRITTLE_CHECK(rows <= kMaxEnergyRows, o.latest({"output.energy_interval", "run.end_time"}),
                ": output.energy_interval = ", format_double(s.output.energy_interval),
                " s gives ", approx(rows), " energy rows over run.end_time = ",
                format_double(s.run.end_time), " s (expected at most ",
                format_double(kMaxEnergyRows), ")");
  const double frames = s.output.frame_interval > 0 ? s.run.end_time / s.output.frame_interval : 0;
  BRITTLE_CHECK(frames <= kMaxFrames, o.latest({"output.frame_interval", "run.end_time"}),
                ": output.frame_interval = ", format_double(s.output.frame_interval), " s gives ",
                approx(frames), " frames over run.end_time = ",
                format_double(s.run.end_time), " s (expected at most ",
                format_double(kMaxFrames), ")");

  const DamageParams& d = s.damage;
  BRITTLE_CHECK(d.v_inf < d.v_R, o.latest({"damage.v_inf", "damage.v_R"}),
                ": damage.v_inf = ", format_double(d.v_inf),
                " m/s is out of range (expected < "
                "damage.v_R = ",
                format_double(d.v_R), " m/s, so that Omega_d0 (6.6) lies in (0, 1))");

  const RenderParams& r = s.render;
  BRITTLE_CHECK(r.sigma1_min < r.sigma1_max, o.latest({"render.sigma1_min", "render.sigma1_max"}),
                ": render.sigma1_min = ", format_double(r.sigma1_min),
                " is not below "
                "render.sigma1_max = ",
                format_double(r.sigma1_max), " (expected min < max)");
  BRITTLE_CHECK(r.damage_min < r.damage_max, o.latest({"render.damage_min", "render.damage_max"}),
                ": render.damage_min = ", format_double(r.damage_min),
                " is not below "
                "render.damage_max = ",
                format_double(r.damage_max), " (expected min < max)");

  if (!s.mesh.file.empty()) {
    const std::string who = o.latest({"mesh.file"});
    const fs::path p(s.mesh.file);
    const std::string ext = lower(p.extension().string());
    BRITTLE_CHECK(ext == ".msh" || ext == ".vtu", who, ": mesh.file = '", s.mesh.file,
                  "' is not a .msh or .vtu file");
    std::error_code ec;
    BRITTLE_CHECK(fs::is_regular_file(p, ec) && std::ifstream(p).good(), who, ": mesh file '",
                  s.mesh.file, "' (mesh.file) cannot be opened");
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
