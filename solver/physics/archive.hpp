// Values as bytes and back (docs/checkpoint.md): the checkpoint's file and the child readers'
// results (mesh/isolated_read) are written by StateWriter and read by StateReader, one io(ar, v)
// for both directions; FNV-1a fingerprints and checksums them.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "error.hpp"
#include "exact_sum.hpp"
#include "material.hpp"

namespace brittle {

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

}  // namespace brittle
