// MPI session, rank queries and `brittle partition` (docs/parallel.md).
#include "parallel.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <sstream>

#include <boost/program_options.hpp>
#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include "command_line.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "lists.hpp"
#include "output.hpp"
#include "partition.hpp"
#include "plate_mesh.hpp"
#include "scene_options.hpp"

namespace brittle {
namespace {

bool g_mpi = false;  ///< MPI_Init was called by the MpiSession

/// The grid with cell data "rank" (the cell's part) and point data "owner" (the node's).
void write_partition_vtu(const Grid& grid, const Partition& p, const std::string& path) {
  auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
  copy->ShallowCopy(grid.vtk());
  auto rank = vtkSmartPointer<vtkIntArray>::New();
  rank->SetName("rank");
  rank->SetNumberOfTuples(grid.num_cells());
  std::copy(p.cell_part.begin(), p.cell_part.end(), rank->GetPointer(0));
  auto owner = vtkSmartPointer<vtkIntArray>::New();
  owner->SetName("owner");
  owner->SetNumberOfTuples(grid.num_points());
  std::copy(p.node_owner.begin(), p.node_owner.end(), owner->GetPointer(0));
  copy->GetCellData()->Initialize();
  copy->GetPointData()->Initialize();
  copy->GetCellData()->AddArray(rank);
  copy->GetPointData()->AddArray(owner);
  write_vtu_file(*copy, path);
}

}  // namespace

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  g_mpi = true;
}

MpiSession::~MpiSession() {
  if (g_mpi) MPI_Finalize();
  g_mpi = false;
}

int mpi_rank() {
  int rank = 0;
  if (g_mpi) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int mpi_size() {
  int size = 1;
  if (g_mpi) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

void mpi_barrier() {
  if (g_mpi) MPI_Barrier(MPI_COMM_WORLD);
}

void mpi_max(std::vector<int>& values) {
  if (g_mpi && !values.empty())
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_INT, MPI_MAX,
                  MPI_COMM_WORLD);
}

int partition_command(const std::vector<std::string>& args) {
  namespace po = boost::program_options;
  std::vector<std::string> files, sets;
  std::string ranks = "2,4,8", out;
  po::options_description opts("brittle partition options");
  opts.add_options()("help,h", "show this help")(
      "ranks", po::value(&ranks)->default_value("2,4,8"), "rank counts, comma separated")(
      "set", po::value(&sets)->composing(), "override one key: section.key=value (repeatable)")(
      "out", po::value(&out),
      "also write DIR/partition_<ranks>.vtu: cell data rank, point data owner (for ParaView)")(
      "scene", po::value(&files)->composing(), "scene INI files, later ones override earlier");
  auto vm = parse_command_line(args, opts, "scene");
  if (vm.count("help")) {
    std::ostringstream text;
    text << opts;
    std::printf("usage: brittle partition SCENE.ini [MORE.ini ...] [--ranks 2,4,8] [--set k=v ...] "
                "[--out DIR]\n%s", text.str().c_str());
    return 0;
  }
  po::notify(vm);
  BRITTLE_CHECK(!files.empty(), "brittle partition: no scene file given (usage: brittle "
                                "partition SCENE.ini [--ranks 2,4,8])");
  std::vector<int> counts;
  for (const std::string& w : list_words(ranks)) {
    const auto v = parse_number(w);
    BRITTLE_CHECK(v && *v >= 1 && *v <= 4096 && *v == static_cast<int>(*v), "--ranks '", ranks,
                  "': '", w, "' is not a rank count (expected whole numbers 1 to 4096)");
    counts.push_back(static_cast<int>(*v));
  }
  BRITTLE_CHECK(!counts.empty(), "--ranks '", ranks, "': no rank count given");
  const Scene scene = load_scene(files, sets);
  if (!out.empty()) std::filesystem::create_directories(out);
  auto mesh = make_mesh(scene);
  Grid grid(*mesh);
  std::printf("%lld tets, %lld nodes\n", static_cast<long long>(grid.num_cells()),
              static_cast<long long>(grid.num_points()));
  std::printf("%6s %10s %9s %12s %12s %14s %12s %11s %16s\n", "ranks", "imbalance", "cut faces",
              "ghost nodes", "ghost/owned", "redundant tets", "max ghosts", "max neighb.",
              "max bytes/step");
  for (int parts : counts) {
    const Partition p = partition_grid(grid, parts);
    long most_ghosts = 0;
    int most_neighbours = 0;
    double worst_ratio = 0;
    for (const PartStats& s : p.stats) {
      most_ghosts = std::max(most_ghosts, s.ghost_nodes);
      most_neighbours = std::max(most_neighbours, s.neighbours);
      if (s.owned_nodes > 0) worst_ratio = std::max(worst_ratio, double(s.ghost_nodes) / s.owned_nodes);
    }
    // Every step a rank receives the positions and velocities of its ghost nodes: 6 doubles.
    std::printf("%6d %10.3f %9ld %11.2f%% %11.2f%% %13.2f%% %12ld %11d %16ld\n", parts,
                p.imbalance(), p.cut_faces, 100 * p.ghost_fraction(), 100 * worst_ratio,
                100 * p.redundant_fraction(), most_ghosts, most_neighbours, 48 * most_ghosts);
    if (!out.empty()) write_partition_vtu(grid, p, out + "/partition_" + std::to_string(parts) + ".vtu");
  }
  if (!out.empty()) std::printf("wrote %s/partition_*.vtu\n", out.c_str());
  return 0;
}

}  // namespace brittle
