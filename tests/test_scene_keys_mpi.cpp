// Every scene key under mpirun (issue 52): each key of the scene format is listed with the case
// that runs it on 2 ranks against the serial run, or with the test that does, or with why it
// cannot change a decomposed run's bits. A key added to the format without an entry fails here,
// so a key that breaks parity is caught when it is added.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.hpp"
#include "mpi_helpers.hpp"
#include "scene_options.hpp"

namespace brittle {
namespace {

using namespace mpi_test;
using brittle_test::TempDir;

/// Every key `brittle run --help` lists: "section.key", and "kind.NAME.key" for the named
/// sections.
std::set<std::string> every_scene_key() {
  std::ostringstream text;
  print_scene_keys(text);
  std::set<std::string> keys;
  std::string section, line;
  std::istringstream in(text.str());
  const std::regex header(R"(^\[([a-z]+(\.NAME)?)\])"),
      key(R"(^  ([a-z_0-9]+(\.[a-z_0-9A-Z]+)*)\s)");
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, header)) {
      section = m[1];
    } else if (std::regex_search(line, m, key)) {
      const std::string name = m[1];
      keys.insert(name.find('.') == std::string::npos ? section + "." + name : name);
    }
  }
  return keys;
}

/// A case: the arguments of `brittle run` (scene files and --set) that the serial run and the
/// 2-rank run share.
struct Case {
  std::string name, args;
};

std::vector<Case> cases() {
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::string glass =
      quote(scenes + "glass-branching.ini") + " --set mesh.band_size=1e-3 --set run.end_time=40e-6";
  return {
      // the shipped glass scene (notch, traction boundaries, facet criterion) with the facet
      // keys and the output keys set away from their defaults
      {"glass-facet", glass + " --set fracture.beta=2 --set fracture.facet_link=traction"
                              " --set fracture.min_branch_length=2e-3"
                              " --set fracture.speed_edge_margin=3e-3"
                              " --set output.frame_times=10e-6,30e-6"
                              " --set output.energy_interval=0.2e-6"
                              " --set output.imbalance_warning=0.5"},
      // the criteria that read past one ghost layer (docs/parallel.md, "Ghost depth")
      {"nonlocal", glass + " --set fracture.criterion=nonlocal-facet --set fracture.length=2e-3"},
      {"coupled", glass + " --set fracture.criterion=coupled-facet"},
      {"recovered", glass + " --set fracture.criterion=recovered-facet"},
      // (with the paper's damage at a set Omega_d0)
      {"energy", glass + " --set fracture.criterion=energy --set fracture.epsilon=1.5e-3"
                         " --set damage.beta1=5e6 --set damage.beta2=10 --set damage.beta3=0.95"
                         " --set damage.Omega_d0=0.3"},
      // the paper's plate (pre-stress) with branching, damage and rate-dependent links, Weibull
      // strengths, a perturbed mesh, a fracture region, the nodal bound and mass scaling
      {"rm", quote(scenes + "rm.ini") + " " + quote(scenes + "branching.ini") + " " +
                 quote(scenes + "damage.ini") + " " + quote(scenes + "rate-dependent.ini") +
                 " --set run.end_time=8e-6 --set material.weibull_modulus=10"
                 " --set material.strength_seed=3 --set mesh.perturb=0.2"
                 " --set mesh.perturb_seed=5 --set fracture.region=-1,1,-2e-3,2e-3"
                 " --set run.step_bound=nodal --set run.mass_scaling=2e-8"
                 " --set fracture.criterion=nodal-stress"},
      // the paper's straight crack (6.7) under loading.sigma, with a speed window
      {"cm-straight", quote(scenes + "cm.ini") +
                          " --set run.end_time=10e-6 --set loading.sigma=60e6"
                          " --set fracture.speed_window_start=2e-6"},
      // Kalthoff-Winkler: fixed components, a ramped velocity; no stop at cut-through (a
      // table history and a delayed start: the case "table", below)
      {"kalthoff", quote(scenes + "kalthoff.ini") +
                       " --set run.end_time=35e-6 --set run.stop_when_cut_through=false"},
      // 2D bodies (issue 53): the glass plate in plane stress at another thickness, cracking
      // on edges; Kalthoff-Winkler in plane strain
      {"glass-2d", quote(scenes + "glass-branching.ini") + " " +
                       quote(scenes + "glass-branching-2d.ini") +
                       " --set mesh.band_size=1e-3 --set run.end_time=50e-6"
                       " --set mesh.thickness=0.8e-3"},
      {"kalthoff-2d", quote(scenes + "kalthoff.ini") + " " + quote(scenes + "kalthoff-2d.ini") +
                          " --set run.end_time=35e-6 --set run.stop_when_cut_through=false"},
  };
}

/// Where each key runs on 2 ranks against serial: "case NAME" (here), "test NAME" (another
/// test compares a decomposed run with serial there), or "none: why" (it cannot change the
/// bits of a decomposed run).
const std::map<std::string, std::string>& key_table() {
  static const std::map<std::string, std::string> table = [] {
    std::map<std::string, std::string> t;
    for (const char* k : {"rho0", "E", "nu", "sigma_c", "gamma", "zeta1", "zeta2"})
      t[std::string("material.") + k] = "case glass-facet";
    t["material.weibull_modulus"] = t["material.strength_seed"] = "case rm";
    for (const char* k : {"L", "H", "T"}) t[std::string("geometry.") + k] = "case glass-facet";
    t["geometry.notch_depth"] = t["geometry.notch_base"] = "case rm";
    t["mesh.size"] = t["mesh.band"] = t["mesh.band_size"] = t["mesh.layers"] = t["mesh.algorithm"] =
        "case glass-facet";
    t["mesh.perturb"] = t["mesh.perturb_seed"] = "case rm";
    t["mesh.file"] = "test Mpi.SensorsRenderTimesAndGroupRegionsMatchTheSerialRun";
    t["mesh.parts"] = "test Mpi.PartitionedMeshRunHoldsNoWholeGridArray";
    t["mesh.max_elements"] = "none: a guard on the mesh's size, checked before any rank steps";
    t["mesh.dimension"] = t["mesh.thickness"] = "case glass-2d";
    t["material.plane"] = "case kalthoff-2d";
    t["loading.sigma_over_sigmac"] = "case rm";
    t["loading.sigma"] = "case cm-straight";
    t["initial.state"] = "case rm";
    t["fracture.mode"] = "case cm-straight";
    t["fracture.criterion"] = "case nonlocal";
    t["fracture.epsilon"] = "case energy";
    t["fracture.length"] = "case nonlocal";
    t["fracture.beta"] = t["fracture.facet_link"] = t["fracture.min_branch_length"] =
        t["fracture.speed_edge_margin"] = t["fracture.track_join"] = "case glass-facet";
    t["fracture.alpha"] = t["fracture.n"] = t["fracture.region"] = "case rm";
    t["fracture.speed_window_start"] = "case cm-straight";
    for (const char* k : {"beta1", "beta2", "beta3", "v_inf", "v_R"})
      t[std::string("damage.") + k] = "case rm";
    t["damage.Omega_d0"] = "case energy";
    t["run.end_time"] = t["run.cfl"] = "case glass-facet";
    t["run.step_bound"] = t["run.mass_scaling"] = "case rm";
    t["run.threads"] =
        "none: every case runs one thread per rank; results do not depend on the thread count "
        "(Branching.*IndependentOfThreadCount)";
    t["run.stop_when_cut_through"] = "case kalthoff";
    t["output.directory"] = "none: where the files go";
    t["output.frame_interval"] = t["output.frame_times"] = t["output.energy_interval"] =
        t["output.imbalance_warning"] = "case glass-facet";
    t["output.vtu"] = "none: every case writes frames, compared by serial id";
    t["output.checkpoint_interval"] = "test Mpi.DecomposedFacetRunResumesOnAnyRankCount";
    t["render.times"] = "test Mpi.SensorsRenderTimesAndGroupRegionsMatchTheSerialRun";
    for (const char* k : {"fields", "width", "height", "sigma1_min", "sigma1_max", "damage_min",
                          "damage_max", "magnification", "zoom", "colormap", "directory"})
      t[std::string("render.") + k] =
          "none: how rank 0 draws the grid it gathers from the pieces, the serial drawing "
          "(Mpi.DecomposedRunWritesTheSerialFiles compares the PNGs)";
    for (const char* k : {"start", "direction", "length", "opening", "shape"})
      t[std::string("notch.NAME.") + k] = "case glass-facet";
    for (const char* k : {"type", "box", "traction"})
      t[std::string("boundary.NAME.") + k] = "case glass-facet";
    for (const char* k : {"components", "velocity", "history", "ramp_time"})
      t[std::string("boundary.NAME.") + k] = "case kalthoff";
    t["boundary.NAME.start"] = t["boundary.NAME.table"] = "case table";
    t["boundary.NAME.group"] = t["initial.NAME.group"] = t["initial.NAME.box"] =
        t["initial.NAME.velocity"] = "test Mpi.SensorsRenderTimesAndGroupRegionsMatchTheSerialRun";
    for (const char* k : {"position", "direction"})
      t[std::string("sensor.NAME.") + k] =
          "test Mpi.SensorsRenderTimesAndGroupRegionsMatchTheSerialRun";
    return t;
  }();
  return table;
}

/// The scene keys and the table agree: every key has an entry, every entry is a key, and
/// every case an entry names is run below.
TEST(SceneKeys, EveryKeyHasADecomposedCase) {
  const std::set<std::string> keys = every_scene_key();
  EXPECT_GT(keys.size(), 80u);
  std::set<std::string> names;
  for (const Case& c : cases()) names.insert(c.name);
  names.insert("table");  // (below: a scene file of its own)
  for (const std::string& k : keys)
    EXPECT_TRUE(key_table().count(k)) << k << ": a scene key with no decomposed case (add one)";
  for (const auto& [k, where] : key_table()) {
    EXPECT_TRUE(keys.count(k)) << k << ": not a scene key";
    if (where.starts_with("case "))
      EXPECT_TRUE(names.count(where.substr(5))) << k << ": " << where;
    else
      EXPECT_TRUE(where.starts_with("test Mpi.") || where.starts_with("none: ")) << k;
  }
}

/// Each case on 2 ranks writes the serial run's files: energies, tips, events, branches,
/// pattern, summary (timings aside) and the last frame by serial id.
TEST(Mpi, EverySceneKeysCaseRunsOnTwoRanksWithTheSerialBits) {
  TempDir dir;
  std::vector<Case> all = cases();
  {  // a table history and a delayed start: the glass plate pulled by a table of its own
    std::ofstream ini(dir / "table.ini");
    ini << "[boundary.top]\nhistory = table\ntable = 0, 0, 5e-6, 1, 40e-6, 1.2\n"
           "[boundary.bottom]\nstart = 1e-6\n";
    all.push_back({"table", quote(std::string(BRITTLE_SOURCE_DIR) + "/scenes/glass-branching.ini") +
                                " " + quote((dir / "table.ini").string()) +
                                " --set mesh.band_size=1e-3 --set run.end_time=30e-6"});
  }
  const std::string threads = " --set run.threads=1";
  for (const Case& c : all) {
    SCOPED_TRACE(c.name);
    const fs::path serial = dir / (c.name + "_serial"), out = dir / (c.name + "_np2");
    ASSERT_EQ(
        shell(quote(BRITTLE_EXE) + " run " + c.args + threads + " --out " + quote(serial.string()),
              dir / "serial.log"),
        0)
        << read_text(dir / "serial.log");
    ASSERT_EQ(shell(mpiexec(2) + " run " + c.args + threads + " --out " + quote(out.string()),
                    dir / "np2.log"),
              0)
        << read_text(dir / "np2.log");
    for (const char* file :
         {"energies.csv", "crack_tip.csv", "events.csv", "branches.csv", "pattern.json"})
      EXPECT_EQ(read_text(out / file), read_text(serial / file)) << file;
    std::ifstream a(out / "summary.json"), b(serial / "summary.json");
    nlohmann::json j = without_timings(nlohmann::json::parse(a)),
                   e = without_timings(nlohmann::json::parse(b));
    j.erase("threads"), e.erase("threads");
    if (c.name == "rm") {  // a tie in the last bits of the smallest scaled step (parallel.md)
      EXPECT_EQ(j["step_distribution"]["smallest"], e["step_distribution"]["smallest"]);
      j.erase("step_distribution"), e.erase("step_distribution");
    }
    EXPECT_EQ(j, e);
    EXPECT_GT(e["splits"].get<long>(), 0) << "the case should crack";
    const Frame expected = last_frame(serial, 0), got = last_frame(out, 2);
    EXPECT_EQ(got.points, expected.points);
    EXPECT_EQ(got.cells, expected.cells);
    for (const auto& [array, values] : expected.point)
      EXPECT_EQ(got.point.at(array), values) << array;
    for (const auto& [array, values] : expected.cell)
      EXPECT_EQ(got.cell.at(array), values) << array;
  }
}

}  // namespace
}  // namespace brittle
