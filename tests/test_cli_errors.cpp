// The executable's failures: one line on stderr and exit 2 for bad scenes, bad regions and the
// guards; a run that blows up or fills the disk keeps what it wrote readable.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "cli_helpers.hpp"
#include "fixtures.hpp"
#include "output.hpp"
#include "scene_options.hpp"

namespace fs = std::filesystem;
using namespace brittle_test;

// ---------------------------------------------------------------------------------------------
// The executable: one line on stderr, non-zero exit, nothing claimed complete

TEST(Executable, Version) {
  TempDir dir;
  const Result r = run_brittle(dir, {"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind(std::string("brittle ") + BRITTLE_VERSION + " (commit ", 0), 0u) << r.out;
}

TEST(Executable, RunHelpListsEveryKey) {
  TempDir dir;
  const Result r = run_brittle(dir, {"run", "--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ostringstream keys;
  brittle::print_scene_keys(keys);
  EXPECT_TRUE(contains(r.out, keys.str())) << r.out;
  EXPECT_TRUE(contains(r.out, "material.E ")) << r.out;
  EXPECT_TRUE(contains(r.out, "output.frame_times ")) << r.out;
}

namespace {

/// Runs `brittle run <ini> --out <dir>/out` and checks: exit code non-zero, exactly one line
/// "brittle: error: ..." on stderr containing every part, and no summary claiming a finished run.
void expect_run_fails(const TempDir& dir, const std::string& ini, const std::string& ini_text,
                      const std::vector<std::string>& parts) {
  const std::string file = dir.write(ini, ini_text);
  const fs::path out = dir / "out";
  const Result r = run_brittle(dir, {"run", file, "--out", out.string()});
  EXPECT_NE(r.exit_code, 0);
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not exactly one line: " << r.err;
  EXPECT_EQ(r.err.rfind("brittle: error: ", 0), 0u) << r.err;
  for (const auto& p : parts) EXPECT_TRUE(contains(r.err, p)) << "'" << p << "' not in " << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json")) << "a failed run left a summary";
  EXPECT_FALSE(fs::exists(out / "run.pvd")) << "a failed run left a frame collection";
}

}  // namespace

// A criterion's length that nothing can use is refused with one line (issue 51): given to a
// criterion that has none, or longer than the body (a ball of 1000 km on a plate).
TEST(Executable, CriterionLengthsNoBodyCanUseAreRefused) {
  TempDir dir;
  const std::string branching = std::string(kLoad) + "[fracture]\nmode = branching\n";
  expect_run_fails(dir, "bad.ini", branching + "criterion = facet\nepsilon = 1e6\n",
                   {"bad.ini", "fracture.epsilon", "does not use"});
  expect_run_fails(dir, "bad.ini", branching + "criterion = nodal-stress\nlength = 1e-3\n",
                   {"bad.ini", "fracture.length", "does not use"});
  expect_run_fails(dir, "bad.ini", branching + "criterion = energy\nepsilon = 1e6\n",
                   {"fracture.epsilon = 1e+06 m is longer than the body"});
  expect_run_fails(dir, "bad.ini", branching + "criterion = coupled-facet\nlength = 1e6\n",
                   {"fracture.length = 1e+06 m is longer than the body"});
}

// What a 2D body does not have yet is refused with one line naming the key and the file
// (issue 53; docs/model.md, "Two dimensions").
TEST(Executable, WhatA2DBodyLacksIsRefused) {
  TempDir dir;
  const std::string two_d =
      std::string(kLoad) + "[mesh]\ndimension = 2\n[material]\nplane = stress\n";
  expect_run_fails(dir, "bad.ini",
                   two_d + "[fracture]\nmode = branching\ncriterion = coupled-facet\n",
                   {"bad.ini", "fracture.criterion", "mesh.dimension = 2"});
  expect_run_fails(dir, "bad.ini", two_d + "[run]\nmass_scaling = 1e-8\n",
                   {"bad.ini", "run.mass_scaling", "mesh.dimension = 2"});
}

// A material length the mesh does not resolve runs, with one warning line that says so.
TEST(Executable, UnresolvedMaterialLengthWarns) {
  TempDir dir;
  const std::string file = dir.write(
      "coarse.ini", std::string(kLoad) +
                        "[fracture]\nmode = branching\ncriterion = nonlocal-facet\nlength = "
                        "0.1e-3\n[run]\nend_time = 0.2e-6\n");
  const Result r = run_brittle(dir, {"run", file, "--out", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "warning: fracture.length: the material length l = 0.1 mm is not "
                              "resolved by this mesh")) << r.err;
}

TEST(Executable, UnknownKey) {
  TempDir dir;
  expect_run_fails(dir, "bad.ini", std::string(kLoad) + "[material]\nEe = 3e9\n",
                   {"bad.ini", "material.Ee"});
}

TEST(Executable, MalformedNumber) {
  TempDir dir;
  expect_run_fails(dir, "bad.ini", std::string(kLoad) + "[material]\nE = 3.09 GPa\n",
                   {"bad.ini", "material.E", "not a number"});
}

TEST(Executable, PoissonRatioTooLarge) {
  TempDir dir;
  expect_run_fails(dir, "bad.ini", std::string(kLoad) + "[material]\nnu = 0.5\n",
                   {"bad.ini", "material.nu", "out of range"});
}

TEST(Executable, NegativeDensity) {
  TempDir dir;
  expect_run_fails(dir, "bad.ini", std::string(kLoad) + "[material]\nrho0 = -1180\n",
                   {"bad.ini", "material.rho0", "out of range"});
}

TEST(Executable, MissingLoad) {
  TempDir dir;
  expect_run_fails(dir, "bad.ini", "[material]\nE = 3e9\n",
                   {"bad.ini", "loading.sigma_over_sigmac or loading.sigma"});
}

TEST(Executable, BadSetOverride) {
  TempDir dir;
  const std::string file = dir.write("ok.ini", kLoad);
  const Result r =
      run_brittle(dir, {"run", file, "--set", "run.cfl=2", "--out", (dir / "out").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_TRUE(contains(r.err, "--set: run.cfl = 2 is out of range")) << r.err;
}

TEST(Executable, MissingSceneFile) {
  TempDir dir;
  const std::string missing = (dir / "missing.ini").string();
  const Result r = run_brittle(dir, {"run", missing, "--out", (dir / "out").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.err, "brittle: error: scene file '" + missing + "': cannot be opened\n");
}

TEST(Executable, MissingMeshFile) {
  TempDir dir;
  expect_run_fails(dir, "bad.ini", std::string(kLoad) + "[mesh]\nfile = does_not_exist.msh\n",
                   {"bad.ini", "mesh.file", "does_not_exist.msh"});
}

TEST(Executable, ZeroVolumeTetIsRejected) {
  TempDir dir;
  // Four coplanar points (z = 0): the one tet has zero volume.
  fs::path mesh = fs::path(BRITTLE_TEST_DATA) / "degenerate_tet.vtu";
  if (!fs::exists(mesh)) {
    mesh = dir.write("degenerate_tet.vtu", R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="4" NumberOfCells="1">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">
          0 0 0  1e-3 0 0  0 1e-3 0  1e-3 1e-3 0
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
)");
  }
  expect_run_fails(dir, "bad.ini",
                   std::string(kLoad) + "[mesh]\nfile = " + fs::absolute(mesh).string() + "\n",
                   {"degenerate_tet.vtu"});
}

namespace {
TEST(RunErrors, BadRegionsExitTwoWithOneLine) {
  TempDir dir;
  const std::string base = dir.write(
      "bar.ini",
      "[initial]\nstate = rest\n[geometry]\nL = 4e-3\nH = 2e-3\nT = 0.5e-3\nnotch_depth = 0\n"
      "[mesh]\nsize = 1e-3\n[run]\nend_time = 1e-7\n[output]\nvtu = false\nframe_interval = 0\n");
  // A box beside the plate selects nothing.
  const std::string empty = dir.write(
      "empty.ini", "[boundary.pull]\ntype = traction\nbox = 1, 2, -inf, inf, -inf, inf\n"
                   "traction = 1e6, 0, 0\n");
  Result r = run_brittle(dir, {"run", base, empty, "--out", (dir / "o1").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("[boundary.pull]: the region (box 1, 2, -inf, inf, -inf, inf)"),
            std::string::npos)
      << r.err;
  // A box through the body holds the faces between its tets: interior.
  const std::string interior = dir.write(
      "interior.ini", "[boundary.pull]\ntype = traction\nbox = 1e-3, 3e-3, -inf, inf, -inf, inf\n"
                      "traction = 1e6, 0, 0\n");
  r = run_brittle(dir, {"run", base, interior, "--out", (dir / "o2").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("interior face(s); a traction acts on boundary faces only"),
            std::string::npos)
      << r.err;
}
}  // namespace

// Guards (issue 12): values that are each allowed but would hang a run or take the machine down
// (a mesh of 1e15 tets, rows every 1e-300 s, dt near 0) are refused before meshing or stepping:
// exit 2, one line naming the key, within a second plus twice what meshing the plate and
// setting up its Simulation take on this machine (`--dry-run` of the same scene: the dt guards
// need that much; on the 2026-12-03 VM with the other test slot busy it took 0.4-0.7 s, and a
// fixed 1 s failed by 0.15-0.4 s). A run that went on to step would take minutes to hours.
TEST(Executable, GuardsRefuseAtOnce) {
  TempDir dir;
  const auto setup_start = std::chrono::steady_clock::now();
  const Result setup = run_brittle(dir, {"run", dir.write("plain.ini", kLoad), "--dry-run"});
  ASSERT_EQ(setup.exit_code, 0) << setup.err;
  const double setup_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
  struct Case {
    std::string text;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      {"[mesh]\nsize = 1e-9\n", {"mesh.size = 1e-09", "mesh.max_elements"}},
      {"[mesh]\nlayers = 100000\n", {"mesh.layers = 100000", "mesh.max_elements"}},
      {"[geometry]\nH = 20\n", {"geometry.L x H", "mesh.max_elements"}},
      {"[geometry]\nH = 1e3\n", {"geometry.L x H", "within a factor 1000"}},
      {"[output]\nenergy_interval = 1e-300\n", {"output.energy_interval", "energy rows"}},
      {"[output]\nframe_interval = 1e-12\n", {"output.frame_interval", "frames"}},
      {"[output]\nframe_interval = 1e-300\n", {"output.frame_interval", "frames"}},
      {"[run]\nthreads = 2147483647\n", {"run.threads", "1024"}},
      {"[run]\ncfl = 1e-300\n", {"run.cfl", "steps"}},
      {"[material]\nzeta2 = 1e300\n", {"material.zeta2", "stable time step"}},
  };
  for (const Case& c : cases) {
    const std::string file = dir.write("guard.ini", std::string(kLoad) + c.text);
    const fs::path out = dir / "out";
    const auto start = std::chrono::steady_clock::now();
    const Result r = run_brittle(dir, {"run", file, "--out", out.string()});
    const double seconds =  // (not checked under the sanitizers)
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 2) << c.text << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not exactly one line: " << r.err;
    for (const auto& p : c.parts) EXPECT_TRUE(contains(r.err, p)) << "'" << p << "' not in " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.text << "left an output directory";
    if (!kSanitized) {
      EXPECT_LT(seconds, 1.0 + 2 * setup_seconds) << c.text;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Failures keep data (issue 12, item 3): a run that stops writes only complete files, no .tmp,
// and a summary that is valid JSON whenever it can be written; the error is the first one.

namespace {

/// The last line of `text` without its newline.
std::string last_line(const std::string& text) {
  const std::size_t end = text.find_last_not_of('\n');
  if (end == std::string::npos) return "";
  const std::size_t begin = text.rfind('\n', end);
  const std::size_t first = begin == std::string::npos ? 0 : begin + 1;
  return text.substr(first, end - first + 1);
}

/// Every file under `dir` whose name ends with `.tmp`.
std::vector<std::string> temporary_files(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".tmp") found.push_back(e.path().string());
  return found;
}

/// Every VTU / VTP in `dir`/frames reads back whole (VTK reports no error, every cell there),
/// and every file a .pvd lists exists.
void expect_complete_frames(const fs::path& dir, vtkIdType cells) {
  for (const auto& e : fs::directory_iterator(dir / "frames")) {
    const std::string file = e.path().string();
    vtkSmartPointer<vtkXMLReader> reader;
    if (e.path().extension() == ".vtu")
      reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    else
      reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    reader->SetFileName(file.c_str());
    reader->Update();
    EXPECT_EQ(reader->GetErrorCode(), 0) << file;
    vtkDataSet* data = vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
    ASSERT_NE(data, nullptr) << file;
    if (e.path().extension() == ".vtu") {
      EXPECT_EQ(data->GetNumberOfCells(), cells) << file;
    }
    vtkDataArray* time = data->GetFieldData()->GetArray("TimeValue");
    EXPECT_NE(time, nullptr) << file;
  }
  for (const char* pvd : {"run.pvd", "links.pvd"}) {
    if (!fs::exists(dir / pvd)) continue;
    std::vector<brittle::PvdEntry> entries;
    ASSERT_NO_THROW(entries = brittle::read_pvd((dir / pvd).string())) << pvd;
    for (const auto& entry : entries) EXPECT_TRUE(fs::is_regular_file(entry.file)) << entry.file;
  }
}

}  // namespace

// A run that blows up (a patch of nodes thrown at 20 km/s inverts its elements in the first
// step): exit 2, the blow-up on one line, frames so far, and a summary that is valid JSON with
// null where the numbers are not finite and a status that says so.
TEST(Failures, ABlowUpWritesAValidSummary) {
  TempDir dir;
  const std::string file =
      dir.write("kick.ini",
                "[mesh]\nsize = 2e-3\n[loading]\nsigma_over_sigmac = 0.5\n[run]\nend_time = 2e-6\n"
                "threads = 1\n[initial.kick]\nbox = 0.014, 0.018, -0.002, 0.002, -inf, inf\n"
                "velocity = 0, 2e4, 0\n");
  const fs::path out = dir / "out";
  const Result r = run_brittle(dir, {"run", file, "--out", out.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::string error = last_line(r.err);
  EXPECT_EQ(error.rfind("brittle: error: blow-up at t = ", 0), 0u) << r.err;
  const std::string text = read_text(out / "summary.json");
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(text)) << text;
  const std::string status = j.at("status");
  EXPECT_EQ(
      status.rfind("failed: " + error.substr(16) + "; non-finite values written as null: ", 0), 0u)
      << status;
  EXPECT_TRUE(contains(status, "final_elastic")) << status;
  EXPECT_TRUE(j.at("final_elastic").is_null());
  for (const char* number : {": nan", ": -nan", ": inf", ": -inf", ": NaN", "Infinity"})
    EXPECT_EQ(text.find(number), std::string::npos) << number << " in " << text;
  EXPECT_TRUE(temporary_files(out).empty());
  EXPECT_EQ(brittle::read_pvd((out / "run.pvd").string()).size(), 1u);  // the frame at t = 0
  expect_complete_frames(out, 996);
}

// A run onto a full disk: a 2 MB tmpfs holds the CM plate's first two frames (0.7 + 1.0 MB)
// but not the third. The run stops at once with one line naming that frame and the OS reason,
// leaves no .tmp, every file it leaves is complete, and the summary (small: it fits once the
// failed frame's temporary file is gone) carries the same first error.
TEST(Failures, AFullDiskFailsCleanly) {
  brittle::testing::SmallTmpfs disk(2 * 1024 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here: " << disk.reason();
  TempDir dir;
  const fs::path out = disk.path() / "run";
  const Result r =
      run_brittle(dir, {"run", std::string(BRITTLE_SOURCE_DIR) + "/scenes/cm.ini", "--set",
                        "run.end_time=5e-6", "--set", "run.threads=1", "--out", out.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::string error = last_line(r.err);
  EXPECT_EQ(error, "brittle: error: output: cannot write '" +
                       (out / "frames/frame_0002.vtu").string() + "': No space left on device")
      << r.err;
  EXPECT_TRUE(temporary_files(disk.path()).empty()) << temporary_files(disk.path()).front();
  EXPECT_EQ(brittle::read_pvd((out / "run.pvd").string()).size(), 2u);
  expect_complete_frames(out, 14676);
  // energies.csv: whole rows only, from t = 0 on
  std::ifstream csv(out / "energies.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 9) << line;
    ++rows;
  }
  EXPECT_GT(rows, 2);
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(read_text(out / "summary.json")));
  EXPECT_EQ(j.at("status"), "failed: " + error.substr(16));
}
