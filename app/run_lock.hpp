// One run per output directory (issue 27, item 5; docs/output.md, "One run per directory"):
// a run holds DIR/run.lock (its pid, host and start time) from before it writes anything until
// it ends; a second run into DIR is refused with one line naming the first.
#pragma once

#include <string>

#include "error.hpp"

namespace brittle {

/// The refusal: a live run holds the directory (or, from another host, may hold it). Nothing
/// in the directory was touched.
class DirectoryHeld : public Error {
 public:
  using Error::Error;
};

/// Holds DIR/run.lock for as long as it lives: an flock(2) on a file that names the holder,
/// created whole (written aside, then hard-linked in) and removed by the destructor.
///
/// - A lock whose flock is held (a live run on this host, or on another one where the file
///   system shares locks) refuses: DirectoryHeld naming the directory, pid, host and start.
/// - A lock whose flock is free was left by a run that died (the kernel drops an flock with
///   its process): on this host it is stale and taken over; naming another host it refuses,
///   with the hint to remove it, as that host's locks may not reach this one (NFS without
///   lockd, Lustre's localflock) and its run may be alive.
/// - On a file system without flock the pid decides on this host (kill(pid, 0): ESRCH =
///   stale), and a file system without hard links gets the file by O_CREAT | O_EXCL.
/// A lock held by this process's parent is waited for (up to 10 s): a batch command holds it
/// while it prepares a child's directory and spawns the child (app/child_runs.cpp).
class RunLock {
 public:
  /// Creates `directory` if missing and takes its lock, or throws DirectoryHeld.
  explicit RunLock(const std::string& directory);
  /// Removes the lock file (if it is still this lock's) and releases the flock.
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

  /// DIR/run.lock.
  const std::string& path() const { return path_; }

 private:
  /// One attempt: true when the lock is taken, false to look again (it changed meanwhile).
  bool try_take();
  /// Makes a complete lock file aside and links it in (replace: renames it over the stale
  /// one). False when another run linked its lock in first.
  bool install(bool replace);

  std::string directory_, path_;
  int fd_ = -1;
};

/// The lock file's name in a run directory.
inline constexpr const char* kRunLockName = "run.lock";

/// This host's name (gethostname), as a lock records it.
std::string lock_host_name();

}  // namespace brittle
