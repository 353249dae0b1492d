// What the tests of decomposed runs share (test_parallel.cpp, test_scene_keys_mpi.cpp): mpiexec
// of the brittle executable, and a run's files and last frame compared by serial id.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <vtkCellData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_helpers.hpp"
#include "output.hpp"

namespace brittle::mpi_test {

namespace fs = std::filesystem;
using brittle_test::contains;
using brittle_test::quote;
using brittle_test::read_text;

/// mpiexec with the environment Open MPI needs to run as root in CI, oversubscribed.
/// Waiting ranks yield the core (more ranks than cores: a spinning rank would starve the one it
/// waits for).
inline std::string mpiexec(int ranks) {
  return std::string(
             "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
             "OMPI_MCA_mpi_yield_when_idle=1 ") +
         quote(BRITTLE_MPIEXEC) + " --oversubscribe -np " + std::to_string(ranks) + " " +
         quote(BRITTLE_EXE);
}

inline int shell(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > " + quote(log.string()) + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The summary without what depends on the machine's speed.
/// (and the output directory it names among the scene's keys).
inline nlohmann::json without_timings(nlohmann::json j) {
  for (const char* key : {"wall_seconds", "tet_updates_per_second", "phases", "decomposition"})
    j.erase(key);
  if (j.contains("scene")) j["scene"].erase("output.directory");
  return j;
}

/// A frame's arrays by serial id: the serial frame_NNNN.vtu, or the pieces of a decomposed
/// run put together by their global_node / global_cell arrays.
struct Frame {
  std::map<std::string, std::vector<double>> point, cell;  ///< name -> values by serial id
  std::vector<double> points;                              ///< 3 per node
  std::vector<vtkIdType> cells;  ///< 4 serial node ids per cell (triangles: 3, then -1)
};

inline vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& path) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

inline void add_piece(Frame& f, vtkUnstructuredGrid& g, bool pieces) {
  auto id = [&](vtkDataArray* ids, vtkIdType i) {
    return pieces ? static_cast<vtkIdType>(ids->GetTuple1(i)) : i;
  };
  vtkDataArray* nodes = g.GetPointData()->GetArray("global_node");
  vtkDataArray* cells = g.GetCellData()->GetArray("global_cell");
  ASSERT_EQ(pieces, nodes != nullptr);
  ASSERT_EQ(pieces, cells != nullptr);
  auto fill = [&](vtkDataSetAttributes* data, vtkDataArray* ids,
                  std::map<std::string, std::vector<double>>& out) {
    for (int a = 0; a < data->GetNumberOfArrays(); ++a) {
      vtkDataArray* array = data->GetArray(a);
      const std::string name = array->GetName();
      if (name == "global_node" || name == "global_cell") continue;
      const int n = array->GetNumberOfComponents();
      std::vector<double>& values = out[name];
      for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i) {
        const auto at = static_cast<std::size_t>(id(ids, i)) * n;
        if (values.size() < at + n) values.resize(at + n, NAN);
        for (int k = 0; k < n; ++k) values[at + k] = array->GetComponent(i, k);
      }
    }
  };
  fill(g.GetPointData(), nodes, f.point);
  fill(g.GetCellData(), cells, f.cell);
  for (vtkIdType p = 0; p < g.GetNumberOfPoints(); ++p) {
    const auto at = static_cast<std::size_t>(3 * id(nodes, p));
    if (f.points.size() < at + 3) f.points.resize(at + 3, NAN);
    g.GetPoint(p, &f.points[at]);
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c) {
    const auto at = static_cast<std::size_t>(4 * id(cells, c));
    if (f.cells.size() < at + 4) f.cells.resize(at + 4, -1);
    g.GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)  // (a triangle's slot 3 stays -1)
      f.cells[at + k] = id(nodes, ids->GetId(k));
  }
}

/// The last frame of a run directory (pieces if `ranks` > 0).
inline Frame last_frame(const fs::path& run, int ranks) {
  const std::vector<PvdEntry> series = read_pvd((run / "run.pvd").string());
  EXPECT_FALSE(series.empty());
  Frame f;
  if (series.empty()) return f;
  const fs::path file = series.back().file;
  if (ranks == 0) {
    add_piece(f, *read_vtu(file), false);
    return f;
  }
  EXPECT_EQ(file.extension(), ".pvtu");
  const std::string text = read_text(file);
  for (int r = 0; r < ranks; ++r) {  // the summary names every piece, which holds its arrays
    const std::string piece = file.stem().string() + "_r" + std::to_string(r) + ".vtu";
    EXPECT_TRUE(contains(text, "<Piece Source=\"" + piece + "\"/>")) << text;
    add_piece(f, *read_vtu(file.parent_path() / piece), true);
  }
  return f;
}

}  // namespace brittle::mpi_test
