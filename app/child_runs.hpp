// Batch commands (sweep, study) run whole simulations as child `brittle run` processes, a few at
// a time, each with its own directory and run.log, and pass a stop request on to them.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace brittle {

/// One child run: the arguments after the executable, and the directory it writes into (its
/// stdout and stderr go to <directory>/run.log).
struct ChildRun {
  std::vector<std::string> args;
  std::string directory;
};

/// What became of a child run: not started (a stop request came first), started, or not
/// started because a live run holds its directory (run_lock.hpp; nothing in it was touched).
enum class ChildStart { stopped = 0, started = 1, held = 2 };

/// Runs `brittle` (this executable) once per entry, at most `jobs` at a time (0 = number of
/// cores), in order. Each directory is created and a stale summary.json removed first, under
/// the directory's lock (held until the child is spawned), so a run that fails before writing
/// one cannot be read as finished; a directory a live run holds is left alone (a line on
/// stderr, ChildStart::held). A stop request
/// (stop_signal.hpp) is passed on once to the running children, which stop with a checkpoint,
/// and no more are started.
///
/// Under mpirun with N ranks (parallel.hpp) every rank calls this with the same list: rank r
/// runs the entries r, r + N, r + 2N, ... (`jobs` at a time on its node), the children get an
/// environment without the MPI launcher's variables (each is a plain single-process run), and
/// all ranks wait for each other at the end. Returns, per entry, what became of it (on any
/// rank).
std::vector<ChildStart> run_children(const std::vector<ChildRun>& runs, int jobs);

/// A batch's runs (study mesh, study ensemble): with `reuse`, an entry whose directory holds a
/// completed run of the same arguments is read, not run again ("brittle study: reusing DIR" on
/// rank 0); the rest go through run_children. Per entry: empty when it is ready (reused or
/// run), else why not ("not started: ...", `batch` naming what was stopped).
std::vector<std::string> run_or_reuse(const std::vector<ChildRun>& runs, bool reuse, int jobs,
                                      const std::string& batch);

/// The JSON in `path`, or nothing when it is missing or not JSON.
std::optional<nlohmann::json> read_json(const std::string& path);

/// Whether the run's directory holds a completed run of exactly these arguments: its
/// summary's scene sources (files, then "--set k=v" in order) equal the planned ones (a
/// batch's --reuse).
bool finished_same_run(const ChildRun& run);

}  // namespace brittle
