// The scene keys' table (scene_keys.hpp): the kinds of key (a number bound to a Scene member,
// a word bound to an enum, a list of times) and the table itself, from which the
// options_description, the `--help` text, the validation and scene.ini are all built.
#include "scene_keys.hpp"

#include <cctype>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "lists.hpp"

namespace brittle::scene_file {

std::string format_double(double v) {
  char buf[64];
  const double magnitude = v == 0 ? 0 : std::floor(std::log10(std::abs(v)));
  const auto style = (v == 0 || (magnitude >= -4 && magnitude < 7)) ? std::chars_format::fixed
                                                                    : std::chars_format::scientific;
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, style);
  return ec == std::errc() ? std::string(buf, end) : std::to_string(v);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

namespace {

namespace fs = std::filesystem;

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

}  // namespace

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
    k.push_back(word("material.plane", &Scene::material, &MP::plane,
                     "the out-of-plane state of a 2D body (docs/model.md, Two dimensions)",
                     "strain (F33 = 1) | stress (T33 = 0, solved per element)",
                     {{"strain", MP::Plane::strain}, {"stress", MP::Plane::stress}}));
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
    k.push_back(field("mesh.dimension", &Scene::mesh, &MeP::dimension, "",
                      "3: tets through the thickness; 2: triangles in the x-y plane, each a prism "
                      "of mesh.thickness in plane strain or stress (material.plane; issue 53)",
                      "2 or 3", [](const int& v) { return v == 2 || v == 3; }));
    k.push_back(field("mesh.thickness", &Scene::mesh, &MeP::thickness, "m",
                      "a 2D body's thickness, for its masses, areas and energies (0 = geometry.T)",
                      ">= 0", non_negative));
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
             "open faces cut their cells apart; branching mode) | nonlocal-facet (the facet "
             "criterion on stresses averaged over a ball of radius fracture.length; branching "
             "mode) | coupled-facet (a face opens at its strength when the energy over a ball "
             "of radius fracture.length reaches 2 gamma too, Leguillon; branching mode) | "
             "recovered-facet (the facet criterion on the stress recovered at the nodes over "
             "each node's patch of cells, Zienkiewicz-Zhu; branching mode)",
             {{"nodal-stress", FP::Criterion::nodal_stress},
              {"energy", FP::Criterion::energy},
              {"facet", FP::Criterion::facet},
              {"nonlocal-facet", FP::Criterion::nonlocal_facet},
              {"coupled-facet", FP::Criterion::coupled_facet},
              {"recovered-facet", FP::Criterion::recovered_facet}}));
    k.push_back(field("fracture.epsilon", &Scene::fracture, &FP::epsilon, "m",
                      "the energy criterion's length: the radius of the ball whose energy a "
                      "split releases (0 = 3 x the median element size)",
                      ">= 0", non_negative));
    k.push_back(field("fracture.length", &Scene::fracture, &FP::length, "m",
                      "the nonlocal facet criterion's material length l: a face's traction "
                      "comes from stresses averaged over a ball of radius l (Bazant's bell "
                      "weight), as the phase field's l0 or the peridynamic horizon (0 = 0.367 E "
                      "G_c / sigma_c^2: a tip at K = sqrt(E G_c) brings the average to sigma_c)",
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
    k.push_back(field("run.mass_scaling", &Scene::run, &RP::mass_scaling, "s",
                      "mass scaling (docs/performance.md): elements whose altitude-bound step at "
                      "cfl 0.5 is below this get the density that brings it to this; the dry run "
                      "and summary.json report the mass added; 0 = none",
                      ">= 0", non_negative));
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

}  // namespace brittle::scene_file
