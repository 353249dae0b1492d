// Load sweeps (issue: Figs. 5-6): parsing, the parallel runner through the executable, and
// that a sweep's run equals a single run of the same load.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "error.hpp"
#include "output.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"
#include "sweep.hpp"

namespace fs = std::filesystem;

namespace brittle {
namespace {

TEST(Sweep, ParsesLoads) {
  const auto range = parse_loads("0.4:1.0:0.05");
  ASSERT_EQ(range.size(), 13u);
  EXPECT_DOUBLE_EQ(range.front(), 0.4);
  EXPECT_NEAR(range.back(), 1.0, 1e-12);
  EXPECT_EQ(parse_loads("0.6,0.9"), (std::vector<double>{0.6, 0.9}));
  EXPECT_EQ(parse_loads("0.75"), (std::vector<double>{0.75}));
  for (const char* bad : {"", "0.4:1.0", "a,b", "0.4:1.0:0", "1.0:0.4:0.1", "0", "3.5", "0.5;0.6"})
    EXPECT_THROW(parse_loads(bad), Error) << bad;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A tiny straight-crack sweep through the executable, two loads on two processes; the 0.9
// run of the sweep gives the same numbers as `brittle run` at 0.9 on its own.
TEST(Sweep, ParallelRunsMatchSingleRuns) {
  const fs::path dir = fs::temp_directory_path() / "brittle_test_sweep";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "tiny.ini";
  std::ofstream(scene) << "[mesh]\nsize = 2e-3\n[loading]\nsigma_over_sigmac = 0.5\n"
                          "[fracture]\nmode = straight\nspeed_window_start = 4e-6\n"
                          "[run]\nend_time = 14e-6\n";
  const std::string exe = BRITTLE_EXE;
  const std::string sweep = exe + " sweep " + scene.string() + " --loads 0.7,0.9 --jobs 2 --out " +
                            (dir / "sweep").string() + " > " + (dir / "sweep.log").string() +
                            " 2>&1";
  ASSERT_EQ(std::system(sweep.c_str()), 0) << read(dir / "sweep.log");
  const std::string single = exe + " run " + scene.string() +
                             " --set loading.sigma_over_sigmac=0.9 --set output.vtu=false --out " +
                             (dir / "single").string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(single.c_str()), 0);

  EXPECT_GT(fs::file_size(dir / "sweep" / "sweep.png"), 1000u);
  const std::string csv = read(dir / "sweep" / "sweep.csv");
  EXPECT_NE(csv.find("sigma_over_sigmac,W,W_clamped,speed,fitted_speed,fit_r2"), std::string::npos)
      << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;
  const SweepPoint p = read_run((dir / "sweep" / "load_0.900").string());
  EXPECT_EQ(p.status, "completed");
  EXPECT_GT(p.speed, 100.0);
  EXPECT_FALSE(p.arrested);
  EXPECT_DOUBLE_EQ(p.W_clamped, p.W * (1 - 0.35 * 0.35)) << "W (1 - nu^2), nu = 0.35";
  EXPECT_EQ(p.window_end, "end of run");
  std::ifstream a_file(dir / "sweep" / "load_0.900" / "summary.json"),
      b_file(dir / "single" / "summary.json");
  const auto a = nlohmann::json::parse(a_file), b = nlohmann::json::parse(b_file);
  for (const char* key : {"crack_speed", "splits", "final_kinetic", "final_elastic",
                          "cohesive_dissipated", "viscous_dissipated", "tip_x"})
    EXPECT_EQ(a.at(key), b.at(key)) << key;
  EXPECT_EQ(a.at("threads"), 1);
}

// A run that blew up writes nulls for its non-finite numbers: read back they are NaN (no
// exception), so the sweep still writes sweep.csv with that row marked.
TEST(Sweep, NullsInASummaryReadAsNaN) {
  const fs::path dir = fs::temp_directory_path() / "brittle_sweep_nulls";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json")
      << R"({"status": "failed: blow-up", "sigma_over_sigmac": 0.9, "W": 11796.0,)"
      << R"( "crack_speed": null, "crack_speed_r2": null, "crack_speed_samples": 0,)"
      << R"( "tip_x": null, "zhou_speed": 618.0, "speed_stop_x": 0.03})";
  SweepPoint p;
  ASSERT_NO_THROW(p = read_run(dir.string()));
  EXPECT_EQ(p.status, "failed: blow-up");
  EXPECT_DOUBLE_EQ(p.load, 0.9);
  EXPECT_TRUE(std::isnan(p.fitted_speed));
  EXPECT_TRUE(std::isnan(p.r2));
  EXPECT_TRUE(std::isnan(p.tip_x));
  EXPECT_EQ(p.samples, 0);
  write_sweep_csv((dir / "sweep.csv").string(), {p});
  std::ifstream csv(dir / "sweep.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_NE(row.find("failed: blow-up"), std::string::npos) << row;
  // A summary that is not JSON at all (a run killed while writing it) is a failed run whose
  // status names the file: its row stays and the other loads still count.
  std::ofstream(dir / "summary.json") << "{\"status\": ";
  SweepPoint garbage;
  ASSERT_NO_THROW(garbage = read_run(dir.string()));
  EXPECT_EQ(
      garbage.status.rfind("failed: '" + (dir / "summary.json").string() + "' cannot be read", 0),
      0u)
      << garbage.status;
  EXPECT_TRUE(std::isnan(garbage.load));
  // Quotes in a status are doubled inside the quoted CSV field.
  garbage.status = "failed: element \"7\"";
  write_sweep_csv((dir / "sweep.csv").string(), {garbage});
  std::ifstream csv2(dir / "sweep.csv");
  std::getline(csv2, header);
  std::getline(csv2, row);
  EXPECT_NE(row.find(",\"failed: element \"\"7\"\"\","), std::string::npos) << row;
  EXPECT_FALSE(fs::exists(dir / "sweep.csv.tmp"));
}

// What SummaryWriter writes is what read_run reads (the same keys on both sides): a run that
// failed with NaN and infinite numbers reads back as NaN, its finite numbers as written.
TEST(Sweep, ReadRunReadsWhatTheSummaryWriterWrites) {
  const fs::path dir = fs::temp_directory_path() / "brittle_sweep_round_trip";
  fs::remove_all(dir);
  fs::create_directories(dir);
  Scene s;
  s.loading.sigma_over_sigmac = 0.5;
  s.geometry.H = 2e-3;
  auto mesh = generate_box_mesh(4e-3, 2e-3, 1e-3, 1e-3);
  Simulation sim(s, *mesh);
  RunSummary r;
  r.status = "failed: blow-up at t = 3e-06 s";
  r.sigma = 0.7 * s.material.sigma_c;
  r.W = 1234.5;
  r.zhou_speed = 456.25;
  r.tip_x = 2.5e-3;
  r.speed_stop_x = 3e-3;
  r.crack_speed.speed = std::nan("");
  r.crack_speed.r2 = std::numeric_limits<double>::infinity();
  r.crack_speed.samples = 7;
  write_file_atomically((dir / "summary.json").string(), summary_json(sim, r));
  SweepPoint p;
  ASSERT_NO_THROW(p = read_run(dir.string()));
  EXPECT_EQ(p.status, r.status);
  EXPECT_DOUBLE_EQ(p.load, 0.7);
  EXPECT_EQ(p.W, r.W);
  EXPECT_EQ(p.zhou_speed, r.zhou_speed);
  EXPECT_EQ(p.tip_x, r.tip_x);
  EXPECT_EQ(p.samples, 7);
  EXPECT_TRUE(std::isnan(p.fitted_speed));
  EXPECT_TRUE(std::isnan(p.speed));
  EXPECT_TRUE(std::isnan(p.r2));
}

// Every load's scene is checked before anything starts (issue 15): a load whose pre-stress the
// scene cannot take (0.9 sigma_c above 3K = E/(1-2nu)), a misspelt key and a missing file are
// one line each, naming the load, exit 2, and nothing is written. (A run that fails while
// running keeps its row in sweep.csv: Sweep.ABlownUpLoadKeepsItsRowAndTheOthers.)
TEST(Sweep, ABadSceneIsRefusedBeforeAnyRun) {
  const fs::path dir = fs::temp_directory_path() / "brittle_sweep_refused";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "tiny.ini";
  std::ofstream(scene)
      << "[mesh]\nsize = 2e-3\n[material]\nsigma_c = 2e10\n[run]\nend_time = 2e-6\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {scene.string() + " --loads 0.05,0.9", "load 0.900: "},
      {scene.string() + " --loads 0.05 --set material.Ee=1", "material.Ee"},
      {(dir / "missing.ini").string() + " --loads 0.05", "missing.ini"}};
  for (const auto& [args, expected] : cases) {
    SCOPED_TRACE(args);
    const std::string sweep = std::string(BRITTLE_EXE) + " sweep " + args + " --jobs 2 --out " +
                              (dir / "sweep").string() + " > " + (dir / "sweep.log").string() +
                              " 2>&1";
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(sweep.c_str());
    const std::string log = read(dir / "sweep.log");
    ASSERT_TRUE(WIFEXITED(status)) << log;
    EXPECT_EQ(WEXITSTATUS(status), 2) << log;
    EXPECT_NE(log.find(expected), std::string::npos) << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
    EXPECT_FALSE(fs::exists(dir / "sweep")) << "nothing is written";
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5)) << "no run started";
  }
}

// A sweep in which one load really blows up: a patch of nodes thrown at 40 km/s inverts an
// element in the first steps at 0.05 sigma_c, while at 0.5 sigma_c (sigma_c = 2e10 Pa: close to
// the 3K limit, where the pre-stressed plate is about 100 times stiffer) the same kick spreads
// and the run completes (checked for kicks of 10 to 40 km/s). sweep.csv keeps both rows, the
// blown-up one with the blow-up and the values written as null; the command exits 2.
TEST(Sweep, ABlownUpLoadKeepsItsRowAndTheOthers) {
  const fs::path dir = fs::temp_directory_path() / "brittle_sweep_blow_up";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = dir / "kick.ini";
  std::ofstream(scene)
      << "[mesh]\nsize = 2e-3\n[material]\nsigma_c = 2e10\n[run]\nend_time = 1e-6\n"
         "[initial.kick]\nbox = 0.014, 0.018, -0.002, 0.002, -inf, inf\n"
         "velocity = 0, 4e4, 0\n";
  const std::string sweep = std::string(BRITTLE_EXE) + " sweep " + scene.string() +
                            " --loads 0.05,0.5 --jobs 2 --out " + (dir / "sweep").string() + " > " +
                            (dir / "sweep.log").string() + " 2>&1";
  const int status = std::system(sweep.c_str());
  const std::string log = read(dir / "sweep.log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 2) << log;
  std::ifstream csv(dir / "sweep" / "sweep.csv");
  ASSERT_TRUE(csv) << "no sweep.csv: " << log;
  std::string header, failed, completed, extra;
  std::getline(csv, header);
  std::getline(csv, failed);
  std::getline(csv, completed);
  EXPECT_FALSE(std::getline(csv, extra)) << extra;
  EXPECT_EQ(failed.rfind("0.05,", 0), 0u) << failed;
  EXPECT_NE(failed.find(",\"failed: blow-up at t = "), std::string::npos) << failed;
  EXPECT_NE(failed.find("; non-finite values written as null: final_elastic"), std::string::npos)
      << failed;
  EXPECT_EQ(completed.rfind("0.5,", 0), 0u) << completed;
  EXPECT_NE(completed.find(",\"completed\","), std::string::npos) << completed;
  EXPECT_EQ(read_run((dir / "sweep" / "load_0.500").string()).status, "completed");
}

}  // namespace
}  // namespace brittle
