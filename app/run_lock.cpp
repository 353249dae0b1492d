// One run per output directory: DIR/run.lock, a file naming its holder, flock'ed while it runs.
#include "run_lock.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <thread>

namespace brittle {
namespace {

/// What a lock file says: pid=, host=, started= lines.
struct Holder {
  long pid = 0;
  std::string host, started;
  bool complete() const { return pid > 0 && !host.empty(); }
};

std::string lock_text() {
  char started[32];
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::strftime(started, sizeof started, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return error_message("pid=", getpid(), "\nhost=", lock_host_name(), "\nstarted=", started,
                       "\n");
}

Holder read_holder(int fd) {
  std::string text;
  char buffer[512];
  for (ssize_t n; text.size() < 4096 && (n = pread(fd, buffer, sizeof buffer, text.size())) > 0;)
    text.append(buffer, n);
  Holder h;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "pid") h.pid = std::strtol(value.c_str(), nullptr, 10);
    if (key == "host") h.host = value;
    if (key == "started") h.started = value;
  }
  return h;
}

std::string describe(const Holder& h) {
  if (!h.complete()) return "its pid and host not written";
  return error_message("pid ", h.pid, " on host ", h.host,
                       h.started.empty() ? "" : ", started " + h.started);
}

/// True when `fd` is the file at `path` now, not one removed or replaced since it was opened.
bool is_at(int fd, const std::string& path) {
  struct stat open{}, named{};
  return ::fstat(fd, &open) == 0 && ::stat(path.c_str(), &named) == 0 &&
         open.st_dev == named.st_dev && open.st_ino == named.st_ino;
}

/// errno of a file system without flock (some network and cluster file systems).
bool no_flock(int e) { return e == ENOLCK || e == EOPNOTSUPP || e == ENOSYS || e == EINVAL; }

/// flock(LOCK_EX | LOCK_NB): 0 taken, EWOULDBLOCK held, or the errno of no flock; else throws.
int try_flock(int fd, const std::string& path) {
  int rc;
  while ((rc = ::flock(fd, LOCK_EX | LOCK_NB)) != 0 && errno == EINTR) {
  }
  if (rc == 0) return 0;
  const int e = errno;
  BRITTLE_CHECK(e == EWOULDBLOCK || no_flock(e), "cannot lock ", path, ": ", std::strerror(e));
  return e;
}

void write_all(int fd, const std::string& text, const std::string& path) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    BRITTLE_CHECK(n > 0, "cannot write ", path, ": ", std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
}

/// Attempts are 10 ms apart: a lock file being written is waited for up to 0.5 s, a parent's
/// hand-over up to 10 s.
constexpr int kIncompleteAttempts = 50, kAttempts = 1000;

}  // namespace

std::string lock_host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "unknown";
  return name;
}

RunLock::RunLock(const std::string& directory)
    : directory_(directory), path_(directory + "/" + kRunLockName) {
  std::filesystem::create_directories(directory_);
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const int fd = ::open(path_.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) {
      BRITTLE_CHECK(errno == ENOENT, "cannot open ", path_, ": ", std::strerror(errno));
      if (install(false)) return;
      continue;  // another run linked its lock in first: look at it
    }
    struct Closer {
      int fd;
      ~Closer() { ::close(fd); }
    } closer{fd};
    const int flocked = try_flock(fd, path_);
    if (!is_at(fd, path_)) continue;  // removed or replaced since it was opened: look again
    const Holder h = read_holder(fd);
    const std::string host = lock_host_name();
    bool held = flocked == EWOULDBLOCK;
    const bool kernel = flocked == 0 || held;
    if (!kernel && h.complete() && h.host == host)  // no flock here: the pid says
      held = h.pid == getpid() || ::kill(static_cast<pid_t>(h.pid), 0) == 0 || errno != ESRCH;
    // Linked in whole, a lock is complete at once; one made by O_EXCL is written just after.
    if (!h.complete() && attempt < kIncompleteAttempts) continue;
    // A batch command hands its child the directory: it holds the lock until the spawn returns.
    if (held && h.complete() && h.host == host && h.pid == getppid() && attempt < kAttempts - 1)
      continue;
    const std::string hint = error_message("expected a directory no other run is writing: wait "
                                           "for that run, stop it, or choose another directory");
    if (held)
      throw DirectoryHeld(error_message(directory_, ": a live run holds this directory (",
                                        describe(h), "; ", path_, "): ", hint));
    if (h.complete() && h.host != host)  // its flock may not reach this host: it may be alive
      throw DirectoryHeld(error_message(
          directory_, ": ", path_, " names a run on another host (", describe(h),
          "), which cannot be checked from ", host, ": ", hint, " (if no run on ", h.host,
          " is writing it, remove ", path_, ")"));
    if (!kernel && !h.complete())
      throw DirectoryHeld(error_message(directory_, ": ", path_, " does not say which run holds "
                                        "it and this file system has no flock: ", hint,
                                        " (if no run is writing it, remove ", path_, ")"));
    // Stale: its run died. Its flock, ours meanwhile, keeps another run from deciding the same.
    if (install(true)) return;
  }
  throw Error(error_message(path_, ": the lock kept changing for ", kAttempts / 100,
                            " s (expected one run to take it)"));
}

bool RunLock::install(bool replace) {
  static std::atomic<unsigned> serial{0};
  const std::string aside = error_message(path_, ".", getpid(), ".", serial++, ".tmp");
  int fd = ::open(aside.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0644);
  BRITTLE_CHECK(fd >= 0, "cannot create ", aside, ": ", std::strerror(errno));
  const std::string text = lock_text();
  try {
    write_all(fd, text, aside);
    try_flock(fd, aside);  // a new file: only a file system without flock refuses
  } catch (...) {
    ::close(fd);
    ::unlink(aside.c_str());
    throw;
  }
  const int rc = replace ? ::rename(aside.c_str(), path_.c_str()) : ::link(aside.c_str(), path_.c_str());
  const int e = errno;
  if (rc != 0 || !replace) ::unlink(aside.c_str());
  if (rc == 0) {
    fd_ = fd;
    return true;
  }
  ::close(fd);
  if (e == EEXIST) return false;
  // No hard links (FAT, some FUSE and SMB mounts): created exclusively, written just after.
  BRITTLE_CHECK(!replace && (e == EPERM || e == EOPNOTSUPP || e == ENOSYS), "cannot create ",
                path_, ": ", std::strerror(e));
  fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0 && errno == EEXIST) return false;
  BRITTLE_CHECK(fd >= 0, "cannot create ", path_, ": ", std::strerror(errno));
  try {
    try_flock(fd, path_);
    write_all(fd, text, path_);
  } catch (...) {
    ::unlink(path_.c_str());
    ::close(fd);
    throw;
  }
  fd_ = fd;
  return true;
}

RunLock::~RunLock() {
  if (fd_ < 0) return;
  // Removed while still flock'ed: a run that opened it meanwhile sees it is gone (is_at).
  if (is_at(fd_, path_)) ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace brittle
