// MPI session, rank queries and `brittle partition` (docs/parallel.md).
#include "parallel.hpp"

#include <mpi.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>

#include "boundary.hpp"
#include "checkpoint.hpp"
#include "command_line.hpp"
#include "crack_pattern.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "halo.hpp"
#include "lists.hpp"
#include "output.hpp"
#include "partition.hpp"
#include "plate_mesh.hpp"
#include "render_commands.hpp"
#include "run_lock.hpp"
#include "scene_options.hpp"
#include "sensors.hpp"

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

int g_decomposed_rank = -1;  ///< this process's rank in a decomposed run

/// Throws on every rank the error of the lowest rank that has one (brittle::first_error).
void agree(const std::string& mine) {
  const std::string first = first_error(mine);
  if (!first.empty()) throw Error(first);
}

/// Runs `f` on this rank and agrees on its outcome over the ranks (agree).
template <class F>
void on_every_rank(F&& f) {
  std::string error;
  try {
    f();
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "unknown error";
  }
  agree(error);
}

/// Whether a point array is a physical group's node mask (plate_mesh.cpp, boundary.hpp).
bool is_group(const char* name) { return name && std::string(name).starts_with(group_array_name("")); }

/// Rank 0's physical-group node masks ("group:NAME" point arrays of a .msh mesh) on every
/// rank's copy of the mesh, broadcast.
void share_groups(vtkUnstructuredGrid& mesh) {
  const vtkIdType n = mesh.GetNumberOfPoints();
  std::vector<std::string> names;
  if (mpi_rank() == 0)
    for (int i = 0; i < mesh.GetPointData()->GetNumberOfArrays(); ++i)
      if (is_group(mesh.GetPointData()->GetArrayName(i)))
        names.emplace_back(mesh.GetPointData()->GetArrayName(i));
  long count = static_cast<long>(names.size());
  MPI_Bcast(&count, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  names.resize(count);
  std::vector<unsigned char> mask(n);
  for (std::string& name : names) {
    long length = static_cast<long>(name.size());
    MPI_Bcast(&length, 1, MPI_LONG, 0, MPI_COMM_WORLD);
    name.resize(length);
    MPI_Bcast(name.data(), static_cast<int>(length), MPI_CHAR, 0, MPI_COMM_WORLD);
    if (mpi_rank() == 0) {
      vtkDataArray* a = mesh.GetPointData()->GetArray(name.c_str());
      for (vtkIdType p = 0; p < n; ++p) mask[p] = a->GetTuple1(p) != 0;
    }
    MPI_Bcast(mask.data(), static_cast<int>(n), MPI_UNSIGNED_CHAR, 0, MPI_COMM_WORLD);
    if (mpi_rank() == 0) continue;
    auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
    a->SetName(name.c_str());
    a->SetNumberOfTuples(n);
    std::copy(mask.begin(), mask.end(), a->GetPointer(0));
    mesh.GetPointData()->AddArray(a);
  }
}

/// The whole mesh's physical-group masks on a part's nodes (regions by group select the same
/// nodes as in the serial run).
void add_groups(vtkUnstructuredGrid& whole, LocalPart& part) {
  for (int i = 0; i < whole.GetPointData()->GetNumberOfArrays(); ++i) {
    if (!is_group(whole.GetPointData()->GetArrayName(i))) continue;
    vtkDataArray* from = whole.GetPointData()->GetArray(i);
    auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
    a->SetName(from->GetName());
    a->SetNumberOfTuples(static_cast<vtkIdType>(part.global_node.size()));
    for (std::size_t k = 0; k < part.global_node.size(); ++k)
      a->SetValue(static_cast<vtkIdType>(k), from->GetTuple1(part.global_node[k]) != 0);
    part.mesh->GetPointData()->AddArray(a);
  }
}

/// Rank 0's mesh on every rank: points, tets and physical groups, broadcast.
/// The scene's keys that shape the mesh: a piece of a partitioned mesh records them, and a run
/// reads only pieces made for its own.
std::string mesh_signature(const Scene& scene) {
  std::string s;
  for (const auto& [name, value] : scene_entries(scene))
    if ((name.starts_with("geometry.") || name.starts_with("mesh.") ||
         name.starts_with("notch.")) &&
        name != "mesh.parts" && name != "mesh.max_elements")
      s += name + " = " + value + "\n";
  return s;
}

std::string part_path(const std::string& directory, int rank) {
  return directory + "/part_" + std::to_string(rank) + ".vtu";
}

constexpr const char* kPartIds = "brittle_part";  // field data: whole nodes, cells, parts, rank
constexpr const char* kPartSignature = "brittle_part_mesh";
constexpr const char* kHolders = "brittle_holders";  // cell data, the most holders, -1 padded
constexpr const char* kReach = "brittle_part_reach";  // field data: layers, distance

template <class Array, class T>
void add_values(vtkFieldData* data, const char* name, const std::vector<T>& values,
                int components = 1) {
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / components));
  for (std::size_t i = 0; i < values.size(); ++i) a->SetValue(static_cast<vtkIdType>(i), values[i]);
  data->AddArray(a);
}

/// Writes rank `rank`'s part (extract_part, with its groups) as one piece of a partitioned
/// mesh: its mesh and, as arrays, what its Halo needs.
void write_part(LocalPart& part, int rank, const std::string& signature, const std::string& path) {
  vtkUnstructuredGrid& mesh = *part.mesh;
  add_values<vtkIdTypeArray>(mesh.GetPointData(), "global_node", part.global_node);
  add_values<vtkIntArray>(mesh.GetPointData(), "owner", part.owner);
  add_values<vtkIdTypeArray>(mesh.GetCellData(), "global_cell", part.global_cell);
  add_values<vtkIntArray>(mesh.GetCellData(), "cell_part", part.cell_part);
  std::int64_t most = 1;  // (a cell's part, its nodes' owners and the reach's parts)
  for (std::size_t i = 0; i + 1 < part.holder_start.size(); ++i)
    most = std::max(most, part.holder_start[i + 1] - part.holder_start[i]);
  std::vector<int> holders;
  for (std::size_t i = 0; i + 1 < part.holder_start.size(); ++i)
    for (std::int64_t k = 0; k < most; ++k) {
      const std::int64_t h = part.holder_start[i] + k;
      holders.push_back(h < part.holder_start[i + 1] ? part.holders[h] : -1);
    }
  add_values<vtkIntArray>(mesh.GetCellData(), kHolders, holders, static_cast<int>(most));
  add_values<vtkDoubleArray>(mesh.GetFieldData(), kReach,
                             std::vector<double>{double(part.reach.layers), part.reach.distance},
                             2);
  add_values<vtkIdTypeArray>(
      mesh.GetFieldData(), kPartIds,
      std::vector<vtkIdType>{part.whole_nodes, part.whole_cells, part.parts, rank}, 4);
  auto text = vtkSmartPointer<vtkStringArray>::New();
  text->SetName(kPartSignature);
  text->InsertNextValue(signature);
  mesh.GetFieldData()->AddArray(text);
  write_vtu_file(mesh, path);
}

/// Takes array `name` out of `data` (throws naming the piece if it is missing or too short).
vtkSmartPointer<vtkDataArray> take(vtkFieldData* data, const char* name, vtkIdType tuples,
                                   int components, const std::string& path) {
  vtkSmartPointer<vtkDataArray> a = data->GetArray(name);
  BRITTLE_CHECK(a && a->GetNumberOfTuples() == tuples && a->GetNumberOfComponents() == components,
                "mesh.parts: '", path, "' has no array '", name,
                "' of its size (expected a piece written by brittle partition --out)");
  data->RemoveArray(name);
  return a;
}

/// Rank `rank`'s piece of the partitioned mesh mesh.parts names, for a run over `ranks`.
LocalPart read_part(const Scene& scene, int rank, int ranks) {
  const std::string path = part_path(scene.mesh.parts, rank);
  BRITTLE_CHECK(std::filesystem::is_regular_file(path), "mesh.parts = ", scene.mesh.parts,
                ": no part_", rank,
                ".vtu (expected the pieces of `brittle partition SCENE.ini "
                "--ranks ",
                ranks, " --out DIR`: DIR/parts_", ranks, ")");
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  LocalPart part;
  part.mesh = reader->GetOutput();
  BRITTLE_CHECK(part.mesh && part.mesh->GetNumberOfCells() > 0, "mesh.parts: '", path,
                "' is not a readable piece (expected a .vtu written by brittle partition --out)");
  vtkFieldData* field = part.mesh->GetFieldData();
  auto ids = take(field, kPartIds, 1, 4, path);
  auto* signature = vtkStringArray::SafeDownCast(field->GetAbstractArray(kPartSignature));
  BRITTLE_CHECK(signature && signature->GetNumberOfValues() == 1, "mesh.parts: '", path,
                "' has no mesh keys (expected a piece written by brittle partition --out)");
  part.whole_nodes = static_cast<vtkIdType>(ids->GetComponent(0, 0));
  part.whole_cells = static_cast<vtkIdType>(ids->GetComponent(0, 1));
  part.parts = static_cast<int>(ids->GetComponent(0, 2));
  BRITTLE_CHECK(part.parts == ranks && ids->GetComponent(0, 3) == rank, "mesh.parts: '", path,
                "' is part ", ids->GetComponent(0, 3), " of ", part.parts, ", this is rank ", rank,
                " of ", ranks, " (expected the pieces for mpirun -np ", ranks, ": parts_", ranks,
                ")");
  BRITTLE_CHECK(signature->GetValue(0) == mesh_signature(scene), "mesh.parts: '", path,
                "' was cut from another mesh (its [geometry], [mesh] or [notch] keys differ from "
                "the scene's; expected brittle partition run on this scene)");
  field->RemoveArray(kPartSignature);
  const vtkIdType np = part.mesh->GetNumberOfPoints(), nc = part.mesh->GetNumberOfCells();
  auto global_node = take(part.mesh->GetPointData(), "global_node", np, 1, path);
  auto owner = take(part.mesh->GetPointData(), "owner", np, 1, path);
  auto global_cell = take(part.mesh->GetCellData(), "global_cell", nc, 1, path);
  auto cell_part = take(part.mesh->GetCellData(), "cell_part", nc, 1, path);
  vtkDataArray* held = part.mesh->GetCellData()->GetArray(kHolders);
  const int most = held ? held->GetNumberOfComponents() : 1;
  auto holders = take(part.mesh->GetCellData(), kHolders, nc, most, path);
  auto reach = take(field, kReach, 1, 2, path);
  part.reach = GhostReach{static_cast<int>(reach->GetComponent(0, 0)), reach->GetComponent(0, 1)};
  for (vtkIdType k = 0; k < np; ++k) {
    part.global_node.push_back(static_cast<vtkIdType>(global_node->GetComponent(k, 0)));
    part.owner.push_back(static_cast<int>(owner->GetComponent(k, 0)));
    part.owned.push_back(part.owner.back() == rank);
  }
  part.holder_start.push_back(0);
  for (vtkIdType e = 0; e < nc; ++e) {
    part.global_cell.push_back(static_cast<vtkIdType>(global_cell->GetComponent(e, 0)));
    part.cell_part.push_back(static_cast<int>(cell_part->GetComponent(e, 0)));
    for (int k = 0; k < most; ++k)
      if (const int h = static_cast<int>(holders->GetComponent(e, k)); h >= 0)
        part.holders.push_back(h);
    part.holder_start.push_back(static_cast<std::int64_t>(part.holders.size()));
  }
  return part;
}

vtkSmartPointer<vtkUnstructuredGrid> shared_mesh(const Scene& scene) {
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
  std::vector<double> points;
  std::vector<std::int64_t> cells;
  // tets, or a 2D body's triangles (mesh.dimension = 2), as Grid takes them
  const int corners = scene.mesh.dimension == 2 ? 3 : 4;
  const int type = corners == 3 ? VTK_TRIANGLE : VTK_TETRA;
  on_every_rank([&] {
    if (mpi_rank() != 0) return;
    mesh = make_mesh(scene);
    points.resize(3 * mesh->GetNumberOfPoints());
    for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p) mesh->GetPoint(p, &points[3 * p]);
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c) {
      if (mesh->GetCellType(c) != type) continue;
      mesh->GetCellPoints(c, ids);
      for (int k = 0; k < corners; ++k) cells.push_back(ids->GetId(k));
    }
  });
  std::int64_t sizes[2] = {static_cast<std::int64_t>(points.size()),
                           static_cast<std::int64_t>(cells.size())};
  MPI_Bcast(sizes, 2, MPI_INT64_T, 0, MPI_COMM_WORLD);
  points.resize(sizes[0]);
  cells.resize(sizes[1]);
  MPI_Bcast(points.data(), static_cast<int>(sizes[0]), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(cells.data(), static_cast<int>(sizes[1]), MPI_INT64_T, 0, MPI_COMM_WORLD);
  if (mpi_rank() == 0) {
    share_groups(*mesh);
    return mesh;
  }
  auto pts = vtkSmartPointer<vtkPoints>::New();
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(sizes[0] / 3);
  for (std::int64_t p = 0; p < sizes[0] / 3; ++p) pts->SetPoint(p, &points[3 * p]);
  auto array = vtkSmartPointer<vtkCellArray>::New();
  for (std::int64_t c = 0; c < sizes[1] / corners; ++c) {
    vtkIdType ids[4];
    for (int k = 0; k < corners; ++k) ids[k] = cells[corners * c + k];
    array->InsertNextCell(corners, ids);
  }
  mesh = vtkSmartPointer<vtkUnstructuredGrid>::New();
  mesh->SetPoints(pts);
  mesh->SetCells(type, array);
  share_groups(*mesh);
  return mesh;
}

}  // namespace

bool silent_rank() { return g_decomposed_rank > 0; }

void begin_decomposed_run() { g_decomposed_rank = mpi_rank(); }

RunSummary run_decomposed(Scene scene, const std::vector<Observer*>& extra,
                          const std::atomic<int>* stop, bool resume) {
  const int rank = mpi_rank(), ranks = mpi_size();
  begin_decomposed_run();
  scene.resolved = scene_entries(scene);
  // Rank 0 takes the directory's lock for the whole run, before any rank writes: at once when
  // the directory exists, else when it is made (as run_scene); a refusal reaches every rank
  // (on_every_rank), so none goes on.
  std::optional<RunLock> lock;
  const std::string& dir = scene.output.directory;
  on_every_rank([&] {
    if (rank == 0 && std::filesystem::is_directory(dir)) lock.emplace(dir);
  });
  std::unique_ptr<Simulation> sim;
  std::unique_ptr<Halo> halo;
  // A checkpoint of another rank count (or a serial one): every rank rebuilds the whole run's
  // state from it, and takes its part once its Halo is made.
  std::unique_ptr<Simulation> whole_state;
  std::vector<int> initial_owner;
  CheckpointHeader header;  // resume: the checkpoint's, and whether it is of another count
  on_every_rank([&] {
    if (resume) header = read_checkpoint_header(checkpoint_path(dir));
  });
  const bool other_count = resume && header.pieces != static_cast<std::uint32_t>(ranks);
  if (!scene.mesh.parts.empty()) {  // each rank reads its part: no rank holds the whole mesh
    on_every_rank([&] {
      BRITTLE_CHECK(!other_count, "checkpoint '", checkpoint_path(dir), "' was written by ",
                    header.pieces,
                    " ranks: a run on mesh.parts resumes on its own rank count (expected "
                    "mpirun -np ",
                    header.pieces, ")");
      LocalPart part = read_part(scene, rank, ranks);
      sim = std::make_unique<Simulation>(scene, *part.mesh);
      halo = std::make_unique<Halo>(part);
    });
  } else {
    auto mesh = shared_mesh(scene);
    if (other_count) {
      on_every_rank([&] {
        whole_state = std::make_unique<Simulation>(scene, *mesh);
        if (header.pieces == 0)
          restore_checkpoint(*whole_state, checkpoint_path(dir));
        else
          absorb_pieces(*whole_state, *mesh, dir, header);
      });
    }
    const Grid whole(*mesh);
    std::vector<int> cell_part(whole.num_cells(), 0);
    const BodySizes body = grid_body_sizes(whole);  // (once: the reach and the parts)
    on_every_rank([&] {
      if (rank == 0 && ranks > 1) cell_part = partition_grid(whole, ranks, {}, &body).cell_part;
    });
    MPI_Bcast(cell_part.data(), static_cast<int>(cell_part.size()), MPI_INT, 0, MPI_COMM_WORLD);
    const Partition partition =
        partition_from(whole, std::move(cell_part), ranks, ghost_reach(scene, body), &body);
    LocalPart part = extract_part(whole, partition, rank);
    add_groups(*mesh, part);
    mesh = nullptr;  // the whole mesh is not needed from here on
    on_every_rank([&] { sim = std::make_unique<Simulation>(scene, *part.mesh); });
    halo = std::make_unique<Halo>(part);
    if (whole_state) initial_owner = partition.node_owner;
  }
  sim->decompose(*halo);
  if (whole_state) {
    on_every_rank([&] { sim->take_part(*whole_state, initial_owner); });
    whole_state = nullptr;
  } else if (resume) {
    restore_decomposed_checkpoint(*sim, *halo);  // the same error on every rank
  }
  sim->set_stop_flag(stop);
  on_every_rank([&] {
    if (rank == 0 && !lock) lock.emplace(dir);
  });
  std::vector<std::unique_ptr<Observer>> writers;
  on_every_rank([&] {
    std::filesystem::create_directories(dir);
    if (scene.output.vtu) writers.push_back(std::make_unique<PieceSeriesWriter>(dir, *halo));
    if (!scene.sensors.empty())  // on every rank: the owner of a sensor's node reads it
      writers.push_back(std::make_unique<SensorRecorder>(scene, dir, rank == 0));
    if (rank != 0) return;
    write_file_atomically(dir + "/scene.ini", scene_ini(scene));  // the run's own scene
    if (!resume) {  // an earlier run's checkpoint and frames are not this run's
      remove_checkpoints(dir);
      if (const int n = remove_earlier_frames(dir))
        std::fprintf(stderr, "brittle: removed %d frame files of an earlier run from %s/frames\n",
                     n, dir.c_str());
    }
    writers.push_back(std::make_unique<EnergyCsvWriter>(dir, resume));
    if (sim->fracture().enabled()) {
      writers.push_back(std::make_unique<CrackTipCsvWriter>(dir));
      writers.push_back(std::make_unique<PatternWriter>(dir));
    }
    writers.push_back(std::make_unique<SummaryWriter>(dir));
  });
  // render.times: on every rank, as it gathers the pieces on rank 0 that draws them.
  if (auto renderer = make_render_observer(scene)) writers.push_back(std::move(renderer));
  std::vector<Observer*> observers;
  for (auto& w : writers) observers.push_back(w.get());
  if (rank == 0) observers.insert(observers.end(), extra.begin(), extra.end());
  CheckpointWriter checkpoints;
  return sim->run(observers, &checkpoints);
}

void absorb_pieces(Simulation& whole, vtkUnstructuredGrid& mesh, const std::string& directory,
                   const CheckpointHeader& h) {
  const Grid initial(mesh);
  const int parts = static_cast<int>(h.pieces);
  const BodySizes body = grid_body_sizes(initial);
  const Partition partition =  // as that run cut it
      partition_grid(initial, parts, ghost_reach(whole.scene(), body), &body);
  for (int p = 0; p < parts; ++p) {
    LocalPart part = extract_part(initial, partition, p);
    add_groups(mesh, part);
    Simulation sim(whole.scene(), *part.mesh);
    Halo halo(part, p, parts);
    read_checkpoint_piece(sim, halo, directory, h);
    whole.absorb_part(sim, halo);
  }
  whole.finish_absorbing();
}

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
  opts.add_options()("help,h", "show this help")("ranks", po::value(&ranks)->default_value("2,4,8"),
                                                 "rank counts, comma separated")(
      "set", po::value(&sets)->composing(), "override one key: section.key=value (repeatable)")(
      "out", po::value(&out),
      "directory (created) for DIR/partition_<ranks>.vtu (cell data rank, point data owner, "
      "for ParaView) and the mesh cut into parts, DIR/parts_<ranks>/part_<rank>.vtu, which a "
      "run over <ranks> MPI ranks reads with --set mesh.parts=DIR/parts_<ranks>; without it "
      "nothing is written");
  po::options_description hidden;
  hidden.add_options()("scene", po::value(&files)->composing(), "scene INI files");
  auto vm = parse_command_line(args, opts, hidden, "scene");
  if (vm.count("help")) {
    print_command_help(std::cout,
                       "usage: brittle partition SCENE.ini [MORE.ini ...] [--ranks 2,4,8] "
                       "[--set k=v ...] [--out DIR]",
                       "Meshes the scene's plate and partitions it as `mpirun -np N brittle run` "
                       "would, and prints the ghost nodes, redundant cells and imbalance of each "
                       "rank count (docs/parallel.md).",
                       opts);
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
  const std::string signature = mesh_signature(scene);
  if (!out.empty()) std::filesystem::create_directories(out);
  auto mesh = make_mesh(scene);
  Grid grid(*mesh);
  // The ghost cells the scene's criterion reads past the first layer (docs/parallel.md, "Ghost
  // depth"): the pieces hold them, and a run checks that they do.
  const BodySizes body = grid_body_sizes(grid);
  const GhostReach reach = ghost_reach(scene, body);
  std::printf("%lld tets, %lld nodes; ghost reach %d layer%s + %.3g mm (fracture.criterion)\n",
              static_cast<long long>(grid.num_cells()),
              static_cast<long long>(grid.num_points()), reach.layers,
              reach.layers == 1 ? "" : "s", reach.distance * 1e3);
  std::printf("%6s %10s %9s %12s %12s %14s %12s %12s %11s %16s\n", "ranks", "imbalance",
              "cut faces", "ghost nodes", "ghost/owned", "redundant tets", "extra ghosts",
              "max ghosts", "max neighb.", "max bytes/step");
  for (int parts : counts) {
    const Partition p = partition_grid(grid, parts, reach, &body);
    long extra = 0;
    for (const PartStats& s : p.stats) extra += s.extra_ghost_cells;
    long most_ghosts = 0;
    int most_neighbours = 0;
    double worst_ratio = 0;
    for (const PartStats& s : p.stats) {
      most_ghosts = std::max(most_ghosts, s.ghost_nodes);
      most_neighbours = std::max(most_neighbours, s.neighbours);
      if (s.owned_nodes > 0) worst_ratio = std::max(worst_ratio, double(s.ghost_nodes) / s.owned_nodes);
    }
    // Every step a rank receives the positions and velocities of its ghost nodes: 6 doubles.
    std::printf("%6d %10.3f %9ld %11.2f%% %11.2f%% %13.2f%% %12ld %12ld %11d %16ld\n", parts,
                p.imbalance(), p.cut_faces, 100 * p.ghost_fraction(), 100 * worst_ratio,
                100 * p.redundant_fraction(), extra, most_ghosts, most_neighbours,
                48 * most_ghosts);
    if (out.empty()) continue;
    write_partition_vtu(grid, p, out + "/partition_" + std::to_string(parts) + ".vtu");
    const std::string pieces = out + "/parts_" + std::to_string(parts);
    std::filesystem::create_directories(pieces);
    for (int r = 0; r < parts; ++r) {
      LocalPart part = extract_part(grid, p, r);
      add_groups(*mesh, part);
      write_part(part, r, signature, part_path(pieces, r));
    }
  }
  if (!out.empty())
    std::printf(
        "wrote %s/partition_N.vtu (to look at) and %s/parts_N/part_R.vtu (for mpirun -np "
        "N brittle run ... --set mesh.parts=%s/parts_N)\n",
        out.c_str(), out.c_str(), out.c_str());
  return 0;
}

}  // namespace brittle
