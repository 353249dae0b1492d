// Off-screen rendering: works with no display at all, frames match their baselines
// (tests/baselines, vtkImageDifference with a stated threshold), the comparison does fail for a
// changed colour range or camera, and `brittle render` on a stored series gives the frame that
// was rendered during the run.
//
// Regenerate the baselines deliberately (then look at them and commit them):
//   BRITTLE_REGENERATE_BASELINES=1 ctest --test-dir build/release -R Render
// or: cmake --build build/release --target regenerate_baselines
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <array>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <vtkImageData.h>

#include "error.hpp"
#include "fracture.hpp"
#include "crack_surface.hpp"
#include "frame_renderer.hpp"
#include "image_tools.hpp"
#include "plate_mesh.hpp"
#include "render_commands.hpp"
#include "scene_options.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;
using brittle::render::Field;

namespace {

/// Largest accepted comparison error (brittle::render::Comparison::error: mean per-pixel error
/// above kPixelThreshold = 16 of 255, in [0, 1]). Measured on the 400 x 300 frames: identical
/// renderings 0; a camera 0.2 % closer (sub-pixel moves of every edge and glyph, as a Mesa or
/// FreeType update may cause) ~2e-7; a camera 5 % closer ~0.04; the sigma1 range 0..1.0 instead
/// of 0..1.2 ~0.1. 2e-3 sits far from both sides.
constexpr double kMaxError = 2e-3;

const fs::path kBaselines = fs::path(BRITTLE_SOURCE_DIR) / "tests" / "baselines";
const fs::path kOutput = BRITTLE_RENDER_OUTPUT;

/// The small, fast scene of the image tests: CM plate on a 2 mm mesh, damage on, 90 % of
/// sigma_c, 10 us (about 100 steps, a few hundredths of a second), 400 x 300 frames.
brittle::Scene small_scene(const std::vector<std::string>& extra = {}) {
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  std::vector<std::string> sets = {"mesh.size=2e-3", "run.end_time=10e-6", "run.threads=1",
                                   "render.width=400", "render.height=300"};
  sets.insert(sets.end(), extra.begin(), extra.end());
  return brittle::load_scene({scenes + "cm.ini", scenes + "damage.ini"}, sets);
}

/// The small scene's final state (t = 10 us) rendered with its [render] keys.
vtkSmartPointer<vtkImageData> render_small(Field field, const std::vector<std::string>& extra = {}) {
  const brittle::Scene scene = small_scene(extra);
  auto mesh = brittle::make_mesh(scene);
  brittle::Simulation sim(scene, *mesh);
  sim.run({});
  sim.update_output_fields();
  brittle::render::FrameRenderer renderer(scene.render);
  return renderer.render(*sim.grid().vtk(), field);
}

bool regenerating() {
  const char* v = std::getenv("BRITTLE_REGENERATE_BASELINES");
  return v && std::string(v) == "1";
}

/// Compares with tests/baselines/<name>.png; on failure writes <name>.png and <name>.diff.png
/// to the test output directory and names them in the failure message.
void expect_matches_baseline(vtkImageData& image, const std::string& name) {
  const fs::path baseline = kBaselines / (name + ".png");
  if (regenerating()) {
    brittle::render::write_png(image, baseline.string());
    GTEST_SKIP() << "regenerated " << baseline;
  }
  ASSERT_TRUE(fs::exists(baseline)) << baseline << " is missing; regenerate the baselines "
                                    << "(BRITTLE_REGENERATE_BASELINES=1)";
  auto expected = brittle::render::read_png(baseline.string());
  const auto c = brittle::render::compare_images(image, *expected);
  if (!c.same_size || c.error > kMaxError) {
    const fs::path actual = kOutput / (name + ".png"), diff = kOutput / (name + ".diff.png");
    brittle::render::write_png(image, actual.string());
    if (c.difference) brittle::render::write_png(*c.difference, diff.string());
    ADD_FAILURE() << name << " differs from " << baseline << ": error " << c.error << " > "
                  << kMaxError << (c.same_size ? "" : " (different size)") << "; new image "
                  << actual << ", difference " << diff;
  }
  std::cout << name << ": error " << c.error << " (threshold " << kMaxError << ")\n";
}

/// A fresh directory under the build tree's render output, emptied first.
fs::path scratch(const std::string& name) {
  const fs::path dir = kOutput / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

int run(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every test runs as if on a machine without X: no DISPLAY (and no Xvfb is started).
class Render : public ::testing::Test {
 protected:
  void SetUp() override { unsetenv("DISPLAY"); }
};

}  // namespace

TEST_F(Render, WorksWithoutDisplay) {
  ASSERT_EQ(std::getenv("DISPLAY"), nullptr);
  auto image = render_small(Field::sigma1);
  int dims[3];
  image->GetDimensions(dims);
  ASSERT_EQ(dims[0], 400);
  ASSERT_EQ(dims[1], 300);
  ASSERT_EQ(image->GetNumberOfScalarComponents(), 3);
  // Not a blank window: most pixels are the coloured plate, with many distinct colours.
  const auto* px = static_cast<const unsigned char*>(image->GetScalarPointer());
  std::set<int> colours;
  long non_white = 0;
  for (int i = 0; i < dims[0] * dims[1]; ++i) {
    const unsigned char* p = px + 3 * i;
    if (p[0] < 250 || p[1] < 250 || p[2] < 250) ++non_white;
    colours.insert(p[0] << 16 | p[1] << 8 | p[2]);
  }
  EXPECT_GT(non_white, dims[0] * dims[1] / 3);
  EXPECT_GT(colours.size(), 20u);
}

TEST_F(Render, Sigma1MatchesBaseline) {
  auto image = render_small(Field::sigma1);
  expect_matches_baseline(*image, "sigma1_10us");
}

TEST_F(Render, DamageMatchesBaseline) {
  auto image = render_small(Field::damage);
  expect_matches_baseline(*image, "damage_10us");
}

TEST_F(Render, CrackMatchesBaseline) {
  auto image = render_small(Field::crack, {"run.end_time=20e-6"});
  expect_matches_baseline(*image, "crack_20us");
}

namespace {

/// Pixels of a crack frame: dark (crack lines; the text is outside `rows`) and red (tips).
struct CrackPixels {
  long dark = 0, red = 0;
};

CrackPixels count_crack_pixels(vtkImageData& image, int row_lo, int row_hi) {
  int dims[3];
  image.GetDimensions(dims);
  const auto* px = static_cast<const unsigned char*>(image.GetScalarPointer());
  CrackPixels n;
  for (int row = row_lo; row < row_hi; ++row)  // rows counted from the top
    for (int col = 0; col < dims[0]; ++col) {
      const unsigned char* p = px + 3 * ((dims[1] - 1 - row) * dims[0] + col);
      if (p[0] < 60 && p[1] < 60 && p[2] < 60) ++n.dark;
      if (p[0] > 170 && p[1] < 70 && p[2] < 70) ++n.red;
    }
  return n;
}

}  // namespace

/// A cracked run's frame has dark crack lines and a red tip in the band of y = 0 and neither
/// above or below it; an uncracked run's frame has neither anywhere on the plate.
TEST_F(Render, CrackFrameShowsTheCrackAndItsTip) {
  // 400 x 300: the plate's y = 0 is at about row 130 from the top (the band 12 %..75 %).
  auto cracked = render_small(Field::crack, {"run.end_time=20e-6"});
  const CrackPixels band = count_crack_pixels(*cracked, 115, 145);
  const CrackPixels above = count_crack_pixels(*cracked, 45, 100);
  const CrackPixels below = count_crack_pixels(*cracked, 160, 215);
  EXPECT_GT(band.dark, 50);
  EXPECT_GT(band.red, 10);
  EXPECT_EQ(above.dark + above.red + below.dark + below.red, 0);
  auto intact = render_small(Field::crack, {"run.end_time=20e-6", "loading.sigma_over_sigmac=0.2"});
  const CrackPixels none = count_crack_pixels(*intact, 45, 215);
  EXPECT_EQ(none.dark, 0);
  EXPECT_EQ(none.red, 0);
}

/// Crack faces found from the reference positions of a hand-made straight cut: every face of
/// the plane y = 0 with a split node, both sides, and nothing else.
TEST(CrackSurface, StraightCutGivesThePlanesFacesTwice) {
  brittle::Scene scene = small_scene({"mesh.size=1e-3"});
  auto mesh = brittle::make_mesh(scene);
  brittle::Simulation sim(scene, *mesh);
  EXPECT_EQ(brittle::render::find_crack_surface(*sim.grid().vtk()).face_count, 0);
  const double a = scene.geometry.notch_depth, c = 12e-3;
  // The plane's faces before the cut: triangles of the tets with three corners on y = 0.
  const brittle::Grid& grid = sim.grid();
  auto on_plane = [&](vtkIdType k) { return std::abs(grid.X()[3 * k + 1]) < 1e-12; };
  auto cut = [&](vtkIdType k) { return on_plane(k) && grid.X()[3 * k] >= a - 1e-12 && grid.X()[3 * k] <= c; };
  std::set<std::array<vtkIdType, 3>> plane_faces;
  for (vtkIdType e = 0; e < grid.num_cells(); ++e)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<vtkIdType, 3> f;
      int n = 0;
      for (int i = 0; i < 4; ++i)
        if (i != skip) f[n++] = grid.cells()[4 * e + i];
      std::sort(f.begin(), f.end());
      if (on_plane(f[0]) && on_plane(f[1]) && on_plane(f[2]) && (cut(f[0]) || cut(f[1]) || cut(f[2])))
        plane_faces.insert(f);
    }
  ASSERT_GT(plane_faces.size(), 10u);
  std::vector<brittle::SplitCandidate> nodes;
  for (vtkIdType k = 0; k < grid.num_points(); ++k)
    if (cut(k)) nodes.push_back({k, 1.0, brittle::Vec3::UnitY()});
  for (const auto& n : nodes)
    sim.fracture().split(sim.grid(), sim.elements(), sim.forces(), {n});
  const auto crack = brittle::render::find_crack_surface(*sim.grid().vtk());
  EXPECT_EQ(crack.face_count, static_cast<long>(plane_faces.size()));
  ASSERT_EQ(crack.faces.size(), 2 * plane_faces.size());
  for (const auto& face : crack.faces)
    for (vtkIdType k : face) {
      EXPECT_NEAR(sim.grid().X()[3 * k + 1], 0.0, 1e-12);
      EXPECT_LE(sim.grid().X()[3 * k], c + 2 * scene.mesh.size);
    }
}

TEST_F(Render, ChangedColourRangeFailsComparison) {
  if (regenerating()) GTEST_SKIP();
  auto image = render_small(Field::sigma1, {"render.sigma1_max=1.0"});
  auto baseline = brittle::render::read_png((kBaselines / "sigma1_10us.png").string());
  const auto c = brittle::render::compare_images(*image, *baseline);
  std::cout << "colour range 0..1.0 instead of 0..1.2: error " << c.error << "\n";
  EXPECT_TRUE(c.same_size);
  EXPECT_GT(c.error, kMaxError);
}

TEST_F(Render, ChangedCameraFailsComparison) {
  if (regenerating()) GTEST_SKIP();
  auto image = render_small(Field::damage, {"render.zoom=1.05"});
  auto baseline = brittle::render::read_png((kBaselines / "damage_10us.png").string());
  const auto c = brittle::render::compare_images(*image, *baseline);
  std::cout << "camera zoomed by 5 %: error " << c.error << "\n";
  EXPECT_TRUE(c.same_size);
  EXPECT_GT(c.error, kMaxError);
}

TEST_F(Render, SubPixelChangePassesComparison) {
  // What the tolerance is for: a camera 0.2 % closer moves edges and glyphs by under a pixel,
  // as a Mesa or FreeType update may.
  if (regenerating()) GTEST_SKIP();
  auto image = render_small(Field::sigma1, {"render.zoom=1.002"});
  auto baseline = brittle::render::read_png((kBaselines / "sigma1_10us.png").string());
  const auto c = brittle::render::compare_images(*image, *baseline);
  std::cout << "camera zoomed by 0.2 %: error " << c.error << "\n";
  EXPECT_LE(c.error, kMaxError);
}

TEST_F(Render, StoredSeriesGivesTheFrameOfTheRun) {
  const fs::path dir = scratch("stored_series");
  const std::string exe = BRITTLE_EXE, scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::string keys =
      " --set mesh.size=2e-3 --set run.end_time=10e-6 --set render.width=400"
      " --set render.height=300";
  ASSERT_EQ(run(exe + " run " + scenes + "cm.ini " + scenes + "damage.ini" + keys +
                    " --set output.frame_interval=2e-6 --set render.times=5e-6,10e-6"
                    " --set render.fields=sigma1,damage,crack --out '" +
                    (dir / "run").string() + "'",
                dir / "run.log"),
            0)
      << read(dir / "run.log");
  ASSERT_EQ(run(exe + " render '" + (dir / "run" / "run.pvd").string() +
                    "' --set render.width=400 --set render.height=300 --times 5e-6,10e-6 "
                    "--field sigma1,damage,CRACK --out '" + (dir / "again").string() + "'",
                dir / "render.log"),
            0)
      << read(dir / "render.log");
  int compared = 0;
  // Crack frames too: the tips travel through the VTU as field data (crack_tips).
  for (const char* name : {"sigma1_005.000us.png", "damage_005.000us.png", "crack_005.000us.png",
                           "sigma1_010.000us.png", "damage_010.000us.png", "crack_010.000us.png"}) {
    SCOPED_TRACE(name);
    auto during = brittle::render::read_png((dir / "run" / "render" / name).string());
    auto after = brittle::render::read_png((dir / "again" / name).string());
    const auto c = brittle::render::compare_images(*after, *during);
    EXPECT_TRUE(c.same_size);
    EXPECT_LE(c.error, kMaxError);
    EXPECT_EQ(c.error, 0.0) << "same data, same renderer: expected identical pixels";
    ++compared;
  }
  EXPECT_EQ(compared, 6);
}

TEST_F(Render, FigureCommandWritesTheFourPanels) {
  const fs::path dir = scratch("figure");
  const std::string exe = BRITTLE_EXE, scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::string command = exe + " figure " + scenes + "cm.ini " + scenes + "damage.ini" +
                              " --set mesh.size=2e-3 --set render.width=200 --set "
                              "render.height=150 --set render.times=1e-6,4e-6 --runs '" +
                              (dir / "runs").string() + "' --out '" + (dir / "figs").string() + "'";
  ASSERT_EQ(run(command, dir / "first.log"), 0) << read(dir / "first.log");
  for (const char* run_dir : {"straight-60", "straight-90", "branching-60", "branching-90"})
    EXPECT_TRUE(fs::exists(dir / "runs" / run_dir / "run.pvd")) << run_dir;
  for (const char* fig : {"fig07.png", "fig08.png", "fig09.png", "fig10.png"}) {
    SCOPED_TRACE(fig);
    auto image = brittle::render::read_png((dir / "figs" / fig).string());
    int dims[3];
    image->GetDimensions(dims);
    EXPECT_GT(dims[0], 2 * 200);  // two columns + row titles
    EXPECT_GT(dims[1], 2 * 150);  // two rows + column titles + title
  }
  // --reuse lays the panels out again from the stored runs, without running them.
  ASSERT_EQ(run(command + " --reuse", dir / "second.log"), 0) << read(dir / "second.log");
  EXPECT_NE(read(dir / "second.log").find("reusing"), std::string::npos);
  EXPECT_EQ(read(dir / "second.log").find("fracture at"), std::string::npos);
}

TEST_F(Render, RenderCommandErrors) {
  const fs::path dir = scratch("errors");
  const std::string exe = BRITTLE_EXE;
  EXPECT_EQ(run(exe + " render '" + (dir / "none.pvd").string() + "'", dir / "a.log"), 2);
  EXPECT_NE(read(dir / "a.log").find("no such file"), std::string::npos) << read(dir / "a.log");
  EXPECT_EQ(run(exe + " run --set render.fields=stress", dir / "b.log"), 2);
}

TEST(RenderKeys, RenderTimesBecomeFrames) {
  brittle::Scene scene = small_scene({"output.frame_interval=1e-6", "run.end_time=3e-6",
                                      "render.times=1.5e-6, 2e-6"});
  const std::vector<double> frames = brittle::frame_times(scene);
  const std::vector<double> expected = {0, 1e-6, 1.5e-6, 2e-6, 3e-6};
  ASSERT_EQ(frames.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(frames[i], expected[i], 1e-15);
}

TEST(RenderKeys, RangesAndFieldsAreChecked) {
  EXPECT_THROW(small_scene({"render.sigma1_min=2"}), brittle::Error);
  EXPECT_THROW(small_scene({"render.fields=sigma1, stress"}), brittle::Error);
  EXPECT_THROW(small_scene({"render.width=4"}), brittle::Error);
  EXPECT_EQ(small_scene({"render.fields=damage"}).render.fields,
            std::vector<std::string>{"damage"});
}
