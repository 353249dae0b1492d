// Scene files: load_scene (defaults, override order, --set, lists, named sections, every error
// message naming its file and key), the key table's --help, and docs/scenes.md against it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.hpp"
#include "error.hpp"
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
  expect_message(error_of([&] {
                   load_scene({}, {"loading.sigma=1e6", "run.mass_scaling=1e300"});
                 }),
                 {"--set: run.mass_scaling = 1e+300 s is longer than run.end_time",
                  "expected a step shorter than the run"});
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
