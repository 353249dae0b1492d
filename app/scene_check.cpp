// The checks between scene keys (scene_check.hpp).
#include "scene_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "error.hpp"
#include "scene_keys.hpp"

namespace brittle::scene_file {

namespace fs = std::filesystem;

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
  if (s.mesh.dimension == 2) {  // what 2D runs do not have yet (issue 53; docs/model.md)
    const auto refuse = [&](bool ok, const char* key, const char* expected) {
      BRITTLE_CHECK(ok, o.latest({key, "mesh.dimension"}), ": ", key,
                    " is not available with mesh.dimension = 2 yet (expected ", expected, ")");
    };
    refuse(s.fracture.mode == FractureParams::Mode::none ||
               s.fracture.criterion == FractureParams::Criterion::nodal_stress ||
               s.fracture.criterion == FractureParams::Criterion::facet,
           "fracture.criterion", "fracture.criterion = nodal-stress or facet, or fracture.mode = none");
    // (the uniaxial pre-stress (B.6) is a plane-stress state: F33 = b, the element's root)
    refuse(s.initial.state == InitialParams::State::rest ||
               s.material.plane == MaterialParams::Plane::stress,
           "initial.state", "initial.state = rest, or material.plane = stress");
    refuse(s.mesh.file.empty(), "mesh.file", "the generated plate");
    refuse(s.run.mass_scaling == 0, "run.mass_scaling", "run.mass_scaling = 0");
    refuse(s.mesh.parts.empty(), "mesh.parts", "one process");
  }
  BRITTLE_CHECK(s.run.mass_scaling <= s.run.end_time, o.latest({"run.mass_scaling", "run.end_time"}),
                ": run.mass_scaling = ", format_double(s.run.mass_scaling),
                " s is longer than run.end_time = ", format_double(s.run.end_time),
                " s (expected a step shorter than the run)");
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
  using C = FractureParams::Criterion;
  const C c = s.fracture.criterion;
  const bool facets = c == C::facet || c == C::nonlocal_facet || c == C::coupled_facet ||
                      c == C::recovered_facet;
  BRITTLE_CHECK(!facets || s.fracture.mode == FractureParams::Mode::branching,
                o.latest({"fracture.criterion", "fracture.mode"}), ": fracture.criterion = ",
                c == C::facet             ? "facet"
                : c == C::nonlocal_facet  ? "nonlocal-facet"
                : c == C::coupled_facet   ? "coupled-facet"
                                          : "recovered-facet",
                " needs fracture.mode = branching (straight splits the paper's plane by its "
                "normal stress (6.7))");
  // A criterion's length given to another criterion would be ignored without a word.
  BRITTLE_CHECK(s.fracture.epsilon == 0 ||
                    s.fracture.criterion == FractureParams::Criterion::energy,
                o.latest({"fracture.epsilon", "fracture.criterion"}), ": fracture.epsilon = ",
                format_double(s.fracture.epsilon),
                " is the energy criterion's length, which this fracture.criterion does not use "
                "(expected fracture.criterion = energy, or no fracture.epsilon)");
  BRITTLE_CHECK(s.fracture.length == 0 || c == C::nonlocal_facet || c == C::coupled_facet,
                o.latest({"fracture.length", "fracture.criterion"}), ": fracture.length = ",
                format_double(s.fracture.length),
                " is the material length of the nonlocal and coupled facet criteria, which this "
                "fracture.criterion does not use (expected fracture.criterion = nonlocal-facet "
                "or coupled-facet, or no fracture.length)");
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

}  // namespace brittle::scene_file
