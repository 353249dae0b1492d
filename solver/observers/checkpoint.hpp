// Checkpoint and resume (docs/checkpoint.md): the whole state of a run between two steps, in
// one binary file written atomically, from which the run continues with the same bits as if it
// had never stopped.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "archive.hpp"
#include "simulation.hpp"

namespace brittle {

/// What a checkpoint says about itself, readable without building the run.
struct CheckpointHeader {
  std::string version;               ///< brittle version that wrote it
  std::vector<std::string> sources;  ///< scene files (absolute) and "--set k=v", in order
  double time = 0;                   ///< simulated time of the state
  long steps = 0;
  /// 0: the file holds the state. N > 0: a run decomposed over N MPI ranks wrote it; the
  /// state is in the N pieces of `generation` (checkpoint_piece_path), their checksums here.
  std::uint32_t pieces = 0;
  std::uint64_t generation = 0;
  std::vector<std::uint64_t> piece_sums;
};

/// The file name of a run's checkpoint in its output directory.
inline std::string checkpoint_path(const std::string& directory) {
  return directory + "/checkpoint.bin";
}

/// Writes the simulation's state to `path` through `path`.tmp, fsync and a rename, so that a
/// kill at any moment leaves the previous checkpoint (or none) intact. Returns bytes written.
std::size_t write_checkpoint(const Simulation& sim, const std::string& path);

/// A decomposed run's checkpoint piece: rank `rank`'s part of set `generation`.
std::string checkpoint_piece_path(const std::string& directory, std::uint64_t generation,
                                  int rank);

/// Removes a run directory's checkpoint: checkpoint.bin, every piece, and their .tmp files
/// (a fresh run into the directory: they are not its state).
void remove_checkpoints(const std::string& directory);

/// A decomposed run's checkpoint (collective; docs/checkpoint.md): every rank writes its piece
/// (write_checkpoint's file, of its part and its Halo), then rank 0 rewrites checkpoint.bin to
/// name the new set with the pieces' checksums, then each rank removes its earlier pieces. A
/// kill at any moment leaves checkpoint.bin naming a whole set. A failure on any rank throws on
/// every rank. Returns the bytes this rank wrote.
std::size_t write_decomposed_checkpoint(const Simulation& sim, const Halo& halo);

/// Simulation::run's checkpoints into the run's output directory: checkpoint.bin
/// (write_checkpoint), or in a decomposed run its pieces and manifest
/// (write_decomposed_checkpoint).
class CheckpointWriter : public Checkpointer {
 public:
  std::string path(const Simulation& sim) const override;
  std::size_t write(const Simulation& sim) override;
};

/// Restores this rank's piece of the set checkpoint.bin names in the output directory
/// (collective): the same rank count, each piece's checksum the one checkpoint.bin holds, and
/// the checks of restore_checkpoint; a failure on any rank throws on every rank.
void restore_decomposed_checkpoint(Simulation& sim, const Halo& halo);

/// Reads the piece that rank halo.rank() wrote of the decomposed checkpoint `h` in
/// `directory` into `part` (built fresh on that rank's part of the mesh; `halo` built offline
/// for it), checked against the set's checksum and the scene: the first step of resuming on
/// another rank count (Simulation::absorb_part). Joins no other rank.
void read_checkpoint_piece(Simulation& part, Halo& halo, const std::string& directory,
                           const CheckpointHeader& h);

/// Throws brittle::Error unless the checkpoint at `path` (its header `h`) was written by a run
/// over `ranks` MPI ranks (0: a serial run), naming the rank count that wrote it: the guard of
/// restore_checkpoint and restore_decomposed_checkpoint (another count goes through
/// read_checkpoint_piece and the re-cut of Simulation).
void check_rank_count(const CheckpointHeader& h, const std::string& path, int ranks);

/// Reads the header of a checkpoint (version, scene sources, time); throws brittle::Error
/// naming the file if it is not one.
CheckpointHeader read_checkpoint_header(const std::string& path);

/// Restores the state saved in `path` into `sim`, built from the same scene (only run.end_time,
/// run.threads and output.directory may differ) and mesh: else throws brittle::Error saying
/// what differs.
void restore_checkpoint(Simulation& sim, const std::string& path);

}  // namespace brittle
