// Checkpoint, resume and the graceful stop (issue 12; docs/checkpoint.md): a resumed run is
// bitwise the uninterrupted one, SIGINT/SIGTERM leave readable output and a checkpoint that
// resumes, a kill while a checkpoint is written leaves the previous one, and a checkpoint of
// another scene, version or a damaged one is refused with one line and exit 2.
#include <gtest/gtest.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "checkpoint.hpp"
#include "cli_helpers.hpp"
#include "output.hpp"

using namespace brittle_test;

namespace {

const std::string kScenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";

/// `brittle run` arguments: cm.ini, the overlays, --out, the --set overrides.
std::vector<std::string> run_args(const std::vector<std::string>& overlays, const fs::path& out,
                                  const std::vector<std::string>& sets) {
  std::vector<std::string> a{"run", kScenes + "cm.ini"};
  for (const auto& o : overlays) a.push_back(kScenes + o);
  a.insert(a.end(), {"--out", out.string()});
  for (const auto& s : sets) a.insert(a.end(), {"--set", s});
  return a;
}

nlohmann::json summary(const fs::path& dir) { return nlohmann::json::parse(read_text(dir / "summary.json")); }

/// summary.json without what measures the machine (wall times, rates, threads) or names the
/// command lines that made it.
nlohmann::json physics_of(nlohmann::json j) {
  for (const char* key : {"wall_seconds", "tet_updates_per_second", "phases", "threads",
                          "scene_sources", "checkpoint", "checkpoint_time", "checkpoints_written",
                          "checkpoint_bytes", "checkpoint_seconds", "decomposition"})
    j.erase(key);
  j.erase("scene");  // the command's keys (directory, threads), as scene_sources
  return j;
}

/// Every file of `a` (recursively) is in `b` with the same bytes; summary.json by its physics.
void expect_same_outputs(const fs::path& a, const fs::path& b) {
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(a)) {
    if (!entry.is_regular_file()) continue;
    const fs::path rel = fs::relative(entry.path(), a);
    const std::string name = rel.filename().string();
    // (scene.ini and run.log say how each was run: another directory, thread count, a resume;
    // checkpoints hold wall times)
    if (rel.extension() == ".bin" || name.starts_with("stdout") || name.starts_with("stderr") ||
        name == "scene.ini" || name == "run.log")
      continue;
    ++files;
    ASSERT_TRUE(fs::exists(b / rel)) << rel;
    if (name == "summary.json")
      EXPECT_EQ(physics_of(summary(a)), physics_of(summary(b)));
    else
      EXPECT_TRUE(read_text(entry.path()) == read_text(b / rel)) << rel << " differs";
  }
  EXPECT_GT(files, 10);
  int in_b = 0;
  for (const auto& entry : fs::recursive_directory_iterator(b)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && entry.path().extension() != ".bin" && name != "scene.ini" &&
        name != "run.log")
      ++in_b;
  }
  EXPECT_EQ(in_b, files) << "the resumed directory has other files";
}

/// Reads a .pvd and every VTU it lists; fails the test on any that does not read.
std::size_t expect_readable_series(const fs::path& pvd) {
  const std::vector<brittle::PvdEntry> entries = brittle::read_pvd(pvd.string());
  for (const auto& e : entries) {
    auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    reader->SetFileName(e.file.c_str());
    reader->Update();
    EXPECT_GT(reader->GetOutput()->GetNumberOfCells(), 0) << e.file;
  }
  return entries.size();
}

/// Waits until `file` has at least `lines` lines (the run is stepping); false after 120 s.
bool wait_for_lines(const fs::path& file, std::size_t lines) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < until) {
    const std::string text = read_text(file);
    if (static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) >= lines) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace

// The paper's hardest setting on CM: branching, damage and rate-dependent links, stopped at
// 3 us (a checkpoint every 1 us) and resumed to 6 us on another thread count.
TEST(Checkpoint, ResumedRunIsBitwiseTheUninterruptedRun) {
  TempDir dir;
  const std::vector<std::string> overlays{"branching.ini", "damage.ini", "rate-dependent.ini"};
  // PNGs rendered during the run too (one before the checkpoint, one after) and a sensor.
  const std::string render = "render.times=1e-6, 5e-6";
  const std::string sensor = "sensor.top.position=16e-3, 8e-3, 0.5e-3";
  const std::string normal = "sensor.top.direction=0, 1, 0";
  Result r = run_brittle(dir, run_args(overlays, dir / "full",
                                       {"run.end_time=6e-6", "run.threads=2", render, sensor,
                                        normal}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_brittle(dir, run_args(overlays, dir / "part",
                                {"run.end_time=3e-6", "run.threads=1",
                                 "output.checkpoint_interval=1e-6", render, sensor, normal}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The checkpoint holds every mechanism: split nodes, live links, damage.
  const nlohmann::json before = summary(dir / "part");
  EXPECT_GT(before.at("splits").get<long>(), 2);
  EXPECT_GT(before.at("live_links").get<long>(), 2);
  EXPECT_GT(before.at("damage_dissipated").get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(before.at("checkpoint_time").get<double>(), before.at("time").get<double>());

  r = run_brittle(dir, {"run", "--resume", (dir / "part").string(), "--set", "run.end_time=6e-6",
                        "--set", "run.threads=2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "part/render/damage_005.000us.png"));
  EXPECT_TRUE(fs::exists(dir / "part/sensors.csv"));
  expect_same_outputs(dir / "full", dir / "part");
}

// The facet criteria's open faces are state (the nonlocal balls and the energy balls are
// caches, rebuilt): a branching run on faces, stopped at 3 us and resumed to 6 us on another
// thread count, is the uninterrupted run; with the coupled criterion too.
TEST(Checkpoint, FacetCriterionRunResumesBitwise) {
  for (const std::vector<std::string>& keys :
       {std::vector<std::string>{"fracture.criterion=facet"},
        {"fracture.criterion=coupled-facet", "fracture.length=1e-3"}}) {
    SCOPED_TRACE(keys[0]);
    TempDir dir;
    const std::vector<std::string> overlays{"branching.ini"};
    const auto with = [&](std::vector<std::string> sets) {
      sets.insert(sets.end(), keys.begin(), keys.end());
      return sets;
    };
    Result r = run_brittle(
        dir, run_args(overlays, dir / "full", with({"run.end_time=6e-6", "run.threads=2"})));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_brittle(dir, run_args(overlays, dir / "part",
                                  with({"run.end_time=3e-6", "run.threads=1",
                                        "output.checkpoint_interval=1e-6"})));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const long at_3us = summary(dir / "part").at("splits").get<long>();
    EXPECT_GT(at_3us, 2);
    r = run_brittle(dir, {"run", "--resume", (dir / "part").string(), "--set",
                          "run.end_time=6e-6", "--set", "run.threads=2"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GT(summary(dir / "part").at("splits").get<long>(), at_3us);  // faces opened after it
    expect_same_outputs(dir / "full", dir / "part");
  }
}

// A 2D body (issue 53: triangles in plane stress, cracking on edges): stopped at 30 us and
// resumed to 45 us on another thread count, the uninterrupted run, crack and all.
TEST(Checkpoint, TwoDimensionalRunResumesBitwise) {
  TempDir dir;
  const auto args = [&](const char* out, std::vector<std::string> sets) {
    std::vector<std::string> a{"run", kScenes + "glass-branching.ini",
                               kScenes + "glass-branching-2d.ini", "--out", (dir / out).string()};
    sets.insert(sets.end(), {"mesh.size=4e-3", "mesh.band_size=1.5e-3"});
    for (const auto& s : sets) a.insert(a.end(), {"--set", s});
    return a;
  };
  Result r = run_brittle(dir, args("full", {"run.end_time=45e-6", "run.threads=2"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_brittle(dir, args("part", {"run.end_time=30e-6", "run.threads=1",
                                     "output.checkpoint_interval=10e-6"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const long at_30us = summary(dir / "part").at("splits").get<long>();
  r = run_brittle(dir, {"run", "--resume", (dir / "part").string(), "--set",
                        "run.end_time=45e-6", "--set", "run.threads=2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(summary(dir / "part").at("splits").get<long>(), at_30us + 10);  // cracked after it
  expect_same_outputs(dir / "full", dir / "part");
}

TEST(Checkpoint, StraightRateIndependentRunResumesBitwise) {
  TempDir dir;
  Result r = run_brittle(dir, run_args({}, dir / "full", {"run.end_time=8e-6"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_brittle(dir, run_args({}, dir / "part",
                                {"run.end_time=5e-6", "output.checkpoint_interval=2.5e-6"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_brittle(dir, {"run", "--resume", (dir / "part").string(), "--set", "run.end_time=8e-6"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_same_outputs(dir / "full", dir / "part");
}

// SIGINT: the step finishes, a checkpoint and a last frame are written, the summary says
// "interrupted", exit 130; the run resumes from there.
TEST(Checkpoint, SigintStopsCleanlyAndTheRunResumes) {
  TempDir dir;
  const fs::path out = dir / "run";
  Background run(dir, run_args({"branching.ini"}, out, {"run.end_time=400e-6"}));
  ASSERT_TRUE(wait_for_lines(out / "energies.csv", 20)) << run.err();
  run.signal(SIGINT);
  EXPECT_EQ(run.wait(), 130) << run.err();
  EXPECT_TRUE(contains(run.err(), "brittle run --resume")) << run.err();
  const nlohmann::json s = summary(out);
  EXPECT_EQ(s.at("status"), "interrupted");
  const double stopped = s.at("time").get<double>();
  EXPECT_GT(stopped, 1.75e-6);  // 19 energy rows: 0 to 1.8 us
  EXPECT_LT(stopped, 400e-6);
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(out / "checkpoint.bin.tmp"));
  const std::size_t frames = expect_readable_series(out / "run.pvd");
  ASSERT_GE(frames, 2u);
  EXPECT_DOUBLE_EQ(brittle::read_pvd((out / "run.pvd").string()).back().time, stopped)
      << "the last frame is the state at the stop";

  char end[64];
  std::snprintf(end, sizeof end, "run.end_time=%.17g", stopped + 2.5e-6);
  const Result r = run_brittle(dir, {"run", "--resume", out.string(), "--set", end});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summary(out).at("status"), "completed");
  EXPECT_GE(expect_readable_series(out / "run.pvd"), frames + 1);
}

TEST(Checkpoint, SigtermExitsWith143) {
  TempDir dir;
  const fs::path out = dir / "run";
  Background run(dir, run_args({}, out, {"run.end_time=400e-6", "output.vtu=false"}));
  ASSERT_TRUE(wait_for_lines(out / "energies.csv", 10)) << run.err();
  run.signal(SIGTERM);
  EXPECT_EQ(run.wait(), 143) << run.err();
  EXPECT_EQ(summary(out).at("status"), "interrupted");
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
}

// A SIGKILL half-way through writing the third checkpoint (the test hook of checkpoint.cpp)
// leaves the second one whole: the run resumes from it to the uninterrupted result.
TEST(Checkpoint, KillDuringAWriteLeavesThePreviousCheckpoint) {
  TempDir dir;
  const std::vector<std::string> overlays{"branching.ini", "rate-dependent.ini"};
  const std::vector<std::string> sets{"run.end_time=5e-6", "output.checkpoint_interval=1e-6"};
  Result r = run_brittle(dir, run_args(overlays, dir / "full", sets));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Background killed(dir, run_args(overlays, dir / "part", sets),
                    {"BRITTLE_TEST_KILL_IN_CHECKPOINT=3"});
  EXPECT_EQ(killed.wait(), 128 + SIGKILL);
  ASSERT_TRUE(fs::exists(dir / "part/checkpoint.bin.tmp")) << "the kill came before the write";
  const brittle::CheckpointHeader h =
      brittle::read_checkpoint_header((dir / "part/checkpoint.bin").string());
  EXPECT_NEAR(h.time, 2e-6, 0.1e-6);
  r = run_brittle(dir, {"run", "--resume", (dir / "part").string(), "--set",
                        "output.checkpoint_interval=0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "part/checkpoint.bin.tmp")) << "the half-written one is removed";
  EXPECT_TRUE(read_text(dir / "full/energies.csv") == read_text(dir / "part/energies.csv"));
  EXPECT_TRUE(read_text(dir / "full/frames/frame_0005.vtu") ==
              read_text(dir / "part/frames/frame_0005.vtu"));
}

TEST(Checkpoint, RefusesAnotherSceneVersionOrADamagedFile) {
  TempDir dir;
  const std::string scene = dir.write("s.ini", read_text(kScenes + "cm.ini"));
  const fs::path out = dir / "run";
  Result r = run_brittle(dir, {"run", scene, "--out", out.string(), "--set", "run.end_time=1e-6",
                               "--set", "output.checkpoint_interval=1e-6", "--set",
                               "output.vtu=false"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path ck = out / "checkpoint.bin";
  const std::string good = read_text(ck);
  auto refused = [&](const std::vector<std::string>& sets, const std::vector<std::string>& parts) {
    std::vector<std::string> args{"run", "--resume", out.string()};
    for (const auto& s : sets) args.insert(args.end(), {"--set", s});
    const Result res = run_brittle(dir, args);
    EXPECT_EQ(res.exit_code, 2) << res.err;
    EXPECT_EQ(std::count(res.err.begin(), res.err.end(), '\n'), 1) << res.err;
    for (const auto& p : parts) EXPECT_TRUE(contains(res.err, p)) << p << " not in " << res.err;
  };
  refused({"material.E=3e9"}, {"--set material.E=3e9", "run.end_time"});
  refused({"run.end_time=0.5e-6"}, {"before the checkpoint"});

  // The scene file changed since: its [loading] no longer matches.
  std::string changed = read_text(kScenes + "cm.ini");
  const std::size_t load = changed.find("sigma_over_sigmac = 0.9");
  ASSERT_NE(load, std::string::npos);
  changed.replace(load, 23, "sigma_over_sigmac = 0.8");
  dir.write("s.ini", changed);
  refused({}, {"[loading]", "differ"});
  dir.write("s.ini", read_text(kScenes + "cm.ini"));

  // Another version: the version string patched and the checksum made to match.
  std::string other = good;
  const std::size_t at = other.find(BRITTLE_VERSION);
  ASSERT_NE(at, std::string::npos);
  other[at] = other[at] == '9' ? '8' : '9';
  const std::uint64_t sum = brittle::fnv1a(other.data(), other.size() - 8);
  std::memcpy(other.data() + other.size() - 8, &sum, 8);
  std::ofstream(ck, std::ios::binary | std::ios::trunc) << other;
  refused({}, {"was written by brittle", "this is brittle " BRITTLE_VERSION});

  std::ofstream(ck, std::ios::binary | std::ios::trunc) << good.substr(0, good.size() / 2);
  refused({}, {"checkpoint.bin", "damaged"});
  std::ofstream(ck, std::ios::binary | std::ios::trunc) << "[loading]\n";
  refused({}, {"not a brittle checkpoint"});
  fs::remove(ck);
  refused({}, {"no such file"});

  // And the good one still resumes.
  std::ofstream(ck, std::ios::binary | std::ios::trunc) << good;
  r = run_brittle(dir, {"run", "--resume", out.string(), "--set", "run.end_time=1.2e-6"});
  EXPECT_EQ(r.exit_code, 0) << r.err;

  // A fresh run into the directory removes the earlier run's checkpoint: it is not its state.
  r = run_brittle(dir, {"run", scene, "--out", out.string(), "--set", "run.end_time=0.5e-6",
                        "--set", "output.vtu=false"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(ck));
}

// A stopped sweep passes the request on to its runs (each stops with a checkpoint), starts no
// more, writes sweep.csv with every load and exits 130.
TEST(Checkpoint, SigintStopsASweepAndItsRuns) {
  TempDir dir;
  const fs::path out = dir / "sweep";
  Background sweep(dir, {"sweep", kScenes + "cm.ini", "--loads", "0.6,0.7,0.8", "--jobs", "2",
                         "--set", "run.end_time=400e-6", "--out", out.string()});
  ASSERT_TRUE(wait_for_lines(out / "load_0.600/energies.csv", 10)) << sweep.err();
  ASSERT_TRUE(wait_for_lines(out / "load_0.700/energies.csv", 10)) << sweep.err();
  sweep.signal(SIGINT);
  EXPECT_EQ(sweep.wait(), 130) << sweep.err();
  const std::string csv = read_text(out / "sweep.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4) << csv;
  EXPECT_TRUE(contains(csv, "0.8,nan")) << csv;
  EXPECT_TRUE(contains(csv, "not started")) << csv;
  for (const char* load : {"load_0.600", "load_0.700"}) {
    EXPECT_EQ(summary(out / load).at("status"), "interrupted") << load;
    EXPECT_TRUE(fs::exists(out / load / "checkpoint.bin")) << load;
  }
  EXPECT_FALSE(fs::exists(out / "load_0.800"));
}

// ---- Decomposed runs (mpiexec; suite Mpi: release only, as every test that starts mpiexec) ----

namespace {

/// mpiexec -np `ranks`, oversubscribed (the bits, not the speed), as root in CI.
std::vector<std::string> mpiexec(int ranks) {
  return {BRITTLE_MPIEXEC, "--oversubscribe", "-np", std::to_string(ranks)};
}
const std::vector<std::string> kMpiEnv{"OMPI_ALLOW_RUN_AS_ROOT=1",
                                       "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
                                       "OMPI_MCA_mpi_yield_when_idle=1"};

/// Runs brittle under mpiexec with `ranks` ranks to the end; its exit code.
int run_mpi(const TempDir& dir, int ranks, const std::vector<std::string>& args,
            const std::vector<std::string>& env = {}, std::string* err = nullptr) {
  std::vector<std::string> e = kMpiEnv;
  e.insert(e.end(), env.begin(), env.end());
  Background run(dir, args, e, mpiexec(ranks));
  const int code = run.wait();
  if (err) *err = run.err();
  return code;
}

/// The lines of `text` that brittle wrote (mpiexec adds its own notes).
int brittle_lines(const std::string& text) {
  std::istringstream lines(text);
  int n = 0;
  for (std::string line; std::getline(lines, line);) n += line.starts_with("brittle");
  return n;
}

}  // namespace

/// What a resume on another rank count must give (docs/checkpoint.md): energies.csv,
/// events.csv, crack_tip.csv and every frame file from frame `first` on are those of the
/// uninterrupted run `a` at the new count, byte for byte, and no other frame file from `first`
/// on is left (the stopped run's pieces of the other count are gone).
void expect_same_from(const fs::path& a, const fs::path& b, int first) {
  for (const char* name : {"energies.csv", "events.csv", "crack_tip.csv"})
    EXPECT_TRUE(read_text(a / name) == read_text(b / name)) << name << " differs";
  auto index = [](const std::string& name) { return std::stoi(name.substr(6, 4)); };
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(a / "frames")) {
    const std::string name = entry.path().filename().string();
    if (index(name) < first) continue;
    ++frames;
    ASSERT_TRUE(fs::exists(b / "frames" / name)) << name;
    EXPECT_TRUE(read_text(entry.path()) == read_text(b / "frames" / name)) << name << " differs";
  }
  EXPECT_GT(frames, 3);
  for (const auto& entry : fs::directory_iterator(b / "frames")) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(index(name) < first || fs::exists(a / "frames" / name)) << name << " left over";
  }
}

// Issue 27's criterion: a 2-rank branching + damage + RD run checkpointed every 5 us, killed
// half-way through its third set (15 us of 20), keeps the 10 us set. Resumed on 2 ranks it
// gives every file of the uninterrupted 2-rank run; resumed serially and on 3 ranks (the state
// re-cut, docs/checkpoint.md) it gives those runs' energies, events and frames.
TEST(Mpi, DecomposedRunKilledInACheckpointResumesBitwise) {
  TempDir dir;
  const std::vector<std::string> overlays{"branching.ini", "damage.ini", "rate-dependent.ini"};
  const std::vector<std::string> sets{"run.end_time=20e-6", "run.threads=1",
                                      "output.frame_interval=2.5e-6",
                                      "output.checkpoint_interval=5e-6"};
  std::string err;
  ASSERT_EQ(run_mpi(dir, 2, run_args(overlays, dir / "full", sets), {}, &err), 0) << err;
  ASSERT_EQ(run_mpi(dir, 3, run_args(overlays, dir / "full3", sets), {}, &err), 0) << err;
  ASSERT_EQ(run_brittle(dir, run_args(overlays, dir / "full1", sets)).exit_code, 0);
  EXPECT_NE(run_mpi(dir, 2, run_args(overlays, dir / "part", sets),
                    {"BRITTLE_TEST_KILL_IN_CHECKPOINT=3"}, &err), 0);
  const fs::path part = dir / "part";
  ASSERT_FALSE(fs::exists(part / "summary.json")) << "the run was killed: " << err;
  const brittle::CheckpointHeader h = brittle::read_checkpoint_header((part / "checkpoint.bin").string());
  EXPECT_EQ(h.pieces, 2u);
  EXPECT_EQ(h.generation, 2u);
  EXPECT_NEAR(h.time, 10e-6, 0.1e-6);
  for (int r = 0; r < 2; ++r)
    EXPECT_TRUE(fs::exists(brittle::checkpoint_piece_path(part.string(), 2, r))) << r;
  EXPECT_TRUE(fs::exists(part / "frames/frame_0006_r1.vtu")) << "a frame after the checkpoint";
  for (const char* copy : {"serial", "three", "damaged"})
    fs::copy(part, dir / copy, fs::copy_options::recursive);

  // A damaged piece: refused with one line naming it, on any count, and nothing written.
  const fs::path damaged = dir / "damaged";
  const std::string piece = brittle::checkpoint_piece_path(damaged.string(), 2, 1);
  fs::resize_file(piece, fs::file_size(piece) / 2);
  const std::string energies = read_text(damaged / "energies.csv");
  ASSERT_NE(run_mpi(dir, 3, {"run", "--resume", damaged.string()}, {}, &err), 0);
  EXPECT_TRUE(contains(err, piece)) << err;
  EXPECT_EQ(brittle_lines(err), 1) << err;
  const Result refused = run_brittle(dir, {"run", "--resume", damaged.string()});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_TRUE(contains(refused.err, piece)) << refused.err;
  EXPECT_TRUE(read_text(damaged / "energies.csv") == energies) << "a refused resume wrote";

  ASSERT_EQ(run_mpi(dir, 2, {"run", "--resume", part.string()}, {}, &err), 0) << err;
  expect_same_outputs(dir / "full", part);
  int pieces = 0;  // the run's last set, and nothing half-written
  for (const auto& entry : fs::directory_iterator(part)) {
    const std::string name = entry.path().filename().string();
    EXPECT_FALSE(name.ends_with(".tmp")) << name;
    pieces += name.starts_with("checkpoint_r");
  }
  EXPECT_EQ(pieces, 2);

  const Result serial = run_brittle(dir, {"run", "--resume", (dir / "serial").string()});
  ASSERT_EQ(serial.exit_code, 0) << serial.err;
  expect_same_from(dir / "full1", dir / "serial", 5);  // frame 5 is at 12.5 us
  ASSERT_EQ(run_mpi(dir, 3, {"run", "--resume", (dir / "three").string()}, {}, &err), 0) << err;
  expect_same_from(dir / "full3", dir / "three", 5);

  // And back: a serial run killed the same way, resumed on 2 ranks.
  const fs::path back = dir / "back";
  Background killed(dir, run_args(overlays, back, sets), {"BRITTLE_TEST_KILL_IN_CHECKPOINT=3"});
  EXPECT_EQ(killed.wait(), 128 + SIGKILL);
  EXPECT_EQ(brittle::read_checkpoint_header((back / "checkpoint.bin").string()).pieces, 0u);
  ASSERT_EQ(run_mpi(dir, 2, {"run", "--resume", back.string()}, {}, &err), 0) << err;
  expect_same_from(dir / "full", back, 5);
}

// The facet criterion decomposed (issue 52, item 4): a 2-rank run checkpointed at 3 us resumes
// on 1, 2 and 3 ranks to 6 us with the serial run's energies, events and tips (the open faces
// and their tractions travel per cell, each piece giving its owned cells).
TEST(Mpi, DecomposedFacetRunResumesOnAnyRankCount) {
  TempDir dir;
  const std::vector<std::string> overlays{"branching.ini"};
  const std::vector<std::string> keys{"fracture.criterion=facet", "run.threads=1"};
  const auto with = [&](std::vector<std::string> sets) {
    sets.insert(sets.end(), keys.begin(), keys.end());
    return sets;
  };
  Result r = run_brittle(dir, run_args(overlays, dir / "full", with({"run.end_time=6e-6"})));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string err;
  ASSERT_EQ(run_mpi(dir, 2, run_args(overlays, dir / "part",
                                     with({"run.end_time=3e-6", "output.checkpoint_interval=1e-6"})),
                    {}, &err),
            0)
      << err;
  EXPECT_GT(summary(dir / "part").at("splits").get<long>(), 2);
  for (int ranks : {1, 2, 3}) {
    SCOPED_TRACE(ranks);
    const fs::path copy = dir / ("resume" + std::to_string(ranks));
    fs::copy(dir / "part", copy, fs::copy_options::recursive);
    const std::vector<std::string> resume{"run", "--resume", copy.string(), "--set",
                                          "run.end_time=6e-6"};
    if (ranks == 1) {
      r = run_brittle(dir, resume);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    } else {
      ASSERT_EQ(run_mpi(dir, ranks, resume, {}, &err), 0) << err;
    }
    EXPECT_GT(summary(copy).at("splits").get<long>(), summary(dir / "part").at("splits").get<long>());
    for (const char* name : {"energies.csv", "events.csv", "crack_tip.csv", "pattern.json"})
      EXPECT_TRUE(read_text(dir / "full" / name) == read_text(copy / name)) << name << " differs";
  }
}

// Ctrl-C under mpirun (it passes the stop on to the ranks): every rank finishes the same step,
// the set is written, the summary says interrupted, and the run resumes on as many ranks.
TEST(Mpi, StopUnderMpirunWritesACheckpointThatResumes) {
  TempDir dir;
  const fs::path out = dir / "run";
  std::vector<std::string> e = kMpiEnv;
  Background run(dir, run_args({"branching.ini"}, out, {"run.end_time=400e-6", "run.threads=1"}),
                 e, mpiexec(2));
  ASSERT_TRUE(wait_for_lines(out / "energies.csv", 20)) << run.err();
  run.signal(SIGINT);
  EXPECT_NE(run.wait(), 0);
  EXPECT_TRUE(contains(run.err(), "mpirun -np 2 brittle run --resume")) << run.err();
  const nlohmann::json s = summary(out);
  EXPECT_EQ(s.at("status"), "interrupted");
  const double stopped = s.at("time").get<double>();
  EXPECT_LT(stopped, 400e-6);
  EXPECT_EQ(brittle::read_checkpoint_header((out / "checkpoint.bin").string()).pieces, 2u);
  char end[64];
  std::snprintf(end, sizeof end, "run.end_time=%.17g", stopped + 2.5e-6);
  std::string err;
  ASSERT_EQ(run_mpi(dir, 2, {"run", "--resume", out.string(), "--set", end}, {}, &err), 0) << err;
  EXPECT_EQ(summary(out).at("status"), "completed");
}
