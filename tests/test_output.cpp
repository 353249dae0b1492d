// VTU frames + PVD collection, energies.csv and summary.json written by a run, read back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iterator>
#include <fstream>
#include <limits>
#include <new>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "output.hpp"
#include "error.hpp"
#include "fixtures.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;

namespace brittle {
namespace {

/// Keeps a copy of the grid's arrays at every frame, to compare with what was written.
struct Snapshots : Observer {
  struct Frame {
    double time;
    std::vector<double> u, v, sigma1, stress;
  };
  std::vector<Frame> frames;
  void on_frame(const Simulation& sim) override {
    const Grid& g = sim.grid();
    frames.push_back({sim.time(),
                      {g.u(), g.u() + 3 * g.num_points()},
                      {g.v(), g.v() + 3 * g.num_points()},
                      {g.sigma1_over_sigmac(), g.sigma1_over_sigmac() + g.num_cells()},
                      {g.stress(), g.stress() + 6 * g.num_cells()}});
  }
};

void expect_array(vtkDataArray* a, const std::vector<double>& expected, const char* name) {
  ASSERT_NE(a, nullptr) << name;
  ASSERT_EQ(a->GetNumberOfValues(), static_cast<vtkIdType>(expected.size())) << name;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
    ASSERT_EQ(a->GetComponent(i / a->GetNumberOfComponents(), i % a->GetNumberOfComponents()),
              expected[i])
        << name << " value " << i;
}

TEST(Output, TimeSeriesReadsBackAsWritten) {
  const fs::path dir = fs::temp_directory_path() / "brittle_test_output";
  fs::remove_all(dir);
  Scene s;
  s.loading.sigma_over_sigmac = 0.9;
  s.run.end_time = 1e-6;
  s.output.directory = dir.string();
  s.output.frame_times = {0.0, 0.5e-6, 1e-6};
  s.mesh.size = 1e-3;
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  OutputWriters writers(sim);
  Snapshots snapshots;
  auto observers = writers.observers();
  observers.push_back(&snapshots);
  sim.run(observers);

  const auto entries = read_pvd((dir / "run.pvd").string());
  ASSERT_EQ(entries.size(), 3u);
  ASSERT_EQ(snapshots.frames.size(), 3u);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const auto& f = snapshots.frames[k];
    EXPECT_EQ(entries[k].time, f.time);
    EXPECT_NEAR(f.time, s.output.frame_times[k], sim.dt());
    auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    reader->SetFileName(entries[k].file.c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    ASSERT_EQ(g->GetNumberOfPoints(), sim.grid().num_points());
    ASSERT_EQ(g->GetNumberOfCells(), sim.grid().num_cells());
    expect_array(g->GetPointData()->GetArray(field::displacement), f.u, field::displacement);
    expect_array(g->GetPointData()->GetArray(field::velocity), f.v, field::velocity);
    expect_array(g->GetCellData()->GetArray(field::sigma1_over_sigmac), f.sigma1,
                 field::sigma1_over_sigmac);
    expect_array(g->GetCellData()->GetArray(field::stress), f.stress, field::stress);
    ASSERT_NE(g->GetCellData()->GetArray(field::damage), nullptr);
    vtkDataArray* time = g->GetFieldData()->GetArray(field::time);
    ASSERT_NE(time, nullptr);
    EXPECT_EQ(time->GetTuple1(0), f.time);
  }
  // At t = 0 the plate holds the uniform pre-stress: sigma1 / sigma_c = 0.9 away from the notch.
  int near_load = 0;
  for (double s1 : snapshots.frames[0].sigma1) near_load += std::abs(s1 - 0.9) < 1e-6;
  EXPECT_GT(near_load, static_cast<int>(0.8 * snapshots.frames[0].sigma1.size()));

  std::ifstream csv(dir / "energies.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "time,kinetic,elastic,viscous_dissipated,cohesive_stored,cohesive_dissipated,"
            "damage_dissipated,external_work,total,relative_imbalance");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_GE(rows, 10);
  std::ifstream summary(dir / "summary.json");
  const std::string json((std::istreambuf_iterator<char>(summary)), {});
  EXPECT_NE(json.find("\"status\": \"completed\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"tet_updates_per_second\""), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "run.pvd.tmp"));
}

// ParaView's Warp By Vector (docs/output.md): the stored points are the deformed positions,
// reference_position + displacement gives them back (to 2 ulp: u = x - X is rounded), and no
// array is the active vector, so the filter does not add `displacement` a second time by
// default. Checked on a frame read back from disk after a straight crack has opened.
TEST(Output, PointsAreReferencePlusDisplacement) {
  const fs::path dir = fs::temp_directory_path() / "brittle_test_warp";
  fs::remove_all(dir);
  Scene s = testing::plate_scene(0.9, 8e-6, FractureParams::Mode::straight);
  s.mesh.size = 1e-3;
  s.output.directory = dir.string();
  s.output.vtu = true;
  s.output.frame_times = {8e-6};
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation sim(s, *mesh);
  OutputWriters writers(sim);
  EXPECT_GT(sim.run(writers.observers()).splits, 0);
  const auto entries = read_pvd((dir / "run.pvd").string());
  ASSERT_EQ(entries.size(), 1u);
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(entries[0].file.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  EXPECT_EQ(g->GetPointData()->GetVectors(), nullptr) << "no active vector";
  vtkDataArray* X = g->GetPointData()->GetArray(field::reference_position);
  vtkDataArray* u = g->GetPointData()->GetArray(field::displacement);
  ASSERT_TRUE(X && u);
  double largest = 0;
  for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p) {
    double x[3];
    g->GetPoint(p, x);
    for (int k = 0; k < 3; ++k) {
      largest = std::max(largest, std::abs(u->GetComponent(p, k)));
      ASSERT_LE(std::abs(X->GetComponent(p, k) + u->GetComponent(p, k) - x[k]),
                2 * std::numeric_limits<double>::epsilon() * std::abs(x[k]))
          << "node " << p << " component " << k;
    }
  }
  EXPECT_GT(largest, 1e-6) << "the plate has deformed (and the crack opened)";
  fs::remove_all(dir);
}

TEST(Output, ReadPvdRejectsGarbage) {
  const fs::path file = fs::temp_directory_path() / "brittle_garbage.pvd";
  std::ofstream(file) << "not xml at all";
  EXPECT_THROW(read_pvd(file.string()), Error);
  EXPECT_THROW(read_pvd("/nonexistent/run.pvd"), Error);
}

// A run that blew up has NaN and infinite numbers; its summary is still valid JSON, with null
// for them, and quotes and backslashes in the status and warnings survive.
TEST(Output, SummaryWithNonFiniteNumbersIsValidJson) {
  Scene s;
  s.loading.sigma_over_sigmac = 0.5;
  s.geometry.H = 2e-3;
  s.sources = {"a.ini", "--set run.cfl=0.4"};
  auto mesh = generate_box_mesh(4e-3, 2e-3, 1e-3, 1e-3);
  Simulation sim(s, *mesh);
  RunSummary r;
  r.status = "failed: element \"7\" at C:\\path";
  r.crack_speed.speed = std::nan("");
  r.crack_speed.r2 = std::numeric_limits<double>::infinity();
  r.final_energies.elastic = -std::nan("");
  r.max_relative_imbalance = -std::numeric_limits<double>::infinity();
  r.warnings = {"energy budget off by \"12\" % \\ here"};
  r.splits = 3;
  const std::string text = summary_json(sim, r);
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(text)) << text;
  EXPECT_TRUE(j.at("crack_speed").is_null());
  EXPECT_TRUE(j.at("crack_speed_r2").is_null());
  EXPECT_TRUE(j.at("final_elastic").is_null());
  EXPECT_TRUE(j.at("max_relative_imbalance").is_null());
  // The status says which values every run defines were not finite; the crack speed and its
  // fit may be undefined (fewer than 3 samples) and are null without a word.
  EXPECT_EQ(
      j.at("status"),
      r.status + "; non-finite values written as null: final_elastic, max_relative_imbalance");
  EXPECT_EQ(j.at("warnings"), nlohmann::json(r.warnings));
  EXPECT_EQ(j.at("scene_sources"), nlohmann::json(s.sources));
  EXPECT_EQ(j.at("splits"), 3);
  EXPECT_EQ(text.find("nan"), std::string::npos);
  EXPECT_EQ(text.find("inf"), std::string::npos);

  // A completed run without a steady crack speed keeps its status as it is.
  RunSummary done;
  done.status = "completed";
  done.crack_speed.speed = std::nan("");
  const auto k = nlohmann::json::parse(summary_json(sim, done));
  EXPECT_EQ(k.at("status"), "completed");
  EXPECT_TRUE(k.at("crack_speed").is_null());
}

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// The brittle::Error that `f` throws ("" and a test failure if none).
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-brittle exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "nothing thrown";
  return "";
}

// A write that cannot be done throws brittle::Error naming the file and the reason, and
// leaves no temporary file; the file keeps what it held.
TEST(Output, AFailedWriteNamesTheFileAndLeavesNoTemporaryFile) {
  const std::string missing = "/nonexistent_brittle_dir/summary.json";
  const std::string message = error_of([&] { write_file_atomically(missing, "{}\n"); });
  EXPECT_NE(message.find(missing), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;

  testing::SmallTmpfs disk(64 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here: " << disk.reason();
  const fs::path file = disk.path() / "frame.vtu";
  write_file_atomically(file.string(), "complete\n");
  const std::string full =
      error_of([&] { write_file_atomically(file.string(), std::string(200 * 1024, 'x')); });
  EXPECT_EQ(full, "output: cannot write '" + file.string() + "': No space left on device");
  EXPECT_EQ(file_text(file), "complete\n");
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
  EXPECT_EQ(std::distance(fs::directory_iterator(disk.path()), fs::directory_iterator()), 1);
}

// energies.csv grows by rows: on a full disk the append throws naming the file and the
// reason, and the file ends with a whole row (the part of the row that landed is cut).
TEST(Output, ARowFileOnAFullDiskKeepsWholeRows) {
  testing::SmallTmpfs disk(64 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here: " << disk.reason();
  const fs::path file = disk.path() / "energies.csv";
  const std::string row = "0.125," + std::string(1000, '7') + "\n";  // does not divide 64 k
  RowFile csv(file.string(), /*truncate=*/true);
  std::string message;
  int rows = 0;
  for (; rows < 1000 && message.empty(); ++rows) {
    try {
      csv.append(row);
    } catch (const Error& e) {
      message = e.what();
    }
  }
  EXPECT_EQ(message, "output: cannot write '" + file.string() + "': No space left on device");
  EXPECT_GT(rows, 10);
  const std::string text = file_text(file);
  EXPECT_EQ(text.size(), (rows - 1) * row.size());
  EXPECT_EQ(text.size() % row.size(), 0u);
  // closed after its first error: later rows are refused, the file stays as it was
  EXPECT_THROW(csv.append(row), Error);
  EXPECT_EQ(file_text(file).size(), text.size());
}

/// Throws `what` from on_frame at the given frame, or from on_finish.
struct Thrower : Observer {
  int frame = -1;
  bool at_finish = false;
  std::function<void()> raise;
  int frames = 0;
  void on_frame(const Simulation&) override {
    if (frames++ == frame) raise();
  }
  void on_finish(const Simulation&, const RunSummary&) override {
    if (at_finish) raise();
  }
};

std::string summary_status(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  return nlohmann::json::parse(in).at("status");
}

// Whatever stops a run (not only brittle::Error: a std::bad_alloc or a filesystem_error inside
// the step loop), the summary is written with "failed: <that error>", run() throws it as
// brittle::Error, and a later failure (here an observer's on_finish) does not replace it. A
// completed run whose writer fails in on_finish is failed by the first such error, and the
// summary written after it says so.
TEST(Output, TheFirstErrorIsReportedAndTheSummaryStillWritten) {
  const fs::path dir = fs::temp_directory_path() / "brittle_test_first_error";
  Scene s;
  s.loading.sigma_over_sigmac = 0.5;
  s.geometry.H = 2e-3;
  s.run.end_time = 2e-7;
  s.output.frame_times = {0.0, 1e-7};
  s.output.directory = dir.string();
  auto mesh = generate_box_mesh(4e-3, 2e-3, 1e-3, 1e-3);
  for (const bool bad_alloc : {true, false}) {
    fs::remove_all(dir);
    Simulation sim(s, *mesh);
    Thrower during, finish;
    during.frame = 1;
    during.raise = [&] {
      if (bad_alloc) throw std::bad_alloc();
      throw fs::filesystem_error("cannot rename",
                                 std::make_error_code(std::errc::no_space_on_device));
    };
    finish.at_finish = true;
    finish.raise = [] { throw Error("a later failure"); };
    OutputWriters writers(sim);
    std::vector<Observer*> observers = {&finish};  // on_finish before the writers'
    for (Observer* o : writers.observers()) observers.push_back(o);
    observers.push_back(&during);  // on_frame after the writers' (the frame is written)
    const std::string message = error_of([&] { sim.run(observers); });
    const std::string first =
        bad_alloc ? "std::bad_alloc" : "filesystem error: cannot rename: No space left on device";
    EXPECT_EQ(message.rfind(first, 0), 0u) << message;
    EXPECT_EQ(summary_status(dir).rfind("failed: " + first, 0), 0u) << summary_status(dir);
    EXPECT_EQ(read_pvd((dir / "run.pvd").string()).size(), 2u);
  }
  fs::remove_all(dir);
  Simulation sim(s, *mesh);
  Thrower finish;
  finish.at_finish = true;
  finish.raise = [] {
    throw Error("output: cannot write 'crack_tip.csv': No space left on device");
  };
  OutputWriters writers(sim);
  std::vector<Observer*> observers = {&finish};
  for (Observer* o : writers.observers()) observers.push_back(o);
  EXPECT_EQ(error_of([&] { sim.run(observers); }),
            "output: cannot write 'crack_tip.csv': No space left on device");
  EXPECT_EQ(summary_status(dir),
            "failed: output: cannot write 'crack_tip.csv': No space left on device");
}

}  // namespace
}  // namespace brittle
