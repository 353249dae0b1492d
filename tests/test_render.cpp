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
#include <memory>
#include <algorithm>
#include <array>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include "error.hpp"
#include "fracture.hpp"
#include "grid.hpp"
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
  brittle::render::FrameRenderer renderer(scene.render, "cm + damage");
  return renderer.render(*sim.grid().vtk(), field);
}

/// The small scene at t = 0, not run (a few hundredths of a second): the grid to paint on.
struct SmallGrid {
  brittle::Scene scene;
  std::unique_ptr<brittle::Simulation> sim;
  explicit SmallGrid(const std::vector<std::string>& extra = {}) : scene(small_scene(extra)) {
    auto mesh = brittle::make_mesh(scene);
    sim = std::make_unique<brittle::Simulation>(scene, *mesh);
    sim->update_output_fields();
  }
  vtkUnstructuredGrid& grid() { return *sim->grid().vtk(); }
  /// Every cell's sigma1/sigma_c set to `value`.
  void fill_sigma1(double value) {
    grid().GetCellData()->GetArray(brittle::field::sigma1_over_sigmac)->FillComponent(0, value);
  }
};

/// RGB of the pixel in column `col`, row `row` counted from the top.
std::array<int, 3> pixel(vtkImageData& image, int col, int row) {
  int dims[3];
  image.GetDimensions(dims);
  const auto* p = static_cast<const unsigned char*>(image.GetScalarPointer()) +
                  3 * ((dims[1] - 1 - row) * dims[0] + col);
  return {p[0], p[1], p[2]};
}

/// How many pixels of the box [col0, col1) x [row0, row1) (rows from the top) `pred` accepts.
template <class Pred>
long count_pixels(vtkImageData& image, int col0, int col1, int row0, int row1, Pred pred) {
  long n = 0;
  for (int row = row0; row < row1; ++row)
    for (int col = col0; col < col1; ++col)
      if (pred(pixel(image, col, row))) ++n;
  return n;
}

bool is_dark(const std::array<int, 3>& p) { return p[0] < 90 && p[1] < 90 && p[2] < 90; }
bool is_white(const std::array<int, 3>& p) { return p[0] > 250 && p[1] > 250 && p[2] > 250; }
bool is_magenta(const std::array<int, 3>& p) { return p[0] > 245 && p[1] < 10 && p[2] > 245; }
/// A ramp colour (saturated, as on a colour bar or the plate), not black, white or grey text.
bool is_colour(const std::array<int, 3>& p) {
  return std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 100;
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

/// Splits every node `cut` selects on the plane y = 0 (normal y), then finds the crack.
template <class Cut>
brittle::render::CrackSurface cut_and_find(brittle::Simulation& sim, Cut cut) {
  std::vector<brittle::SplitCandidate> nodes;
  for (vtkIdType k = 0; k < sim.grid().num_points(); ++k)
    if (cut(k)) nodes.push_back({k, 1.0, brittle::Vec3::UnitY()});
  for (const auto& n : nodes)
    sim.fracture().split(sim.grid(), sim.elements(), sim.forces(), {n});
  return brittle::render::find_crack_surface(*sim.grid().vtk());
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
  const auto crack = cut_and_find(sim, cut);
  EXPECT_EQ(crack.face_count, static_cast<long>(plane_faces.size()));
  ASSERT_EQ(crack.faces.size(), 2 * plane_faces.size());
  for (const auto& face : crack.faces)
    for (vtkIdType k : face) {
      EXPECT_NEAR(sim.grid().X()[3 * k + 1], 0.0, 1e-12);
      EXPECT_LE(sim.grid().X()[3 * k], c + 2 * scene.mesh.size);
    }
}

/// The same cut in a 2D body (issue 53): the cracked edges of y = 0, both sides, each drawn as
/// the "face" (a, b, b).
TEST(CrackSurface, StraightCutOfA2DBodyGivesItsEdgesTwice) {
  brittle::Scene scene = small_scene(
      {"mesh.size=1e-3", "mesh.dimension=2", "material.plane=stress", "damage.beta1=0"});
  auto mesh = brittle::make_mesh(scene);
  brittle::Simulation sim(scene, *mesh);
  const brittle::Grid& grid = sim.grid();
  ASSERT_EQ(grid.corners(), 3);
  EXPECT_EQ(brittle::render::find_crack_surface(*grid.vtk()).face_count, 0);
  const double a = scene.geometry.notch_depth, c = 12e-3;
  auto on_plane = [&](vtkIdType k) { return std::abs(grid.X()[3 * k + 1]) < 1e-12; };
  auto cut = [&](vtkIdType k) {
    return on_plane(k) && grid.X()[3 * k] >= a - 1e-12 && grid.X()[3 * k] <= c;
  };
  std::set<std::array<vtkIdType, 2>> plane_edges;
  for (vtkIdType e = 0; e < grid.num_cells(); ++e)
    for (int i = 0; i < 3; ++i) {
      std::array<vtkIdType, 2> f = {grid.cells()[3 * e + i], grid.cells()[3 * e + (i + 1) % 3]};
      std::sort(f.begin(), f.end());
      if (on_plane(f[0]) && on_plane(f[1]) && (cut(f[0]) || cut(f[1]))) plane_edges.insert(f);
    }
  ASSERT_GT(plane_edges.size(), 5u);
  const auto crack = cut_and_find(sim, cut);
  EXPECT_EQ(crack.face_count, static_cast<long>(plane_edges.size()));
  ASSERT_EQ(crack.faces.size(), 2 * plane_edges.size());
  for (const auto& face : crack.faces) {
    EXPECT_EQ(face[1], face[2]);
    for (vtkIdType k : face) EXPECT_NEAR(sim.grid().X()[3 * k + 1], 0.0, 1e-12);
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
                    "--fields sigma1,damage,CRACK --out '" + (dir / "again").string() + "'",
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
  // With the facet criterion (branching mode only): the branching runs and Figs. 9-10.
  const std::string facet = exe + " figure " + scenes + "cm.ini " + scenes + "damage.ini" +
                            " --set mesh.size=2e-3 --set render.width=200 --set "
                            "render.height=150 --set render.times=1e-6,4e-6 --set "
                            "fracture.criterion=facet --runs '" + (dir / "facet-runs").string() +
                            "' --out '" + (dir / "facet-figs").string() + "'";
  ASSERT_EQ(run(facet, dir / "facet.log"), 0) << read(dir / "facet.log");
  EXPECT_NE(read(dir / "facet.log").find("fig07.png and fig08.png skipped"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "facet-runs" / "straight-90"));
  EXPECT_TRUE(fs::exists(dir / "facet-runs" / "branching-90" / "run.pvd"));
  EXPECT_FALSE(fs::exists(dir / "facet-figs" / "fig07.png"));
  EXPECT_TRUE(fs::exists(dir / "facet-figs" / "fig09.png"));
  EXPECT_TRUE(fs::exists(dir / "facet-figs" / "fig10.png"));
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

TEST(RenderKeys, ColormapIsAWord) {
  EXPECT_EQ(small_scene().render.colormap, brittle::RenderParams::Colormap::jet);
  EXPECT_EQ(small_scene({"render.colormap=Viridis"}).render.colormap,
            brittle::RenderParams::Colormap::viridis);
  EXPECT_THROW(small_scene({"render.colormap=parula"}), brittle::Error);
}

/// Values above the colour range are magenta, below it grey, on the plate; the bar of a single
/// frame shows both as swatches at its ends.
TEST_F(Render, OverRangeCellsGetTheMarkedColours) {
  SmallGrid small;
  brittle::render::FrameRenderer renderer(small.scene.render);
  // 400 x 300: the plate spans rows ~36..225 from the top; (300, 100) is on it, above y = 0.
  small.fill_sigma1(2.9);  // sigma1/sigma_c at a crack tip; the bar ends at 1.2
  auto above = renderer.render(small.grid(), Field::sigma1);
  EXPECT_EQ(pixel(*above, 300, 100), (std::array<int, 3>{255, 0, 255}));
  small.fill_sigma1(-0.3);
  auto below = renderer.render(small.grid(), Field::sigma1);
  const auto grey = pixel(*below, 300, 100);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(grey[k], 128, 1);
  small.fill_sigma1(0.9);
  auto inside = renderer.render(small.grid(), Field::sigma1);
  EXPECT_FALSE(is_magenta(pixel(*inside, 300, 100)));
  // The swatches: magenta and grey in the colour bar's strip (bottom 25 %), none on the plate.
  EXPECT_GT(count_pixels(*inside, 0, 400, 225, 300, is_magenta), 20);
  EXPECT_EQ(count_pixels(*inside, 0, 400, 0, 225, is_magenta), 0);
}

TEST_F(Render, ViridisDiffersFromJet) {
  SmallGrid small;
  small.fill_sigma1(0.6);  // the middle of 0..1.2
  brittle::render::FrameRenderer jet(small.scene.render);
  brittle::RenderParams params = small.scene.render;
  params.colormap = brittle::RenderParams::Colormap::viridis;
  brittle::render::FrameRenderer viridis(params);
  const auto j = pixel(*jet.render(small.grid(), Field::sigma1), 300, 100);
  const auto v = pixel(*viridis.render(small.grid(), Field::sigma1), 300, 100);
  // jet's middle is green; viridis' is its teal #21918c (33, 145, 140).
  EXPECT_GT(j[1], 200);
  EXPECT_LT(j[0] + j[2], 60);
  EXPECT_NEAR(v[0], 33, 3);
  EXPECT_NEAR(v[1], 145, 3);
  EXPECT_NEAR(v[2], 140, 3);
}

TEST(ScaleBar, LengthIsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(brittle::render::scale_bar_length(32e-3), 5e-3);
  EXPECT_DOUBLE_EQ(brittle::render::scale_bar_length(0.1), 0.02);
  EXPECT_DOUBLE_EQ(brittle::render::scale_bar_length(1e-3), 2e-4);
  EXPECT_DOUBLE_EQ(brittle::render::scale_bar_length(0.5), 0.1);
}

namespace {

/// The longest run of dark pixels along a row in the box (rows from the top).
int longest_dark_run(vtkImageData& image, int col0, int col1, int row0, int row1) {
  int best = 0;
  for (int row = row0; row < row1; ++row)
    for (int col = col0, run = 0; col < col1; ++col) {
      run = is_dark(pixel(image, col, row)) ? run + 1 : 0;
      best = std::max(best, run);
    }
  return best;
}

}  // namespace

/// The scale bar is as long, in pixels, as its length in mm is on the plate: measured against
/// the plate's own width in pixels (the known reference width), single frames and panel cells.
TEST_F(Render, ScaleBarMatchesTheCamera) {
  SmallGrid small;
  double range[2];
  small.grid().GetPointData()->GetArray(brittle::field::reference_position)->GetRange(range, 0);
  const double plate_width = range[1] - range[0];
  brittle::render::FrameRenderer renderer(small.scene.render);
  for (auto layout : {brittle::render::Layout::single, brittle::render::Layout::cell}) {
    SCOPED_TRACE(layout == brittle::render::Layout::single ? "single" : "cell");
    auto image = renderer.render(small.grid(), Field::sigma1, layout);
    const long plate_px =
        count_pixels(*image, 0, 400, 100, 101, [](auto p) { return !is_white(p); });
    const double px_per_m = plate_px / plate_width;
    const brittle::render::ScaleBar& bar = renderer.scale_bar();
    EXPECT_NEAR(bar.length, 5e-3, 1e-12);  // a 32 mm plate: 5 mm
    // Bottom strip, right of the colour bar: the bar is the longest dark line there.
    const int measured = longest_dark_run(*image, 270, 400, 255, 300);
    EXPECT_NEAR(measured, bar.length * px_per_m, 2.0) << "plate " << plate_px << " px";
    EXPECT_NEAR(measured, bar.pixels, 1.0);
  }
}

/// Single frames name the scene (bottom right); panel cells and unnamed renderers do not.
TEST_F(Render, SceneNameInSingleFrames) {
  SmallGrid small;
  brittle::render::FrameRenderer named(small.scene.render, "cm + damage");
  brittle::render::FrameRenderer unnamed(small.scene.render);
  auto corner = [](vtkImageData& image) {
    return count_pixels(image, 280, 400, 281, 300, is_dark);
  };
  EXPECT_GT(corner(*named.render(small.grid(), Field::sigma1)), 30);
  EXPECT_EQ(corner(*unnamed.render(small.grid(), Field::sigma1)), 0);
  // A cell is the same picture with or without a name (its bottom strip holds the scale bar).
  auto cell = named.render(small.grid(), Field::sigma1, brittle::render::Layout::cell);
  auto unnamed_cell = unnamed.render(small.grid(), Field::sigma1, brittle::render::Layout::cell);
  EXPECT_EQ(brittle::render::compare_images(*cell, *unnamed_cell).error, 0.0);
}

/// A panel has one colour bar, right of the frames: the cells have none, the panel is one bar
/// wider than without it, and the bar's magenta swatch is only in that last column.
TEST_F(Render, PanelHasOneSharedColourBar) {
  SmallGrid small;
  brittle::render::FrameRenderer renderer(small.scene.render);
  auto single = renderer.render(small.grid(), Field::sigma1);
  auto a = renderer.render(small.grid(), Field::sigma1, brittle::render::Layout::cell);
  auto b = renderer.render(small.grid(), Field::sigma1, brittle::render::Layout::cell);
  // The bottom 12 % of a cell holds the scale bar only; a single frame's holds its colour bar.
  EXPECT_EQ(count_pixels(*a, 0, 400, 264, 300, is_colour), 0);
  EXPECT_GT(count_pixels(*single, 0, 400, 264, 300, is_colour), 1000);
  const int bar_w = renderer.colour_bar_width();
  auto bar = renderer.colour_bar(Field::sigma1, bar_w, 300);
  const std::vector<std::vector<vtkImageData*>> cells = {{a, b}};
  auto with = brittle::render::panel(cells, {"sigma1"}, {"1 us", "2 us"}, "title", {{bar, 1}});
  auto without = brittle::render::panel(cells, {"sigma1"}, {"1 us", "2 us"}, "title");
  int w1[3], w0[3];
  with->GetDimensions(w1);
  without->GetDimensions(w0);
  EXPECT_EQ(w1[0], w0[0] + bar_w);
  EXPECT_EQ(w1[1], w0[1]);
  EXPECT_GT(count_pixels(*with, w0[0], w1[0], 0, w1[1], is_magenta), 20);
  EXPECT_EQ(count_pixels(*with, 0, w0[0], 0, w1[1], is_magenta), 0);
}

/// A run without damage (damage.beta1 = 0) gets no Omega frames, during the run and from
/// `brittle render` (by its scene.ini, or by its frames when that is gone), and its panel no
/// Omega row; stderr says so.
TEST_F(Render, RunWithoutDamageHasNoDamageFrames) {
  const fs::path dir = scratch("no_damage");
  const std::string exe = BRITTLE_EXE, scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  ASSERT_EQ(run(exe + " run " + scenes + "cm.ini --set mesh.size=2e-3 --set run.end_time=2e-6"
                    " --set render.width=200 --set render.height=150 --set render.times=2e-6"
                    " --out '" + (dir / "run").string() + "'",
                dir / "run.log"),
            0)
      << read(dir / "run.log");
  EXPECT_TRUE(fs::exists(dir / "run" / "render" / "sigma1_002.000us.png"));
  EXPECT_FALSE(fs::exists(dir / "run" / "render" / "damage_002.000us.png"));
  EXPECT_NE(read(dir / "run.log").find("no damage in this run: damage frames skipped"),
            std::string::npos);
  const std::string render = exe + " render '" + (dir / "run").string() +
                             "' --set render.width=200 --set render.height=150 --times 2e-6"
                             " --fields sigma1,damage --panel '" + (dir / "panel.png").string() +
                             "' --out ";
  for (const char* out : {"again", "without_scene_ini"}) {
    SCOPED_TRACE(out);
    if (std::string(out) == "without_scene_ini") fs::remove(dir / "run" / "scene.ini");
    const fs::path log = dir / (std::string(out) + ".log");
    ASSERT_EQ(run(render + "'" + (dir / out).string() + "'", log), 0) << read(log);
    EXPECT_TRUE(fs::exists(dir / out / "sigma1_002.000us.png"));
    EXPECT_FALSE(fs::exists(dir / out / "damage_002.000us.png"));
    const std::string text = read(log);
    EXPECT_NE(text.find("no damage in this run: damage frames skipped"), std::string::npos) << text;
    auto panel = brittle::render::read_png((dir / "panel.png").string());
    int dims[3];
    panel->GetDimensions(dims);
    EXPECT_LT(dims[1], 2 * 150);  // one row (sigma1) under the titles, not two
  }
}

TEST_F(Render, FigureWithoutDamageDropsTheOmegaFigures) {
  const fs::path dir = scratch("figure_no_damage");
  const std::string exe = BRITTLE_EXE, scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  ASSERT_EQ(run(exe + " figure " + scenes + "cm.ini --set mesh.size=2e-3 --set render.width=200"
                    " --set render.height=150 --set render.times=1e-6,2e-6 --runs '" +
                    (dir / "runs").string() + "' --out '" + (dir / "figs").string() + "'",
                dir / "log"),
            0)
      << read(dir / "log");
  EXPECT_TRUE(fs::exists(dir / "figs" / "fig07.png"));
  EXPECT_TRUE(fs::exists(dir / "figs" / "fig09.png"));
  EXPECT_FALSE(fs::exists(dir / "figs" / "fig08.png"));
  EXPECT_FALSE(fs::exists(dir / "figs" / "fig10.png"));
  EXPECT_NE(read(dir / "log").find("no damage"), std::string::npos);
}
