// Test support (LD_PRELOAD; tests/test_parallel.cpp, Mpi.PartitionedMeshRunHoldsNoWholeGridArray):
// notes the size of every allocation of 4 kB or more a process makes and, at its exit, writes
// them to $BRITTLE_ALLOC_LOG/alloc_<pid>.txt with the MPI rank first. It forwards to glibc's
// allocator, so the process runs as it would without it.
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstdlib>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
}

namespace {
constexpr std::size_t kSmallest = 4096, kCapacity = 1 << 20;
std::size_t g_sizes[kCapacity];
std::atomic<std::size_t> g_count{0};

void note(std::size_t n) {
  if (n < kSmallest) return;
  const std::size_t i = g_count.fetch_add(1, std::memory_order_relaxed);
  if (i < kCapacity) g_sizes[i] = n;
}

__attribute__((destructor)) void write_log() {
  const char* dir = std::getenv("BRITTLE_ALLOC_LOG");
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  if (!dir || !rank) return;  // (mpirun itself)
  char path[4096];
  std::snprintf(path, sizeof path, "%s/alloc_%d.txt", dir, static_cast<int>(getpid()));
  std::FILE* f = std::fopen(path, "w");
  if (!f) return;
  const std::size_t n = g_count.load() < kCapacity ? g_count.load() : kCapacity;
  std::fprintf(f, "%s\n", rank);
  for (std::size_t i = 0; i < n; ++i) std::fprintf(f, "%zu\n", g_sizes[i]);
  std::fclose(f);
}
}  // namespace

extern "C" {
void* malloc(std::size_t n) {
  note(n);
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t size) {
  note(count * size);
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t n) {
  note(n);
  return __libc_realloc(p, n);
}
void free(void* p) {
  __libc_free(p);
}
void* memalign(std::size_t alignment, std::size_t n) {
  note(n);
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  note(n);
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  note(n);
  void* p = __libc_memalign(alignment, n);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
}
