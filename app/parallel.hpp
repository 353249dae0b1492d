// MPI for brittle (issue 14, docs/parallel.md): the session (MPI is started only when the
// process was launched by mpirun), whole runs of batch commands spread over ranks, and
// `brittle partition`, which measures the domain decomposition of a scene's mesh.
#pragma once

#include <string>
#include <vector>

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

/// `brittle partition SCENE.ini [MORE.ini ...] --ranks 2,4 [--set k=v ...]`: meshes the
/// scene, partitions it for each rank count and prints the partition quality (ghost nodes,
/// redundant cells, imbalance, messages and bytes per step).
int partition_command(const std::vector<std::string>& args);

}  // namespace brittle
