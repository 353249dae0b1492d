// Checkpoint and resume (docs/checkpoint.md): the whole state of a run between two steps, in
// one binary file written atomically, from which the run continues with the same bits as if it
// had never stopped.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "exact_sum.hpp"
#include "error.hpp"
#include "material.hpp"

namespace brittle {

class Simulation;
class Halo;

/// FNV-1a over bytes (fingerprints and the checkpoint's checksum), continuing from h.
inline std::uint64_t fnv1a(const void* data, std::size_t size,
                           std::uint64_t h = 14695981039346656037ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

/// Writes values as their bytes (the checkpoint is read back by the same build on the same
/// kind of machine: the version check refuses any other): into bytes(), or with a file
/// descriptor through a 1 MB buffer into the file, so that a checkpoint costs no copy of the
/// state in memory. Keeps the FNV-1a checksum of everything written.
class StateWriter {
 public:
  static constexpr bool loading = false;
  StateWriter() = default;
  /// Into the open file `fd`; `kill_after_first_block` is the test hook of write_checkpoint.
  explicit StateWriter(int fd, bool kill_after_first_block = false)
      : fd_(fd), kill_(kill_after_first_block) {}
  template <class T>
  void raw(const T* data, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t size = count * sizeof(T), old = bytes_.size();
    if (size == 0) return;
    hash_ = fnv1a(data, size, hash_);
    written_ += size;
    if (fd_ >= 0 && old + size > kBlock) {
      flush();
      if (size > kBlock) return write_out(data, size);
    }
    bytes_.resize(bytes_.size() + size);
    std::memcpy(bytes_.data() + bytes_.size() - size, static_cast<const void*>(data), size);
  }
  /// Writes the buffer to the file (if any); the first error (errno) is kept in error().
  void flush();
  std::string& bytes() { return bytes_; }
  std::uint64_t hash() const { return hash_; }
  std::size_t written() const { return written_; }
  int error() const { return error_; }
  const std::string& what() const { return what_; }

 private:
  static constexpr std::size_t kBlock = std::size_t(1) << 20;
  void write_out(const void* data, std::size_t size);
  std::string bytes_;
  int fd_ = -1;
  bool kill_ = false;
  int error_ = 0;
  std::uint64_t hash_ = 14695981039346656037ull;
  std::size_t written_ = 0;
  std::string what_ = "checkpoint";
};

/// Reads what StateWriter wrote; every read is bounds-checked, so a damaged file gives a
/// brittle::Error, never a crash or a huge allocation.
class StateReader {
 public:
  static constexpr bool loading = true;
  StateReader(const char* begin, const char* end, std::string what)
      : p_(begin), end_(end), what_(std::move(what)) {}
  template <class T>
  void raw(T* data, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    check(count, sizeof(T));
    if (count == 0) return;  // data may be null (an empty vector)
    std::memcpy(static_cast<void*>(data), p_, count * sizeof(T));
    p_ += count * sizeof(T);
  }
  /// Throws unless `count` values of `size` bytes are left.
  void check(std::size_t count, std::size_t size) const {
    BRITTLE_CHECK(size == 0 || count <= static_cast<std::size_t>(end_ - p_) / size, what_,
                  ": truncated or damaged (expected a checkpoint written by this brittle)");
  }
  bool done() const { return p_ == end_; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  const std::string& what() const { return what_; }

 private:
  const char* p_;
  const char* end_;
  std::string what_;
};

// io(ar, value): one function for both directions. Scalars and trivially copyable vectors as
// bytes, other vectors element by element, classes through their `state(ar)` member.
template <class Ar, class T>
  requires std::is_arithmetic_v<T> || std::is_enum_v<T>
void io(Ar& ar, T& v) {
  ar.raw(&v, 1);
}
template <class Ar>
void io(Ar& ar, Vec3& v) {
  ar.raw(v.data(), 3);
}
template <class Ar>
void io(Ar& ar, ExactSum& s) {  // its settled words
  ExactSum::Words w = s.words();
  ar.raw(w.data(), w.size());
  if constexpr (Ar::loading) s = ExactSum::from_words(w);
}
template <class Ar>
void io(Ar& ar, std::string& s) {
  std::uint64_t n = s.size();
  io(ar, n);
  if constexpr (Ar::loading) ar.check(n, 1), s.resize(n);
  ar.raw(s.data(), n);
}
template <class Ar, class T>
  requires requires(Ar& ar, T& t) { t.state(ar); }
void io(Ar& ar, T& t) {
  t.state(ar);
}
template <class Ar, class T>
void io(Ar& ar, std::vector<T>& v) {
  std::uint64_t n = v.size();
  io(ar, n);
  if constexpr (std::is_trivially_copyable_v<T> && !std::is_same_v<T, bool>) {
    if constexpr (Ar::loading) ar.check(n, sizeof(T)), v.resize(n);
    ar.raw(v.data(), n);
  } else {
    if constexpr (Ar::loading) ar.check(n, 1), v.resize(n);  // each element takes a byte at least
    for (T& x : v) io(ar, x);
  }
}
template <class Ar, class... T>
void io_all(Ar& ar, T&... v) {
  (io(ar, v), ...);
}

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
