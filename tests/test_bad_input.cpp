// Inputs that crashed brittle or a library inside it (issue 12, item 1): each now ends in one
// line naming the file and what was expected, exit 2 (docs/mesh.md, "Reading files safely").
#include <gtest/gtest.h>

#include "cli_helpers.hpp"

using namespace brittle_test;

namespace {

const std::string kScenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
const std::string kData = BRITTLE_TEST_DATA;

/// Exit 2, one line on stderr holding every part, no "Segmentation" or core dump.
void expect_refused(const Result& r, const std::vector<std::string>& parts) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const auto& p : parts) EXPECT_TRUE(contains(r.err, p)) << "'" << p << "' not in " << r.err;
}

/// A scene that reads `mesh` (a short run, no frames).
std::string mesh_scene(const TempDir& dir, const std::string& mesh) {
  return dir.write("mesh.ini", "[loading]\nsigma_over_sigmac = 0.5\n[mesh]\nfile = " + mesh +
                                   "\n[run]\nend_time = 1e-8\n[output]\nvtu = false\n");
}

}  // namespace

// VTK 9.1's XML reader dereferences the missing type of a FieldData array (SIGSEGV): in the
// child process that reads it, so brittle reports it.
TEST(BadInput, VtuThatCrashesTheVtkReader) {
  TempDir dir;
  const Result r = run_brittle(dir, {"run", mesh_scene(dir, kData + "/fielddata_without_type.vtu"),
                                     "--out", (dir / "out").string()});
  // (Under AddressSanitizer the child may end through the sanitizer instead: "failed".)
  expect_refused(r, {"fielddata_without_type.vtu", "VTK reader", "on this file", "expected"});
}

TEST(BadInput, MshWithNodeTagZero) {
  TempDir dir;
  const Result r = run_brittle(
      dir, {"run", mesh_scene(dir, kData + "/node_tag_zero.msh"), "--out", (dir / "out").string()});
  expect_refused(r, {"node_tag_zero.msh", "expected a Gmsh .msh or VTK .vtu file"});
}

TEST(BadInput, TruncatedAndForeignMeshFiles) {
  TempDir dir;
  Result r = run_brittle(dir, {"run", kScenes + "cm.ini", "--set", "run.end_time=1e-6", "--out",
                               (dir / "run").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string frame = read_text(dir / "run/frames/frame_0001.vtu");
  for (std::size_t cut : {frame.size() / 2, frame.size() - 100, std::size_t(600)}) {
    dir.write("cut.vtu", frame.substr(0, cut));
    r = run_brittle(dir, {"run", mesh_scene(dir, (dir / "cut.vtu").string()), "--out",
                          (dir / "out").string()});
    expect_refused(r, {"cut.vtu"});
  }
  dir.write("empty.msh", "");
  r = run_brittle(dir, {"run", mesh_scene(dir, (dir / "empty.msh").string())});
  expect_refused(r, {"empty.msh", "is empty"});
  dir.write("text.vtu", "hello\n");
  r = run_brittle(dir, {"run", mesh_scene(dir, (dir / "text.vtu").string())});
  expect_refused(r, {"text.vtu", "XML header"});
  dir.write("text.msh", "hello\n");
  r = run_brittle(dir, {"run", mesh_scene(dir, (dir / "text.msh").string())});
  expect_refused(r, {"text.msh", "$MeshFormat"});
}

// The frames `brittle render` reads go through the same child process.
TEST(BadInput, RenderOfACorruptFrame) {
  TempDir dir;
  Result r = run_brittle(dir, {"run", kScenes + "cm.ini", "--set", "run.end_time=1e-6", "--out",
                               (dir / "run").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  fs::copy_file(kData + "/fielddata_without_type.vtu", dir / "run/frames/frame_0001.vtu",
                fs::copy_options::overwrite_existing);
  r = run_brittle(dir, {"render", (dir / "run/run.pvd").string(), "--times", "1e-6", "--out",
                        (dir / "png").string()});
  expect_refused(r, {"frame_0001.vtu", "VTK reader", "on this file"});
  dir.write("run/run.pvd", "<VTKFile type=\"Collection\"><Collection><DataSet timestep=\"x\"");
  r = run_brittle(dir, {"render", (dir / "run/run.pvd").string(), "--out", (dir / "png").string()});
  expect_refused(r, {"run.pvd"});
}

// A binary scene file: the message names the key with its control bytes escaped.
TEST(BadInput, ControlBytesInMessagesAreEscaped) {
  TempDir dir;
  const std::string scene = dir.write("bin.ini", std::string("[material]\nE\x01\x1b[31m = 5\n"));
  const Result r = run_brittle(dir, {"run", scene});
  expect_refused(r, {"material.E\\x01\\x1b[31m"});
  for (char c : r.err) EXPECT_TRUE(c == '\n' || static_cast<unsigned char>(c) >= 0x20) << r.err;
}

// Plates Gmsh cannot mesh (or meshes forever): refused before meshing, or Gmsh's failure.
TEST(BadInput, PlatesGmshCannotMesh) {
  TempDir dir;
  Result r = run_brittle(dir, {"run", kScenes + "cm.ini", "--set", "geometry.H=1e30", "--set",
                               "mesh.size=1e29"});
  expect_refused(r, {"geometry.L x H", "within a factor 1000"});
  r = run_brittle(dir, {"run", kScenes + "cm.ini", "--set", "mesh.size=1"});
  expect_refused(r, {"mesh.size = 1", "shorter side"});
  r = run_brittle(dir, {"run", kScenes + "cm.ini", "--set", "geometry.T=1e-300", "--out",
                        (dir / "out").string()});
  expect_refused(r, {"Gmsh failed"});
}

// `brittle chart` on directories that are not sweeps, or whose files are broken.
TEST(BadInput, ChartOfBrokenSweepDirectories) {
  TempDir dir;
  Result r = run_brittle(dir, {"chart", (dir / "none").string(), "--out", (dir / "c").string()});
  expect_refused(r, {"none"});
  dir.write("s/sweep.csv", "sigma_over_sigmac,W\n\x01\x02garbage\n");
  r = run_brittle(dir, {"chart", (dir / "s").string(), "--out", (dir / "c").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}
