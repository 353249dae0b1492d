// `brittle run` and the other commands as a user drives them: --dry-run, words in any case,
// the run directory that repeats itself, progress and run.log, frames on the requested times,
// every command's --help and --out, a run that stops when the crack cuts through.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkFieldData.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "cli_helpers.hpp"
#include "output.hpp"

namespace fs = std::filesystem;
using namespace brittle_test;

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
