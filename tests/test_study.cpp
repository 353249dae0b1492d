// The mesh-size study (issue 13 item 3, docs/mesh-study.md): the (6.10) capacity ratio by hand,
// the exponent fit, argument parsing, and the command on two tiny meshes through the
// executable: rows equal to what each run wrote, a bad scene refused before any run.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "error.hpp"
#include "scene_options.hpp"
#include "study.hpp"

namespace fs = std::filesystem;
using brittle_test::contains;
using brittle_test::run_brittle;
using brittle_test::TempDir;

namespace brittle {
namespace {

const std::string kScenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

TEST(Study, CapacityRatioIsEquation610) {
  // (6.10) with n = L/h: 4 E gamma alpha_t / (Omega_d0 sigma^2 h), alpha_t = 12.93, Omega_d0 =
  // 1 - (675/906)^2 (6.6), sigma = 0.9 x 75 MPa: 23.651 at h = 0.5 mm, by hand.
  const Scene scene = load_scene({kScenes + "cm.ini", kScenes + "damage.ini"}, {});
  const double omega = 1 - (675.0 / 906.0) * (675.0 / 906.0);
  const double expected = 4 * 3.09e9 * 150 * 12.93 / (omega * 67.5e6 * 67.5e6 * 500e-6);
  EXPECT_NEAR(capacity_ratio_6_10(scene, 500e-6), expected, 1e-12 * expected);
  EXPECT_NEAR(expected, 23.651, 0.001);
  EXPECT_DOUBLE_EQ(capacity_ratio_6_10(scene, 250e-6), 2 * capacity_ratio_6_10(scene, 500e-6));
  // Without damage there is no U_d to compare with.
  EXPECT_TRUE(std::isnan(capacity_ratio_6_10(load_scene({kScenes + "cm.ini"}, {}), 500e-6)));
}

TEST(Study, ExponentOfTheRatioIn1OverH) {
  std::vector<MeshStudyRow> rows;
  for (double h : {1e-3, 500e-6, 250e-6}) {
    MeshStudyRow a, b, c;
    a.label = "linear", a.size = h, a.ratio = 3e-4 / h;             // ~ h^-1, as (6.10)
    b.label = "square", b.size = h, b.ratio = 2e-7 / (h * h);        // ~ h^-2
    c.label = "no damage", c.size = h;                               // ratio NaN
    rows.insert(rows.end(), {a, b, c});
  }
  const auto e = study_exponents(rows);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].label, "linear");
  EXPECT_NEAR(e[0].exponent, 1.0, 1e-12);
  EXPECT_EQ(e[0].points, 3);
  EXPECT_NEAR(e[1].exponent, 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(e[2].exponent));
  EXPECT_EQ(e[2].points, 0);
}

TEST(Study, ParsesSizesAndCases) {
  EXPECT_EQ(parse_sizes("1e-3,500e-6"), (std::vector<double>{1e-3, 500e-6}));
  for (const char* bad : {"", "0", "-1e-3", "1e-3,x", "2"})
    EXPECT_THROW(parse_sizes(bad), Error) << bad;
  const StudyCase c = parse_case("branching+damage=a.ini,b.ini");
  EXPECT_EQ(c.label, "branching+damage");
  EXPECT_EQ(c.overlays, (std::vector<std::string>{"a.ini", "b.ini"}));
  EXPECT_TRUE(parse_case("straight").overlays.empty());
  for (const char* bad : {"", "=a.ini", "../x", "a/b", "..", "sp ace"})
    EXPECT_THROW(parse_case(bad), Error) << bad;
}

/// Two tiny meshes (h = 2 and 1 mm, 10 us), straight cracks with and without damage; the plate
/// is 2 mm thick so that the automatic layers differ (1 and 2).
TEST(Study, RunsOnTwoTinyMeshes) {
  TempDir dir;
  const fs::path out = dir / "study";
  const auto r = run_brittle(dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "2e-3,1e-3",
                                   "--case", "straight", "--case",
                                   "damage=" + kScenes + "damage.ini", "--set",
                                   "run.end_time=10e-6", "--set", "geometry.T=2e-3", "--jobs",
                                   "2", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_TRUE(contains(r.out, "damage: U_c/U_d ~ h^(")) << r.out;
  for (const char* chart : {"study_ratio.png", "study_area.png", "study_ae.png", "study_events.png"})
    EXPECT_TRUE(fs::exists(out / chart)) << chart;

  const nlohmann::json study = read_json(out / "study.json");
  ASSERT_EQ(study["rows"].size(), 4u);
  const std::vector<std::string> labels = {"straight", "straight", "damage", "damage"};
  const std::vector<double> sizes = {2e-3, 1e-3, 2e-3, 1e-3};
  const std::vector<int> layers = {1, 2, 1, 2};
  for (std::size_t i = 0; i < 4; ++i) {
    const nlohmann::json& row = study["rows"][i];
    SCOPED_TRACE(i);
    EXPECT_EQ(row["case"], labels[i]);
    EXPECT_DOUBLE_EQ(row["h"].get<double>(), sizes[i]);
    EXPECT_EQ(row["layers"], layers[i]);
    EXPECT_EQ(row["status"], "completed");
    const fs::path run = row["directory"].get<std::string>();
    EXPECT_EQ(run.filename(), i % 2 == 0 ? "h_2000um" : "h_1000um");
    // Each number is the run's own, read back unchanged.
    const nlohmann::json summary = read_json(run / "summary.json");
    EXPECT_EQ(row["tets"], summary["tets"]);
    EXPECT_EQ(row["splits"], summary["splits"]);
    EXPECT_GT(row["splits"].get<double>(), 0);
    EXPECT_EQ(row["U_c"], summary["cohesive_dissipated"]);
    EXPECT_EQ(row["U_d"], summary["damage_dissipated"]);
    const nlohmann::json pattern = read_json(run / "pattern.json");
    EXPECT_EQ(row["branches"], pattern["branches"]);
    EXPECT_EQ(row["area_over_2T_advance"], pattern["area_against_advance"].back()[3]);
    // The study's sensor: on the face z = T at (3/4 L, H/4), out-of-plane velocity.
    const nlohmann::json sensors = read_json(run / "sensors.json");
    ASSERT_EQ(sensors.size(), 1u);
    EXPECT_EQ(sensors[0]["name"], "ae");
    EXPECT_NEAR(sensors[0]["position"][2].get<double>(), 2e-3, 1e-12);
    EXPECT_EQ(row["ae_centroid_frequency"], sensors[0]["centroid_frequency"]);
    EXPECT_GT(row["ae_centroid_frequency"].get<double>(), 0);
    if (labels[i] == "straight") {
      EXPECT_EQ(row["U_d"].get<double>(), 0.0);
      EXPECT_TRUE(row["U_c_over_U_d"].is_null());
      EXPECT_TRUE(row["capacity_ratio_6_10"].is_null());
    } else {
      EXPECT_GT(row["U_d"].get<double>(), 0.0);
      EXPECT_DOUBLE_EQ(row["U_c_over_U_d"].get<double>(),
                       row["U_c"].get<double>() / row["U_d"].get<double>());
      EXPECT_GT(row["capacity_ratio_6_10"].get<double>(), 0.0);
    }
  }
  EXPECT_DOUBLE_EQ(study["rows"][3]["capacity_ratio_6_10"].get<double>(),
                   2 * study["rows"][2]["capacity_ratio_6_10"].get<double>());
  // study.csv: a header with units and one row per run.
  std::ifstream csv(out / "study.csv");
  std::string line;
  int lines = 0;
  std::getline(csv, line);
  EXPECT_TRUE(contains(line, "h_m,layers,tets")) << line;
  EXPECT_TRUE(contains(line, "U_c_J,U_d_J,U_c_over_U_d,capacity_ratio_6_10")) << line;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 4);

  // --reuse extends the study by a size: the four finished runs are read, not run again.
  const auto before = fs::last_write_time(out / "straight" / "h_2000um" / "summary.json");
  const auto again = run_brittle(
      dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "2e-3,1e-3,4e-3", "--case",
            "straight", "--case", "damage=" + kScenes + "damage.ini", "--set", "run.end_time=10e-6",
            "--set", "geometry.T=2e-3", "--jobs", "2", "--reuse", "--out", out.string()});
  ASSERT_EQ(again.exit_code, 0) << again.err << again.out;
  std::size_t reused = 0;
  for (auto at = again.err.find("reusing"); at != std::string::npos;
       at = again.err.find("reusing", at + 1))
    ++reused;
  EXPECT_EQ(reused, 4u) << again.err;
  EXPECT_EQ(fs::last_write_time(out / "straight" / "h_2000um" / "summary.json"), before);
  EXPECT_TRUE(fs::exists(out / "damage" / "h_4000um" / "summary.json"));
  EXPECT_EQ(read_json(out / "study.json")["rows"].size(), 6u);
}

/// --frames keeps the VTU series and lays the last crack frame of every run out in one panel.
TEST(Study, FramesGiveACrackPanel) {
  TempDir dir;
  const fs::path out = dir / "study";
  const auto r = run_brittle(dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "2e-3,1e-3",
                                   "--case", "straight", "--set", "run.end_time=10e-6",
                                   "--frames", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_TRUE(fs::exists(out / "straight" / "h_1000um" / "run.pvd"));
  ASSERT_TRUE(fs::exists(out / "study_cracks.png"));
  EXPECT_GT(fs::file_size(out / "study_cracks.png"), 5000u);
}

TEST(Study, ABadSceneIsRefusedBeforeAnyRun) {
  TempDir dir;
  const fs::path out = dir / "study";
  auto r = run_brittle(dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "2e-3,1e-3",
                             "--case", "straight", "--case", "typo=" + kScenes + "damage.ini",
                             "--set", "fracture.nn=3", "--out", out.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "brittle study: case 'straight' at h = 0.002 m:")) << r.err;
  EXPECT_TRUE(contains(r.err, "fracture.nn")) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(out));  // nothing started, nothing written

  r = run_brittle(dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "1e-3", "--case",
                        "x=" + (dir / "missing.ini").string(), "--out", out.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "missing.ini")) << r.err;
  EXPECT_FALSE(fs::exists(out));

  r = run_brittle(dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "1e-3", "--set",
                        "fracture.mode=none", "--out", out.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "fracture.mode is none")) << r.err;

  r = run_brittle(dir, {"study", "loads", kScenes + "cm.ini"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "unknown study 'loads' (expected: brittle study mesh")) << r.err;

  r = run_brittle(dir, {"study", "mesh", kScenes + "cm.ini", "--sizes", "1e-3", "--case", "a",
                        "--case", "a"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "'a' is given twice")) << r.err;

  r = run_brittle(dir, {"study", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(contains(r.out, "--sizes")) << r.out;
}

}  // namespace
}  // namespace brittle
