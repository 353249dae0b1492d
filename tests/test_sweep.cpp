// Load sweeps (issue: Figs. 5-6): parsing, the parallel runner through the executable, and
// that a sweep's run equals a single run of the same load.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "error.hpp"
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
  EXPECT_NE(csv.find("sigma_over_sigmac,W,speed,fitted_speed,fit_r2"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;
  const SweepPoint p = read_run((dir / "sweep" / "load_0.900").string());
  EXPECT_EQ(p.status, "completed");
  EXPECT_GT(p.speed, 100.0);
  EXPECT_FALSE(p.arrested);
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
  // A summary that is not JSON at all is an error naming the file.
  std::ofstream(dir / "summary.json") << "{\"status\": ";
  try {
    read_run(dir.string());
    FAIL() << "garbage must not read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("summary.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace brittle
