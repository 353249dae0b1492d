// Scene files and the command line: load_scene (defaults, override order, --set, lists, every
// error message naming its file and key) and the `brittle` executable's one-line errors.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
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
#include "error.hpp"
#include "fixtures.hpp"
#include "output.hpp"
#include "scene_options.hpp"

namespace fs = std::filesystem;
using namespace brittle_test;
using brittle::load_scene;
using brittle::Scene;
using brittle::BoundaryParams;
using brittle::InitialParams;
using brittle::NotchParams;
using brittle::TimeHistory;

namespace {

/// The minimal valid scene: only the load is required.
const char* kLoad = "[loading]\nsigma_over_sigmac = 0.6\n";

/// The message of the brittle::Error that `f` throws ("" and a test failure if none).
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const brittle::Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-brittle exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no brittle::Error thrown";
  return "";
}

/// Loads one scene file with `text` and returns the error message.
std::string file_error(const TempDir& dir, const std::string& text,
                       const std::vector<std::string>& sets = {}) {
  const std::string file = dir.write("bad.ini", text);
  return error_of([&] { load_scene({file}, sets); });
}

/// Checks a message is one line and contains every part.
void expect_message(const std::string& msg, const std::vector<std::string>& parts) {
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
  for (const auto& p : parts) EXPECT_TRUE(contains(msg, p)) << "'" << p << "' not in: " << msg;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// load_scene: values

TEST(LoadScene, DefaultsAreThePapersValues) {
  TempDir dir;
  const std::string file = dir.write("load.ini", kLoad);
  const Scene s = load_scene({file}, {});
  const Scene def;
  EXPECT_EQ(s.material.rho0, 1180.0);
  EXPECT_EQ(s.material.E, 3.09e9);
  EXPECT_EQ(s.material.nu, 0.35);
  EXPECT_EQ(s.material.sigma_c, 75e6);
  EXPECT_EQ(s.material.gamma, 150.0);
  EXPECT_EQ(s.material.zeta1, def.material.zeta1);
  EXPECT_EQ(s.material.zeta2, def.material.zeta2);
  EXPECT_EQ(s.geometry.L, def.geometry.L);
  EXPECT_EQ(s.geometry.H, def.geometry.H);
  EXPECT_EQ(s.geometry.T, def.geometry.T);
  EXPECT_EQ(s.geometry.notch_depth, def.geometry.notch_depth);
  EXPECT_EQ(s.geometry.notch_base, def.geometry.notch_base);
  EXPECT_EQ(s.mesh.file, "");
  EXPECT_EQ(s.mesh.size, def.mesh.size);
  EXPECT_EQ(s.mesh.band, def.mesh.band);
  EXPECT_EQ(s.mesh.band_size, def.mesh.band_size);
  EXPECT_EQ(s.mesh.layers, def.mesh.layers);
  EXPECT_EQ(s.loading.sigma_over_sigmac, 0.6);
  EXPECT_TRUE(std::isnan(s.loading.sigma));
  EXPECT_DOUBLE_EQ(s.loading.stress(s.material), 0.6 * 75e6);
  EXPECT_EQ(s.run.end_time, def.run.end_time);
  EXPECT_EQ(s.run.cfl, def.run.cfl);
  EXPECT_EQ(s.run.threads, def.run.threads);
  EXPECT_EQ(s.output.directory, def.output.directory);
  EXPECT_EQ(s.output.frame_interval, def.output.frame_interval);
  EXPECT_TRUE(s.output.frame_times.empty());
  EXPECT_EQ(s.output.vtu, def.output.vtu);
  EXPECT_EQ(s.output.energy_interval, def.output.energy_interval);
  EXPECT_EQ(s.sources, std::vector<std::string>{file});
}

TEST(LoadScene, EveryTypeAndSection) {
  TempDir dir;
  const std::string file = dir.write("all.ini", R"(# a comment line
[material]
rho0 = 1200
E = 3e9          # trailing comment
nu = 0.3
sigma_c = 7.0e7
gamma = 100
zeta1 = 0
zeta2 = 0.2
[geometry]
L = 0.02
H = 0.01
T = 1e-3
notch_depth = 0
notch_base = 0
[mesh]
size = 1e-3
band = 2e-3
band_size = 2.5e-4
layers = 3
[loading]
sigma = 30e6
[run]
end_time = 1e-5
cfl = 1
threads = 2
[output]
directory = results/cm
frame_interval = 0
frame_times = 1e-6, 15e-6 30e-6
vtu = false
energy_interval = 2e-7
)");
  const Scene s = load_scene({file}, {});
  EXPECT_EQ(s.material.rho0, 1200.0);
  EXPECT_EQ(s.material.E, 3e9);
  EXPECT_EQ(s.material.nu, 0.3);
  EXPECT_EQ(s.material.sigma_c, 7e7);
  EXPECT_EQ(s.material.gamma, 100.0);
  EXPECT_EQ(s.material.zeta1, 0.0);
  EXPECT_EQ(s.material.zeta2, 0.2);
  EXPECT_EQ(s.geometry.L, 0.02);
  EXPECT_EQ(s.geometry.H, 0.01);
  EXPECT_EQ(s.geometry.T, 1e-3);
  EXPECT_EQ(s.geometry.notch_depth, 0.0);
  EXPECT_EQ(s.geometry.notch_base, 0.0);
  EXPECT_EQ(s.mesh.size, 1e-3);
  EXPECT_EQ(s.mesh.band, 2e-3);
  EXPECT_EQ(s.mesh.band_size, 2.5e-4);
  EXPECT_EQ(s.mesh.layers, 3);
  EXPECT_EQ(s.loading.sigma, 30e6);
  EXPECT_TRUE(std::isnan(s.loading.sigma_over_sigmac));
  EXPECT_EQ(s.run.end_time, 1e-5);
  EXPECT_EQ(s.run.cfl, 1.0);
  EXPECT_EQ(s.run.threads, 2);
  EXPECT_EQ(s.output.directory, "results/cm");
  EXPECT_EQ(s.output.frame_interval, 0.0);
  EXPECT_EQ(s.output.frame_times, (std::vector<double>{1e-6, 15e-6, 30e-6}));
  EXPECT_FALSE(s.output.vtu);
  EXPECT_EQ(s.output.energy_interval, 2e-7);
}

TEST(LoadScene, LaterFilesOverrideEarlierOnes) {
  TempDir dir;
  const std::string a =
      dir.write("a.ini", "[material]\nE = 1e9\nnu = 0.3\n[loading]\nsigma = 1e6\n");
  const std::string b = dir.write("b.ini", "[material]\nE = 2e9\n[mesh]\nlayers = 2\n");
  const std::string c = dir.write("c.ini", "[mesh]\nlayers = 4\n");
  const Scene s = load_scene({a, b, c}, {});
  EXPECT_EQ(s.material.E, 2e9);
  EXPECT_EQ(s.material.nu, 0.3);  // only a.ini sets it
  EXPECT_EQ(s.mesh.layers, 4);
  EXPECT_EQ(s.loading.sigma, 1e6);
  EXPECT_EQ(s.sources, (std::vector<std::string>{a, b, c}));

  const Scene r = load_scene({c, b, a}, {});
  EXPECT_EQ(r.material.E, 1e9);
  EXPECT_EQ(r.mesh.layers, 2);
}

TEST(LoadScene, SetOverridesComeLastInOrder) {
  TempDir dir;
  const std::string a = dir.write("a.ini", "[material]\nE = 1e9\n[loading]\nsigma = 1e6\n");
  const Scene s = load_scene({a}, {"material.E=2e9", "run.threads = 3", "material.E=2.5e9",
                                   "output.vtu=no", "output.frame_times=1e-6 2e-6"});
  EXPECT_EQ(s.material.E, 2.5e9);
  EXPECT_EQ(s.run.threads, 3);
  EXPECT_FALSE(s.output.vtu);
  EXPECT_EQ(s.output.frame_times, (std::vector<double>{1e-6, 2e-6}));
  ASSERT_EQ(s.sources.size(), 6u);
  EXPECT_EQ(s.sources[0], a);
  EXPECT_EQ(s.sources[1], "--set material.E=2e9");
  EXPECT_EQ(s.sources[3], "--set material.E=2.5e9");

  // --set alone (no file) is a complete scene too.
  const Scene t = load_scene({}, {"loading.sigma_over_sigmac=0.9"});
  EXPECT_EQ(t.loading.sigma_over_sigmac, 0.9);
}

TEST(LoadScene, LaterLoadKindClearsTheEarlierOne) {
  TempDir dir;
  const std::string ratio = dir.write("ratio.ini", "[loading]\nsigma_over_sigmac = 0.6\n");
  const std::string pa = dir.write("pa.ini", "[loading]\nsigma = 50e6\n");
  Scene s = load_scene({ratio, pa}, {});
  EXPECT_EQ(s.loading.sigma, 50e6);
  EXPECT_TRUE(std::isnan(s.loading.sigma_over_sigmac));
  EXPECT_EQ(s.loading.stress(s.material), 50e6);

  s = load_scene({pa, ratio}, {});
  EXPECT_EQ(s.loading.sigma_over_sigmac, 0.6);
  EXPECT_TRUE(std::isnan(s.loading.sigma));

  s = load_scene({pa}, {"loading.sigma_over_sigmac=0.9"});
  EXPECT_EQ(s.loading.sigma_over_sigmac, 0.9);
  EXPECT_TRUE(std::isnan(s.loading.sigma));
}

TEST(LoadScene, FrameTimesList) {
  TempDir dir;
  auto times = [&](const std::string& value) {
    const std::string f =
        dir.write("ft.ini", std::string(kLoad) + "[output]\nframe_times = " + value + "\n");
    return load_scene({f}, {}).output.frame_times;
  };
  EXPECT_EQ(times("1e-6"), std::vector<double>{1e-6});
  EXPECT_EQ(times("0, 1e-6,15e-6   30e-6"), (std::vector<double>{0, 1e-6, 15e-6, 30e-6}));
  EXPECT_EQ(times("1e-6 , 2e-6 ,"), (std::vector<double>{1e-6, 2e-6}));
  EXPECT_TRUE(times("").empty());

  expect_message(file_error(dir, std::string(kLoad) + "[output]\nframe_times = 1e-6, abc\n"),
                 {"scene file '",
                  "bad.ini': output.frame_times = '1e-6, abc' is not a list of "
                  "numbers (expected"});
  expect_message(file_error(dir, std::string(kLoad) + "[output]\nframe_times = 2e-6, 1e-6\n"),
                 {"bad.ini", "output.frame_times = 2e-6, 1e-6 is out of range", "ascending"});
  expect_message(file_error(dir, std::string(kLoad) + "[output]\nframe_times = 1e-6 1e-6\n"),
                 {"bad.ini", "output.frame_times", "out of range"});
  expect_message(file_error(dir, std::string(kLoad) + "[output]\nframe_times = -1e-6 1e-6\n"),
                 {"bad.ini", "output.frame_times", "out of range", ">= 0"});
  // fracture.region: four numbers, ordered pairs
  expect_message(file_error(dir, std::string(kLoad) + "[fracture]\nregion = 0, 1, 2\n"),
                 {"bad.ini", "fracture.region", "out of range"});
  expect_message(file_error(dir, std::string(kLoad) + "[fracture]\nregion = 0, 1, 2, 1\n"),
                 {"bad.ini", "fracture.region", "out of range"});
}

TEST(LoadScene, MeshFileIsRelativeToTheSceneFile) {
  TempDir dir;
  dir.write("meshes/plate.vtu", "<VTKFile/>\n");  // only its existence is checked here
  const std::string scene =
      dir.write("scenes/rm.ini", std::string(kLoad) + "[mesh]\nfile = ../meshes/plate.vtu\n");
  const Scene s = load_scene({scene}, {});
  EXPECT_TRUE(fs::equivalent(s.mesh.file, dir / "meshes/plate.vtu")) << s.mesh.file;

  // An absolute path stays as it is; --set paths are relative to the working directory.
  const std::string abs = (dir / "meshes/plate.vtu").string();
  EXPECT_EQ(load_scene({scene}, {"mesh.file=" + abs}).mesh.file, abs);
  // A later empty value goes back to generating the mesh.
  EXPECT_EQ(load_scene({scene}, {"mesh.file="}).mesh.file, "");

  // The relative path's own directory: a file next to the scene, given by name only.
  dir.write("scenes/local.msh", "$MeshFormat\n");
  const std::string scene2 =
      dir.write("scenes/local.ini", std::string(kLoad) + "[mesh]\nfile = local.msh\n");
  EXPECT_TRUE(fs::equivalent(load_scene({scene2}, {}).mesh.file, dir / "scenes/local.msh"));
}

TEST(LoadScene, OutputDirectoryIsKeptAsWritten) {
  TempDir dir;
  const std::string scene =
      dir.write("sub/out.ini", std::string(kLoad) + "[output]\ndirectory = runs/a\n");
  EXPECT_EQ(load_scene({scene}, {}).output.directory, "runs/a");  // relative to the cwd
}

// ---------------------------------------------------------------------------------------------
// load_scene: errors name the file (or --set) and the key, on one line

TEST(LoadSceneErrors, UnreadableFile) {
  TempDir dir;
  const std::string missing = (dir / "nope.ini").string();
  EXPECT_EQ(error_of([&] { load_scene({missing}, {}); }),
            "scene file '" + missing + "': cannot be opened");
  expect_message(error_of([&] { load_scene({dir.path().string()}, {}); }),
                 {"scene file '" + dir.path().string() + "': cannot be opened"});
}

TEST(LoadSceneErrors, UnknownKeys) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  EXPECT_EQ(file_error(dir, std::string(kLoad) + "[material]\nEe = 3e9\n"),
            "scene file '" + f + "': unknown key 'material.Ee' (did you mean 'material.E'?)");
  EXPECT_EQ(
      file_error(dir, std::string(kLoad) + "[material]\nSIGMA_C = 3e9\n"),
      "scene file '" + f + "': unknown key 'material.SIGMA_C' (did you mean 'material.sigma_c'?)");
  expect_message(file_error(dir, std::string(kLoad) + "[material]\ndensity = 1000\n"),
                 {f, "unknown key 'material.density'"});
  EXPECT_FALSE(contains(file_error(dir, std::string(kLoad) + "[material]\ndensity = 1000\n"),
                        "did you mean"));
  expect_message(file_error(dir, std::string(kLoad) + "[materials]\nE = 3e9\n"),
                 {f, "unknown key 'materials.E'", "no section [materials]"});
  expect_message(file_error(dir, "E = 3e9\n" + std::string(kLoad)), {f, "unknown key 'E'"});
  // An unknown key in a known section names the key.
  for (const std::string section : {"fracture", "damage", "render"}) {
    const std::string msg =
        file_error(dir, std::string(kLoad) + "[" + section + "]\nno_such_key = x\n");
    expect_message(msg, {f, "unknown key '" + section + ".no_such_key'"});
  }
  expect_message(error_of([&] {
                   load_scene({}, {"loading.sigma=1e6", "material.Ee=1"});
                 }),
                 {"--set: unknown key 'material.Ee'"});
}

TEST(LoadSceneErrors, MalformedValues) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  EXPECT_EQ(file_error(dir, std::string(kLoad) + "[material]\nE = abc\n"),
            "scene file '" + f +
                "': material.E = 'abc' is not a number (expected Young's modulus in Pa, > 0)");
  expect_message(file_error(dir, std::string(kLoad) + "[material]\nE = 3e9x\n"),
                 {f, "material.E = '3e9x' is not a number"});
  expect_message(file_error(dir, std::string(kLoad) + "[material]\nE =\n"),
                 {f, "material.E = '' is not a number"});
  expect_message(file_error(dir, std::string(kLoad) + "[material]\nE = nan\n"),
                 {f, "material.E = 'nan' is not a number"});
  expect_message(file_error(dir, std::string(kLoad) + "[material]\ngamma = inf\n"),
                 {f, "material.gamma = 'inf' is not a number"});
  expect_message(file_error(dir, std::string(kLoad) + "[mesh]\nlayers = 1.5\n"),
                 {f, "mesh.layers = '1.5' is not an integer", "element layers", ">= 1"});
  expect_message(file_error(dir, std::string(kLoad) + "[output]\nvtu = maybe\n"),
                 {f, "output.vtu = 'maybe' is not true or false"});
  expect_message(file_error(dir, std::string(kLoad) + "[output]\nvtu =\n"),
                 {f, "output.vtu = '' is not true or false"});
  expect_message(error_of([&] {
                   load_scene({}, {"loading.sigma=1e6", "run.cfl=half"});
                 }),
                 {"--set: run.cfl = 'half' is not a number", "fraction of the stable time step"});
  expect_message(error_of([&] {
                   load_scene({}, {"loading.sigma=1e6", "material.E"});
                 }),
                 {"--set 'material.E': expected section.key=value"});
  expect_message(error_of([&] { load_scene({}, {"=1"}); }), {"--set '=1'", "section.key=value"});
}

TEST(LoadSceneErrors, SyntaxAndDuplicates) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  EXPECT_EQ(file_error(dir, std::string(kLoad) + "\n[material]\nE 3e9\n"),
            "scene file '" + f + "', line 5: 'E 3e9' is neither 'key = value' nor '[section]'");
  expect_message(file_error(dir, std::string(kLoad) + "[material]\nE = 1e9\nE = 2e9\n"),
                 {f, "material.E is given more than once"});
}

TEST(LoadSceneErrors, OutOfRange) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  struct Case {
    std::string section, key, value, expected;
  };
  const std::vector<Case> cases = {
      {"material", "rho0", "-1180", "> 0"},
      {"material", "rho0", "0", "> 0"},
      {"material", "E", "-3e9", "> 0"},
      {"material", "nu", "0.5", "-1 < nu < 0.5"},
      {"material", "nu", "0.7", "-1 < nu < 0.5"},
      {"material", "nu", "-1", "-1 < nu < 0.5"},
      {"material", "sigma_c", "0", "> 0"},
      {"material", "gamma", "-150", "> 0"},
      {"material", "zeta1", "-0.1", ">= 0"},
      {"material", "zeta2", "-0.1", ">= 0"},
      {"geometry", "L", "0", "> 0"},
      {"geometry", "H", "-1", "> 0"},
      {"geometry", "T", "0", "> 0"},
      {"geometry", "notch_depth", "-1e-3", "0 <= a"},
      {"geometry", "notch_base", "-1e-3", "0 <= b"},
      {"mesh", "size", "0", "> 0"},
      {"mesh", "band", "-1", ">= 0"},
      {"mesh", "band_size", "-1", ">= 0"},
      {"mesh", "layers", "0", ">= 1"},
      {"run", "end_time", "0", "> 0"},
      {"run", "cfl", "0", "0 < cfl <= 1"},
      {"run", "cfl", "1.01", "0 < cfl <= 1"},
      {"run", "threads", "-1", "0 <= threads <= 1024"},
      {"run", "threads", "1025", "0 <= threads <= 1024"},
      {"output", "frame_interval", "-1e-6", ">= 0"},
      {"output", "energy_interval", "0", "> 0"},
      {"output", "directory", "", "not empty"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.section + "." + c.key + " = " + c.value);
    const std::string msg =
        file_error(dir, std::string(kLoad) + "[" + c.section + "]\n" + c.key + " = " + c.value);
    expect_message(msg, {"scene file '" + f + "': " + c.section + "." + c.key + " = " + c.value +
                             " is out of range (expected ",
                         c.expected});
  }
  for (const std::string v : {"0", "-0.5", "3"}) {
    expect_message(file_error(dir, "[loading]\nsigma_over_sigmac = " + v + "\n"),
                   {f, "loading.sigma_over_sigmac = " + v + " is out of range", "0 < s < 3"});
  }
  expect_message(file_error(dir, "[loading]\nsigma = -1e6\n"),
                 {f, "loading.sigma = -1e6 is out of range", "> 0"});
  expect_message(error_of([&] {
                   load_scene({}, {"loading.sigma=1e6", "material.nu=0.5"});
                 }),
                 {"--set: material.nu = 0.5 is out of range (expected Poisson's ratio, "
                  "-1 < nu < 0.5)"});
}

TEST(LoadSceneErrors, KeysThatConstrainEachOther) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  expect_message(file_error(dir, std::string(kLoad) + "[geometry]\nnotch_depth = 0.032\n"),
                 {f, "geometry.notch_depth = 0.032 is out of range", "< geometry.L = 0.032"});
  expect_message(file_error(dir, std::string(kLoad) + "[geometry]\nH = 1e-4\n"),
                 {f, "geometry.notch_base", "< geometry.H = 0.0001"});
  // The file that made the pair inconsistent is the one named.
  const std::string ok = dir.write("ok.ini", std::string(kLoad) + "[geometry]\nL = 0.01\n");
  expect_message(error_of([&] { load_scene({ok}, {"geometry.notch_depth=0.02"}); }),
                 {"--set: geometry.notch_depth = 0.02", "< geometry.L = 0.01"});

  // A load the uniaxial pre-stress cannot carry (sigma >= 3K).
  expect_message(file_error(dir, "[loading]\nsigma = 1e11\n"),
                 {f, "sigma = 1e+11 Pa is out of range", "3K"});
}

TEST(LoadScene, NamedSections) {
  TempDir dir;
  const std::string f = dir.write("glass.ini",
                                  "[initial]\nstate = rest\n"
                                  "[notch.left]\nstart = 0, 0\ndirection = 1, 0\nlength = 5e-3\n"
                                  "opening = 1e-4\nshape = slot\n"
                                  "[boundary.top]\ntype = traction\nbox = -inf, inf, 8e-3, 8e-3, "
                                  "-inf, inf\ntraction = 0, 1e6, 0\n"
                                  "[boundary.hit]\ntype = velocity\nbox = 0, 0, -inf, inf, -inf, inf\n"
                                  "components = x\nvelocity = 16.5, 0, 0\nhistory = ramp\n"
                                  "ramp_time = 1e-6\n"
                                  "[initial.kick]\nbox = 0, 1e-3, -inf, inf, -inf, inf\n"
                                  "velocity = 1, 0, 0\n");
  // --set overrides one key of a named section; sections keep their order of appearance.
  const Scene s = load_scene({f}, {"boundary.top.traction=0, 2e6, 0"});
  EXPECT_EQ(s.initial.state, InitialParams::State::rest);
  ASSERT_EQ(s.geometry.notches.size(), 1u);
  EXPECT_EQ(s.geometry.notches[0].shape, NotchParams::Shape::slot);
  EXPECT_EQ(s.geometry.notches[0].length, 5e-3);
  ASSERT_EQ(s.boundaries.size(), 2u);
  EXPECT_EQ(s.boundaries[0].name, "top");
  EXPECT_EQ(s.boundaries[0].type, BoundaryParams::Type::traction);
  EXPECT_EQ(s.boundaries[0].value[1], 2e6);
  EXPECT_TRUE(std::isinf(s.boundaries[0].region.box[0]));
  EXPECT_EQ(s.boundaries[1].type, BoundaryParams::Type::velocity);
  EXPECT_TRUE(s.boundaries[1].components[0]);
  EXPECT_FALSE(s.boundaries[1].components[1]);
  EXPECT_EQ(s.boundaries[1].history.kind, TimeHistory::Kind::ramp);
  EXPECT_DOUBLE_EQ(s.boundaries[1].history.at(0.5e-6), 0.5);
  ASSERT_EQ(s.initial.velocities.size(), 1u);
  EXPECT_EQ(s.initial.velocities[0].velocity[0], 1.0);
}

TEST(LoadSceneErrors, NamedSections) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  const std::string rest = "[initial]\nstate = rest\n";
  expect_message(file_error(dir, rest + "[boundary.top]\nbox = 0,1,0,1,0,1\n"),
                 {f, "[boundary.top] needs type", "fixed | velocity | traction"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = push\nbox = 0,1,0,1,0,1\n"),
                 {f, "boundary.top.type = 'push'", "fixed | velocity | traction"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = traction\nbox = 0,1,0,1,0,1\n"),
                 {f, "[boundary.top] needs traction"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = fixed\n"),
                 {f, "[boundary.top] needs box", "or group"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = fixed\nbox = 0,1,0\n"),
                 {f, "boundary.top.box = '0,1,0' has 3 numbers, not 6"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = fixed\nbox = 1,0,0,1,0,1\n"),
                 {f, "boundary.top.box", "minimum above its maximum"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = fixed\nbox = 0,1,0,1,0,1\n"
                                        "traction = 1,2,3\n"),
                 {f, "boundary.top.traction", "does not go with type = fixed"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = fixed\ngroup = top\n"),
                 {"[boundary.top]: group = 'top' needs mesh.file to be a Gmsh .msh file"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntpye = fixed\n"),
                 {f, "unknown key 'boundary.top.tpye'", "keys of [boundary.NAME] are type box"});
  expect_message(file_error(dir, rest + "[boundary]\ntype = fixed\n"),
                 {f, "unknown key 'boundary.type'", "e.g. [boundary.a]"});
  expect_message(file_error(dir, rest + "[boundary.top]\ntype = velocity\nbox = 0,1,0,1,0,1\n"
                                        "velocity = 1,0,0\nhistory = table\ntable = 0,0,1e-6\n"),
                 {f, "boundary.top.table", "(t, value) pairs"});
  expect_message(file_error(dir, rest + "[notch.a]\nstart = 0,0\ndirection = 0,0\nlength = 1\n"
                                        "opening = 1\n"),
                 {f, "notch.a.direction", "zero vector"});
  expect_message(file_error(dir, rest + "[geometry]\nnotch_depth = 1e-3\n[notch.a]\nstart = 0,0\n"
                                        "direction = 1,0\nlength = 1e-3\nopening = 1e-4\n"),
                 {f, "[notch.NAME] sections are both given"});
}

TEST(LoadSceneErrors, ExactlyOneLoad) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  EXPECT_EQ(file_error(dir, "[material]\nE = 3e9\n"),
            "scene file '" + f +
                "': no load given (expected loading.sigma_over_sigmac or loading.sigma in "
                "[loading], or initial.state = rest with [boundary.NAME] loads)");
  expect_message(file_error(dir, "[loading]\nsigma_over_sigmac = 0.6\nsigma = 1e6\n"),
                 {f, "loading.sigma_over_sigmac and loading.sigma are both given"});
  const std::string a = dir.write("a.ini", "[material]\nE = 3e9\n");
  const std::string b = dir.write("b.ini", "[run]\ncfl = 0.4\n");
  expect_message(error_of([&] {
                   load_scene({a, b}, {});
                 }),
                 {"scene files '" + a + "', '" + b + "'",
                  "loading.sigma_over_sigmac or "
                  "loading.sigma"});
}

TEST(LoadSceneErrors, MissingMeshFileNamesTheMeshFile) {
  TempDir dir;
  const std::string f = (dir / "bad.ini").string();
  const std::string msg =
      file_error(dir, std::string(kLoad) + "[mesh]\nfile = does_not_exist.msh\n");
  expect_message(msg, {"scene file '" + f + "'", "mesh.file", (dir / "does_not_exist.msh").string(),
                       "cannot be opened"});
  expect_message(file_error(dir, std::string(kLoad) + "[mesh]\nfile = plate.stl\n"),
                 {f, "mesh.file = '", "plate.stl' is not a .msh or .vtu file"});
}

TEST(SceneKeys, HelpListsEveryKeyWithDefaultUnitAndMeaning) {
  std::ostringstream out;
  brittle::print_scene_keys(out);
  const std::string help = out.str();
  for (const std::string key : {"material.rho0",
                                "material.E",
                                "material.nu",
                                "material.sigma_c",
                                "material.gamma",
                                "material.zeta1",
                                "material.zeta2",
                                "geometry.L",
                                "geometry.H",
                                "geometry.T",
                                "geometry.notch_depth",
                                "geometry.notch_base",
                                "mesh.file",
                                "mesh.size",
                                "mesh.band",
                                "mesh.band_size",
                                "mesh.layers",
                                "loading.sigma_over_sigmac",
                                "loading.sigma",
                                "run.end_time",
                                "run.cfl",
                                "run.threads",
                                "output.directory",
                                "output.frame_interval",
                                "output.frame_times",
                                "output.vtu",
                                "output.energy_interval"})
    EXPECT_TRUE(contains(help, key + " ")) << key;
  for (const std::string section :
       {"[material]", "[geometry]", "[mesh]", "[loading]", "[run]", "[output]"})
    EXPECT_TRUE(contains(help, section)) << section;
  EXPECT_TRUE(contains(help, "3.09e+09")) << help;
  EXPECT_TRUE(contains(help, "[kg/m^3]")) << help;
  EXPECT_TRUE(contains(help, "Young's modulus")) << help;
}

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

// docs/scenes.md documents every key the program knows (the key table is the one source;
// this keeps the page from drifting away from it).
TEST(SceneDocs, EveryKeyIsDocumented) {
  std::ostringstream help;
  brittle::print_scene_keys(help);
  std::ifstream page(std::string(BRITTLE_SOURCE_DIR) + "/docs/scenes.md");
  const std::string doc((std::istreambuf_iterator<char>(page)), {});
  ASSERT_FALSE(doc.empty());
  std::istringstream lines(help.str());
  int keys = 0;
  for (std::string line; std::getline(lines, line);) {
    // key lines: "  section.key   = default ..."
    std::istringstream words(line);
    std::string key, eq;
    if (line.rfind("  ", 0) != 0 || !(words >> key >> eq) || eq != "=" ||
        key.find('.') == std::string::npos)
      continue;
    ++keys;
    EXPECT_NE(doc.find("`" + key + "`"), std::string::npos) << key << " is missing from docs/scenes.md";
  }
  EXPECT_GT(keys, 40);
  // Keys of named sections: "[boundary.NAME]" then "  type  ..." lines, documented as
  // `boundary.NAME.type`.
  std::istringstream named(help.str().substr(help.str().find("Named sections")));
  std::string kind;
  int named_keys = 0;
  for (std::string line; std::getline(named, line);) {
    if (line.rfind("[", 0) == 0) {
      kind = line.substr(1, line.find('.') - 1);
      continue;
    }
    std::istringstream words(line);
    std::string key;
    if (kind.empty() || line.rfind("  ", 0) != 0 || !(words >> key)) continue;
    ++named_keys;
    EXPECT_NE(doc.find("`" + kind + ".NAME." + key + "`"), std::string::npos)
        << kind << ".NAME." << key << " is missing from docs/scenes.md";
  }
  EXPECT_GT(named_keys, 15);
}

}  // namespace

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

// The estimate behind mesh.max_elements is close to what Gmsh makes (docs/scenes.md).
TEST(LoadScene, ElementEstimateIsCloseToTheMesh) {
  Scene cm;  // the paper's plate: 14,676 tets
  EXPECT_NEAR(estimated_tets(cm.geometry, cm.mesh) / 14676, 1.0, 0.05);
  Scene rm = cm;  // RM: 44,652 tets
  rm.mesh.band = 1e-3, rm.mesh.band_size = 250e-6, rm.mesh.layers = 2;
  EXPECT_NEAR(estimated_tets(rm.geometry, rm.mesh) / 44652, 1.0, 0.07);
  Scene fine = cm;  // docs/performance.md's largest plate: 1,776,150 tets
  fine.mesh.size = 100e-6, fine.mesh.layers = 5;
  EXPECT_NEAR(estimated_tets(fine.geometry, fine.mesh) / 1776150, 1.0, 0.01);
}

// brittle run --dry-run: the counts and estimates of a scene, and nothing written.
TEST(Executable, DryRunPrintsTheRunAndWritesNothing) {
  TempDir dir;
  const std::string file = dir.write("plate.ini", std::string(kLoad) + "[run]\nend_time = 2e-6\n");
  const fs::path out = dir / "out";
  const Result r = run_brittle(dir, {"run", file, "--dry-run", "--out", out.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* part : {"14676 tets", "5102 nodes", "steps to 2e-06 s", "frames", "energy rows",
                           "memory", "disk", "wall", "dt_e      smallest", "1st percentile",
                           "median", "within 10 % of the smallest", "smallest: element",
                           "damping ratio"})
    EXPECT_TRUE(contains(r.out, part)) << "'" << part << "' not in " << r.out;
  EXPECT_FALSE(fs::exists(out)) << "a dry run wrote " << out;
  // The guards apply to a dry run too.
  const Result big = run_brittle(dir, {"run", file, "--dry-run", "--set", "mesh.size=1e-9"});
  EXPECT_EQ(big.exit_code, 2);
  EXPECT_TRUE(contains(big.err, "mesh.max_elements")) << big.err;
}

// Words are matched without regard to case, and a wrong word is answered with the words
// (issue 15); `brittle render RUN_DIR` renders RUN_DIR/run.pvd, and links.pvd is refused with
// what to give instead.
TEST(Executable, WordsIgnoreCaseAndRenderTakesARunDirectory) {
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const Result upper = run_brittle(
      dir, {"run", scenes + "cm.ini", "--set", "fracture.mode=STRAIGHT", "--set",
            "initial.state=PreStress", "--set", "render.fields=Sigma1,CRACK", "--show-scene"});
  ASSERT_EQ(upper.exit_code, 0) << upper.err;
  for (const char* line : {"mode = straight\n", "state = prestress\n", "fields = sigma1, crack\n"})
    EXPECT_TRUE(contains(upper.out, line)) << line;
  const Result wrong = run_brittle(dir, {"run", scenes + "cm.ini", "--set", "fracture.mode=branchy",
                                         "--dry-run"});
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_TRUE(contains(wrong.err, "fracture.mode = 'branchy' is not one of: none, straight, branching"))
      << wrong.err;
  const Result named = run_brittle(dir, {"run", scenes + "kalthoff.ini", "--set",
                                         "boundary.impact.history=Rampy", "--dry-run"});
  EXPECT_EQ(named.exit_code, 2);
  EXPECT_TRUE(contains(named.err, "is not one of: constant, ramp, table")) << named.err;
  const fs::path out = dir / "out";
  ASSERT_EQ(run_brittle(dir, {"run", scenes + "cm.ini", "--set", "run.end_time=2e-6", "--out",
                              out.string()})
                .exit_code,
            0);
  const Result render = run_brittle(dir, {"render", out.string(), "--times", "1e-6", "--field",
                                          "sigma1", "--out", (dir / "png").string()});
  EXPECT_EQ(render.exit_code, 0) << render.err;
  EXPECT_TRUE(fs::exists(dir / "png" / "sigma1_001.000us.png")) << render.out;
  const Result links = run_brittle(dir, {"render", (out / "links.pvd").string()});
  EXPECT_EQ(links.exit_code, 2);
  EXPECT_TRUE(contains(links.err, "expected RUN_DIR or RUN_DIR/run.pvd")) << links.err;
}

// A run directory repeats itself (issue 15): DIR/scene.ini holds every key after the files
// and --set, `brittle run DIR/scene.ini` gives the same bits, summary.json names the version
// and every key; `--show-scene` prints the same scene and writes nothing. With the paper's
// hardest setting (branching, damage, RD links) and with named sections (Kalthoff-Winkler:
// [notch.*], [boundary.*] with a ramp, a rest state).
TEST(Executable, RunDirectorySceneRepeatsTheRun) {
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::vector<std::vector<std::string>> cases = {
      {scenes + "cm.ini", scenes + "branching.ini", scenes + "damage.ini",
       scenes + "rate-dependent.ini", "--set", "run.end_time=6e-6", "--set", "mesh.size=1e-3"},
      {scenes + "kalthoff.ini", "--set", "run.end_time=4e-6", "--set", "mesh.size=2e-3"}};
  int n = 0;
  for (const std::vector<std::string>& inputs : cases) {
    SCOPED_TRACE(inputs.front());
    const fs::path first = dir / ("first" + std::to_string(n)), again = dir / ("again" + std::to_string(n));
    ++n;
    std::vector<std::string> args = {"run"};
    args.insert(args.end(), inputs.begin(), inputs.end());
    args.insert(args.end(), {"--out", first.string()});
    ASSERT_EQ(run_brittle(dir, args).exit_code, 0);
    args.push_back("--show-scene");
    const Result shown = run_brittle(dir, args);
    ASSERT_EQ(shown.exit_code, 0) << shown.err;
    EXPECT_EQ(shown.out, read_text(first / "scene.ini"));
    const Result r = run_brittle(dir, {"run", (first / "scene.ini").string(), "--out", again.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* file : {"energies.csv", "crack_tip.csv", "events.csv", "pattern.json"})
      EXPECT_EQ(read_text(again / file), read_text(first / file)) << file;
    std::ifstream a(first / "summary.json"), b(again / "summary.json");
    nlohmann::json ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
    EXPECT_EQ(ja["brittle_version"], BRITTLE_VERSION);
    // the build: the commit it was built from (or why none), compiler, type and flags
    const nlohmann::json& build = ja.at("build");
    EXPECT_EQ(build.at("version"), BRITTLE_VERSION);
    EXPECT_GE(build.at("commit").get<std::string>().size(), 12u) << build;
    EXPECT_TRUE(contains(build.at("compiler").get<std::string>(), ".")) << build;
    EXPECT_FALSE(build.at("build_type").get<std::string>().empty()) << build;
    EXPECT_TRUE(build.at("flags").is_string()) << build;
    EXPECT_EQ(ja["scene"]["output.directory"], first.string());
    EXPECT_EQ(ja["scene"]["run.end_time"], jb["scene"]["run.end_time"]);
    for (auto* j : {&ja, &jb}) {
      for (const char* key : {"wall_seconds", "tet_updates_per_second", "phases", "scene_sources"})
        j->erase(key);
      (*j)["scene"].erase("output.directory");
    }
    EXPECT_EQ(ja, jb);
    EXPECT_GT(ja["scene"].size(), 45u) << "every key";
  }
}

// Progress forced on for batch logs (issue 15): a line every N steps although stderr is not a
// terminal; the run directory's run.log holds what went to stderr, once also for a sweep's
// child (whose stderr is that run.log already); a short run says it has no steady speed.
TEST(Executable, ProgressLinesAndRunLog) {
  TempDir dir;
  const std::string file = dir.write("plate.ini", "[loading]\nsigma_over_sigmac = 0.9\n"
                                                  "[fracture]\nmode = straight\n"
                                                  "[mesh]\nsize = 2e-3\n"
                                                  "[run]\nend_time = 4e-6\n");
  const fs::path out = dir / "out";
  const Result r = run_brittle(dir, {"run", file, "--out", out.string(), "--progress", "10"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int lines = 0;
  for (std::size_t at = r.err.find("brittle: step "); at != std::string::npos;
       at = r.err.find("brittle: step ", at + 1))
    ++lines;
  std::ifstream summary(out / "summary.json");
  const long steps = nlohmann::json::parse(summary)["steps"].get<long>();
  EXPECT_GT(steps, 20);
  EXPECT_EQ(lines, steps / 10) << r.err;  // steps 10, 20, ...
  EXPECT_EQ(read_text(out / "run.log"), r.err);
  EXPECT_TRUE(contains(r.err, "no steady speed")) << r.err;
  EXPECT_FALSE(contains(r.err, "nan m/s")) << r.err;
  const Result quiet = run_brittle(dir, {"run", file, "--out", out.string()});
  EXPECT_FALSE(contains(quiet.err, "brittle: step ")) << "no progress lines unless asked";
  // a sweep's child: its stderr is its run.log; each line once
  const Result sweep = run_brittle(dir, {"sweep", file, "--loads", "0.9", "--jobs", "1", "--out",
                                         (dir / "sweep").string()});
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  const std::string log = read_text(dir / "sweep" / "load_0.900" / "run.log");
  const std::string first = "tets, dt = ";
  EXPECT_NE(log.find(first), std::string::npos) << log;
  EXPECT_EQ(log.find(first), log.rfind(first)) << log;
}

// Frames land exactly on the requested times (issue 15): the step before a frame, and the
// last step, are shortened. The .pvd, each frame's TimeValue, the PNG names of render.times and
// the summary's end time are the decimals of the scene, to the bit.
TEST(Executable, FramesLandExactlyOnTheRequestedTimes) {
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  // the frames asked, with render.times 1 and 2.1 us (frames too)
  const std::vector<double> listed = {0.37e-6, 1e-6, 2.1e-6, 2.5e-6, 3e-6};
  const std::vector<double> every = {0, 0.7e-6, 1e-6, 1.4e-6, 2.1e-6, 2.8e-6};  // every 0.7 us
  for (const bool list : {true, false}) {
    const fs::path out = dir / (list ? "list" : "interval");
    const Result r = run_brittle(
        dir, {"run", scenes + "cm.ini", "--set", "mesh.size=2e-3", "--set", "run.end_time=3e-6",
              "--set",
              list ? "output.frame_times=0.37e-6, 1e-6, 2.5e-6, 3e-6" : "output.frame_interval=0.7e-6",
              "--set", "render.times=1e-6, 2.1e-6", "--set", "render.fields=sigma1", "--out",
              out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto entries = brittle::read_pvd((out / "run.pvd").string());
    std::vector<double> times;
    for (const auto& e : entries) {
      times.push_back(e.time);
      auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
      reader->SetFileName(e.file.c_str());
      reader->Update();
      vtkDataArray* t = reader->GetOutput()->GetFieldData()->GetArray("TimeValue");
      ASSERT_NE(t, nullptr) << e.file;
      EXPECT_EQ(t->GetTuple1(0), e.time) << e.file;
    }
    EXPECT_EQ(times, list ? listed : every);
    const nlohmann::json s = nlohmann::json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s.at("time").get<double>(), 3e-6);
    for (const char* png : {"sigma1_001.000us.png", "sigma1_002.100us.png"})
      EXPECT_TRUE(fs::exists(out / "render" / png)) << png;
  }
}

// One CLI (issue 15): every command's --help is its own usage, what it does and what its --out
// is, without the other commands or the internal positional options; --out is a directory for
// every command; option names are the scene keys' (--fields as render.fields, --frames yes|no
// on sweep, study and reproduce).
TEST(Executable, EveryCommandHasItsOwnHelpAndOneMeaningOfOut) {
  TempDir dir;
  const std::vector<std::string> commands = {"run",  "render", "analyze", "sweep", "chart",
                                             "tips", "figure", "reproduce", "partition"};
  for (const std::string& command : commands) {
    std::vector<std::string> args = {command, "--help"};
    if (command == "study") args = {"study", "--help"};
    const Result r = run_brittle(dir, args);
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
    EXPECT_EQ(r.out.rfind("usage: brittle " + command, 0), 0u) << r.out;
    for (const std::string& other : commands)
      if (other != command) {
        EXPECT_FALSE(contains(r.out, "brittle " + other + " ")) << command << " help names " << other;
      }
    for (const char* internal : {"--scene ", "--input ", "--run ", "--sweep ", "--field ", "--no-frames"})
      EXPECT_FALSE(contains(r.out, internal)) << command << " help shows " << internal;
    const std::size_t out = r.out.find("--out arg");
    if (command == "analyze") {  // writes into the run's own directory
      EXPECT_EQ(out, std::string::npos);
      continue;
    }
    ASSERT_NE(out, std::string::npos) << command;
    EXPECT_TRUE(contains(r.out.substr(out, 60), "directory")) << r.out.substr(out, 80);
  }
  const Result study = run_brittle(dir, {"study", "--help"});
  EXPECT_EQ(study.out.rfind("usage: brittle study mesh", 0), 0u) << study.out;
  EXPECT_TRUE(contains(run_brittle(dir, {"--help"}).out, "--out is always a directory"));

  // A file name given to --out is refused with what the command writes there.
  const Result chart = run_brittle(dir, {"chart", (dir / "s").string(), "--out", "speed.PNG"});
  EXPECT_EQ(chart.exit_code, 2);
  EXPECT_TRUE(contains(chart.err, "--out is a directory for every command")) << chart.err;
  EXPECT_TRUE(contains(chart.err, "crack_speed.png")) << chart.err;
  const Result tips = run_brittle(dir, {"tips", (dir / "r").string(), "--out", "t.png"});
  EXPECT_EQ(tips.exit_code, 2);
  EXPECT_TRUE(contains(tips.err, "tip_speed.png")) << tips.err;
  for (const char* command : {"sweep", "reproduce"}) {
    const Result bad = run_brittle(
        dir, {command, "--frames", "maybe", "--loads", "0.5", "--out", (dir / "x").string()});
    EXPECT_EQ(bad.exit_code, 2) << command;
    EXPECT_TRUE(contains(bad.err, "--frames 'maybe' is not one of: yes, no")) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "x")) << command << " wrote before refusing";
  }

  // render --fields (render.fields) into a directory; a panel is a PNG in that directory.
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const fs::path run = dir / "run";
  ASSERT_EQ(run_brittle(dir, {"run", scenes + "cm.ini", "--set", "mesh.size=2e-3", "--set",
                              "run.end_time=1e-6", "--out", run.string()})
                .exit_code,
            0);
  const Result render = run_brittle(dir, {"render", run.string(), "--fields", "sigma1,crack",
                                          "--out", (dir / "png").string(), "--panel", "both.png"});
  ASSERT_EQ(render.exit_code, 0) << render.err;
  for (const char* png : {"sigma1_001.000us.png", "crack_001.000us.png", "both.png"})
    EXPECT_TRUE(fs::exists(dir / "png" / png)) << png;
  const Result file = run_brittle(dir, {"render", run.string(), "--out", (dir / "f.png").string()});
  EXPECT_EQ(file.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "f.png"));
}

// run.stop_when_cut_through (issue 15), on by default: a straight crack on a short plate
// reaches the far edge (its node there splits) at about 11 us and the run stops there, with a last frame at that time
// and the summary saying when and where; off, the run goes on to run.end_time and the summary
// still says when the plate was cut.
TEST(Executable, ARunStopsWhenTheCrackCutsThePlateThrough) {
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  double cut_time = 0;
  for (const bool stop : {true, false}) {
    const fs::path out = dir / (stop ? "stop" : "on");
    std::vector<std::string> args = {"run", scenes + "cm.ini", "--set", "geometry.L=12e-3",
                                     "--set", "mesh.size=1e-3", "--set", "run.end_time=20e-6",
                                     "--set", "output.frame_interval=5e-6", "--out", out.string()};
    if (!stop) args.insert(args.end(), {"--set", "run.stop_when_cut_through=no"});
    const Result r = run_brittle(dir, args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json s = nlohmann::json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s.at("status"), "completed");
    const nlohmann::json& cut = s.at("cut_through");
    ASSERT_TRUE(cut.is_object()) << s.dump();
    EXPECT_NEAR(cut.at("x").get<double>(), 12e-3, 1e-12) << "the far edge's node split";
    EXPECT_EQ(cut.at("stopped").get<bool>(), stop);
    const auto frames = brittle::read_pvd((out / "run.pvd").string());
    if (stop) {
      cut_time = cut.at("t").get<double>();
      EXPECT_GT(cut_time, 5e-6);
      EXPECT_LT(cut_time, 15e-6);
      EXPECT_EQ(s.at("time").get<double>(), cut_time) << "stopped at the step that cut it";
      EXPECT_EQ(frames.back().time, cut_time) << "the last frame shows the cut plate";
      EXPECT_TRUE(contains(r.err, "cut the plate through")) << r.err;
    } else {
      EXPECT_EQ(cut.at("t").get<double>(), cut_time);
      EXPECT_EQ(s.at("time").get<double>(), 20e-6);
      EXPECT_EQ(frames.back().time, 20e-6);
    }
  }
}

// A run into a directory an earlier, longer run used removes that run's frames (and says so)
// and leaves every other file there as it was.
TEST(Executable, ARunRemovesAnEarlierRunsFramesOnly) {
  TempDir dir;
  const std::string file = dir.write("plate.ini", std::string(kLoad) +
                                                      "[mesh]\nsize = 2e-3\n[run]\nend_time = 2e-6\n");
  const fs::path out = dir / "out";
  ASSERT_EQ(run_brittle(dir, {"run", file, "--out", out.string(), "--set", "run.end_time=4e-6"})
                .exit_code,
            0);
  const int longer = static_cast<int>(
      std::distance(fs::directory_iterator(out / "frames"), fs::directory_iterator()));
  for (const char* mine : {"notes.txt", "frame_final.vtu", "frame_0001.vtu.bak", "links_x.vtp"})
    std::ofstream(out / "frames" / mine) << "the user's\n";
  std::ofstream(out / "frames" / "frame_0099_r3.vtu") << "an earlier decomposed run's piece\n";
  const Result r = run_brittle(dir, {"run", file, "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "removed " + std::to_string(longer + 1) + " frame files of an earlier run"))
      << r.err;
  for (const char* mine : {"notes.txt", "frame_final.vtu", "frame_0001.vtu.bak", "links_x.vtp"})
    EXPECT_EQ(read_text(out / "frames" / mine), "the user's\n") << mine;
  EXPECT_FALSE(fs::exists(out / "frames" / "frame_0099_r3.vtu"));
  // what is left is this run's frames (listed in run.pvd and links.pvd) and the user's files
  std::set<std::string> listed;
  for (const char* pvd : {"run.pvd", "links.pvd"})
    if (fs::exists(out / pvd))
      for (const brittle::PvdEntry& e : brittle::read_pvd((out / pvd).string()))
        listed.insert(fs::path(e.file).filename().string());
  EXPECT_FALSE(listed.empty());
  for (const auto& entry : fs::directory_iterator(out / "frames")) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(listed.count(name) || name == "notes.txt" || name == "frame_final.vtu" ||
                name == "frame_0001.vtu.bak" || name == "links_x.vtp")
        << name << " is left from the earlier run";
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
