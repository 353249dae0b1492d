// Checkpoint and resume (docs/checkpoint.md): the whole state of a run between two steps, in
// one binary file written atomically, from which the run continues with the same bits as if it
// had never stopped.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "error.hpp"
#include "material.hpp"

namespace brittle {

class Simulation;

/// Writes values as their bytes (the checkpoint is read back by the same build on the same
/// kind of machine: the version check refuses any other).
class StateWriter {
 public:
  static constexpr bool loading = false;
  template <class T>
  void raw(const T* data, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t size = count * sizeof(T), old = bytes_.size();
    bytes_.resize(old + size);
    if (size) std::memcpy(bytes_.data() + old, static_cast<const void*>(data), size);
  }
  std::string& bytes() { return bytes_; }
  const std::string& what() const { return what_; }

 private:
  std::string bytes_;
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

/// FNV-1a over bytes (fingerprints and the checkpoint's checksum).
inline std::uint64_t fnv1a(const void* data, std::size_t size,
                           std::uint64_t h = 14695981039346656037ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

/// What a checkpoint says about itself, readable without building the run.
struct CheckpointHeader {
  std::string version;               ///< brittle version that wrote it
  std::vector<std::string> sources;  ///< scene files (absolute) and "--set k=v", in order
  double time = 0;                   ///< simulated time of the state
  long steps = 0;
};

/// The file name of a run's checkpoint in its output directory.
inline std::string checkpoint_path(const std::string& directory) {
  return directory + "/checkpoint.bin";
}

/// Writes the simulation's state to `path` through `path`.tmp, fsync and a rename, so that a
/// kill at any moment leaves the previous checkpoint (or none) intact. Returns bytes written.
std::size_t write_checkpoint(const Simulation& sim, const std::string& path);

/// Reads the header of a checkpoint (version, scene sources, time); throws brittle::Error
/// naming the file if it is not one.
CheckpointHeader read_checkpoint_header(const std::string& path);

/// Restores the state saved in `path` into `sim`, built from the same scene (only run.end_time,
/// run.threads and output.directory may differ) and mesh: else throws brittle::Error saying
/// what differs.
void restore_checkpoint(Simulation& sim, const std::string& path);

}  // namespace brittle
