// `brittle study ensemble` (issue 51, docs/ensembles.md): the statistics by hand, a planted pair
// of members (one forks, one does not) counted right, bad --vary values refused with one line,
// and a tiny ensemble through the executable whose members repeat byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "ensemble.hpp"
#include "error.hpp"

namespace fs = std::filesystem;
using brittle_test::contains;
using brittle_test::run_brittle;
using brittle_test::TempDir;

namespace brittle {
namespace {

const std::string kScenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

TEST(Ensemble, QuartilesAndTheWilsonInterval) {
  const Quartiles q = quartiles({4, 1, 3, 2, std::nan("")});
  EXPECT_EQ(q.n, 4);
  EXPECT_DOUBLE_EQ(q.median, 2.5);
  EXPECT_DOUBLE_EQ(q.q1, 1.75);  // R's type 7: 1 + 0.75 (2 - 1)
  EXPECT_DOUBLE_EQ(q.q3, 3.25);
  EXPECT_TRUE(std::isnan(quartiles({}).median));
  // 7 of 8 at 90 %: (p + z^2/2n) / (1 + z^2/n) -+ z / (1 + z^2/n) sqrt(p q / n + z^2 / 4n^2),
  // z = 1.6449, worked by hand: 0.7802 -+ 0.1914.
  const auto [lo, hi] = wilson_90(7, 8);
  EXPECT_NEAR(lo, 0.5889, 2e-4);
  EXPECT_NEAR(hi, 0.9716, 2e-4);
  const auto [zero_lo, zero_hi] = wilson_90(0, 8);
  EXPECT_EQ(zero_lo, 0.0);
  EXPECT_GT(zero_hi, 0.0);
}

TEST(Ensemble, BadVaryIsRefusedWithOneLine) {
  EXPECT_THROW(parse_vary("seed"), Error);
  EXPECT_EQ(parse_vary("steps"), EnsembleVary::steps);
  TempDir dir;
  const fs::path out = dir / "ensemble";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"study", "ensemble", kScenes + "cm.ini", "--vary", "seeds",
                                 "--out", out.string()},
        {"study", "ensemble", kScenes + "cm.ini", "--vary", "strength", "--out", out.string()},
        {"study", "ensemble", kScenes + "cm.ini", "--vary", "mesh", "--members", "0", "--out",
         out.string()}}) {
    const auto r = run_brittle(dir, args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out / "member_01")) << r.err;  // nothing started
  }
  EXPECT_TRUE(contains(run_brittle(dir, {"study", "ensemble", kScenes + "cm.ini", "--vary",
                                         "seeds"}).err,
                       "--vary 'seeds' is not a variation (expected mesh, strength or steps)"));
  EXPECT_TRUE(contains(run_brittle(dir, {"study", "ensemble", kScenes + "cm.ini", "--vary",
                                         "strength"}).err,
                       "material.weibull_modulus = 0"));
}

// Two planted members: one whose pattern.json has a fork with both arms past the reach, one
// without: one fork of two, the medians those of the one.
TEST(Ensemble, APlantedPairIsCountedRight) {
  TempDir dir;
  const fs::path forked = dir / "member_01", straight = dir / "member_02";
  const std::string summary =
      R"({"status": "completed", "splits": 100, "crack_area": 2e-5,
          "max_relative_imbalance": 1e-3, "wall_seconds": 5})";
  write_text(forked / "summary.json", summary);
  write_text(straight / "summary.json", summary);
  write_text(forked / "pattern.json", R"({"fork": {"t": 4.5e-5, "x": 0.07, "y": 0.001,
      "angle_deg": 60, "arms": [
        {"tip": 1, "length": 0.03, "head": [7.5e-5, 0.1, 0.01], "reach_x": 0.1},
        {"tip": 2, "length": 0.025, "head": [7.6e-5, 0.095, -0.012], "reach_x": 0.095}]}})");
  write_text(straight / "pattern.json", R"({"fork": null})");
  std::vector<EnsembleMember> m = {read_member(forked.string(), 1, "mesh.perturb_seed=1", 0.09),
                                   read_member(straight.string(), 2, "mesh.perturb_seed=2", 0.09)};
  ASSERT_TRUE(m[0].fork);
  EXPECT_TRUE(m[0].both_reach);
  EXPECT_FALSE(m[1].fork);
  EXPECT_FALSE(m[1].both_reach);
  EXPECT_DOUBLE_EQ(m[0].arm_head_y[1], -0.012);
  // Reach 0.098 m: the second arm (0.095 m) falls short, so no Y, still a fork.
  EXPECT_FALSE(read_member(forked.string(), 1, "", 0.098).both_reach);
  EnsembleOptions o;
  o.scenes = {"plate.ini"};
  write_ensemble_tables(dir.path().string(), o, m, 0.09);
  std::ifstream in(dir / "ensemble.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["members"], 2);
  EXPECT_EQ(j["forks"], 1);
  EXPECT_DOUBLE_EQ(j["fork_rate"].get<double>(), 0.5);
  EXPECT_EQ(j["both_arms_reach"], 1);
  EXPECT_DOUBLE_EQ(j["quartiles"]["fork_x"]["median"].get<double>(), 0.07);
  EXPECT_EQ(j["quartiles"]["fork_x"]["n"], 1);
  EXPECT_EQ(j["quartiles"]["splits"]["n"], 2);
  EXPECT_DOUBLE_EQ(j["quartiles"]["shorter_arm_length"]["median"].get<double>(), 0.025);
  const auto [lo, hi] = wilson_90(1, 2);
  EXPECT_DOUBLE_EQ(j["fork_rate_ci90"][0].get<double>(), lo);
  EXPECT_DOUBLE_EQ(j["fork_rate_ci90"][1].get<double>(), hi);
  const std::string csv = read_text(dir / "ensemble.csv");
  EXPECT_TRUE(contains(csv, "\n1,\"mesh.perturb_seed=1\",1,0.07,")) << csv;
  EXPECT_TRUE(contains(csv, "\n2,\"mesh.perturb_seed=2\",0,,")) << csv;
}

// A tiny branching plate as two members varying the step boundaries, run twice: each member's
// events, energies and tips are the same bytes both times, and member 1 (the scene's own
// frames) is the plain `brittle run` of the same keys.
TEST(Ensemble, MembersRepeatByteForByte) {
  TempDir dir;
  const std::vector<std::string> common = {
      "study", "ensemble", kScenes + "cm.ini", kScenes + "branching.ini", "--vary", "steps",
      "--members", "2", "--jobs", "2", "--set", "mesh.size=2e-3", "--set", "geometry.T=2e-3",
      "--set", "run.end_time=8e-6", "--set", "output.frame_interval=2e-6"};
  std::vector<fs::path> outs = {dir / "a", dir / "b"};
  for (const fs::path& out : outs) {
    std::vector<std::string> args = common;
    args.insert(args.end(), {"--out", out.string()});
    const auto r = run_brittle(dir, args);
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_TRUE(contains(r.out, "forks: ")) << r.out;
    EXPECT_TRUE(fs::exists(out / "ensemble.png"));
  }
  for (const char* member : {"member_01", "member_02"})
    for (const char* file : {"events.csv", "energies.csv", "crack_tip.csv"}) {
      SCOPED_TRACE(std::string(member) + "/" + file);
      const std::string a = read_text(outs[0] / member / file);
      EXPECT_FALSE(a.empty());
      EXPECT_EQ(a, read_text(outs[1] / member / file));
    }
  const auto plain = run_brittle(
      dir, {"run", kScenes + "cm.ini", kScenes + "branching.ini", "--set", "run.threads=1",
            "--set", "mesh.size=2e-3", "--set", "geometry.T=2e-3", "--set", "run.end_time=8e-6",
            "--set", "output.frame_interval=2e-6", "--set", "output.vtu=false", "--out",
            (dir / "plain").string()});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(read_text(dir / "plain" / "events.csv"), read_text(outs[0] / "member_01" / "events.csv"));
  EXPECT_EQ(read_text(dir / "plain" / "energies.csv"),
            read_text(outs[0] / "member_01" / "energies.csv"));
  // The second member's frames are offset by half an interval: its own frame times.
  const std::string variation = read_text(outs[0] / "ensemble.csv");
  EXPECT_TRUE(contains(variation, "output.frame_times=1e-06,3e-06,5e-06,7e-06")) << variation;
}

}  // namespace
}  // namespace brittle
