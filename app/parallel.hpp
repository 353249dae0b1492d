// MPI for brittle (issue 14, docs/parallel.md): the session (MPI is started only when the
// process was launched by mpirun), whole runs of batch commands spread over ranks, and
// `brittle partition`, which measures the domain decomposition of a scene's mesh.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "checkpoint.hpp"
#include "simulation.hpp"

namespace brittle {

/// True when the process was started by mpirun/mpiexec or a scheduler's launcher (Open MPI's
/// OMPI_COMM_WORLD_SIZE, PMIx's PMIX_RANK or PMI's PMI_SIZE in the environment). A plain
/// `brittle ...` never touches MPI.
bool launched_by_mpi();

/// MPI_Init_thread in the constructor when launched_by_mpi(), MPI_Finalize in the destructor;
/// otherwise one rank of one. One per process (main).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

/// This process's rank and the number of ranks (0 and 1 without MPI).
int mpi_rank();
int mpi_size();
/// Waits for every rank (nothing without MPI).
void mpi_barrier();
/// Element-wise maximum over the ranks, in place (nothing without MPI).
void mpi_max(std::vector<int>& values);

/// True when this process is a rank other than 0 of a decomposed `brittle run`: it prints no
/// error (every rank ends with the same one, and rank 0 prints it).
bool silent_rank();
/// Marks this process as a rank of a decomposed run (from the moment its options are read).
void begin_decomposed_run();

/// `mpirun -np N brittle run SCENE`: one run decomposed over the ranks (docs/parallel.md).
/// Rank 0 meshes and partitions (METIS) the plate and sends both to every rank; each rank
/// steps its part (solver/parallel/halo.hpp) and writes its piece of every frame; rank 0 writes
/// energies.csv, crack_tip.csv, events.csv, pattern.json, summary.json and the .pvtu/.pvd
/// series; checkpoints are every rank's piece and rank 0's checkpoint.bin that names the set
/// (docs/checkpoint.md). Refused with one line, before anything is written: sensors,
/// render.times and physical-group regions (not built for decomposed runs yet). Rank 0 holds
/// the directory's lock (run_lock.hpp) for the run; a refusal ends every rank before any
/// writes. `extra` observers (progress) run on rank 0. With `resume` (the scene from
/// resume_scene) the run goes on from the checkpoint in the output directory: every rank
/// restores its piece if as many ranks wrote it; else (a serial run's, or another rank
/// count's) every rank rebuilds the whole run's state from it and takes its part
/// (docs/checkpoint.md, "Another rank count").
RunSummary run_decomposed(Scene scene, const std::vector<Observer*>& extra,
                          const std::atomic<int>* stop, bool resume = false);

/// The whole-grid simulation `whole`, built fresh from the scene on `mesh`, takes the state
/// of the decomposed run's checkpoint `h` in `directory`: each piece is read into its part,
/// cut from the mesh as the run that wrote it cut it (the same METIS partition), and
/// absorbed (Simulation::absorb_part). Joins no other rank.
void absorb_pieces(Simulation& whole, vtkUnstructuredGrid& mesh, const std::string& directory,
                   const CheckpointHeader& h);

/// `brittle partition SCENE.ini [MORE.ini ...] --ranks 2,4 [--set k=v ...]`: meshes the
/// scene, partitions it for each rank count and prints the partition quality (ghost nodes,
/// redundant cells, imbalance, messages and bytes per step).
int partition_command(const std::vector<std::string>& args);

}  // namespace brittle
