// Child `brittle run` processes for the batch commands: spawn with the log as stdout/stderr, in
// their own process group, wait, forward one stop request.
#include "child_runs.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <map>
#include <thread>

#include "error.hpp"
#include "parallel.hpp"
#include "paths.hpp"
#include "run_lock.hpp"
#include "stop_signal.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace brittle {
namespace {

/// This process's environment without the MPI launcher's variables, so that a child is a
/// plain run and not a rank of a job it was never part of.
std::vector<std::string> child_environment() {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    bool mpi = false;
    for (const char* prefix : {"OMPI_", "PMIX_", "PMI_", "HYDRA_", "MPI_LOCALNRANKS", "MPI_LOCALRANKID"})
      mpi = mpi || entry.rfind(prefix, 0) == 0;
    if (!mpi) env.push_back(entry);
  }
  return env;
}

/// Starts `exe args...` with stdout and stderr into `log`; returns its pid.
pid_t spawn(const std::string& exe, const std::vector<std::string>& args, const std::string& log) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(exe.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // Its own process group: a Ctrl-C at the terminal reaches the batch command only, which
  // passes one stop request on (run_children); the run would take a second one as "stop at
  // once".
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = 0;
  static const std::vector<std::string> env = child_environment();
  std::vector<char*> envp;
  for (const std::string& e : env) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  const int rc = posix_spawn(&pid, exe.c_str(), &actions, &attributes, argv.data(), envp.data());
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  BRITTLE_CHECK(rc == 0, "cannot start '", exe, "' (error ", rc, ")");
  return pid;
}

}  // namespace

std::vector<ChildStart> run_children(const std::vector<ChildRun>& runs, int jobs) {
  const std::string exe = self_executable();
  if (jobs <= 0) jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // This rank's share, in order.
  const int rank = mpi_rank(), ranks = mpi_size();
  std::vector<std::size_t> mine;
  for (std::size_t i = rank; i < runs.size(); i += ranks) mine.push_back(i);
  std::vector<int> started(runs.size(), 0);
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  bool passed_on = false;
  while (next < mine.size() || !running.empty()) {
    const int stop = stop_signal().load();
    if (stop && !passed_on) {
      for (const auto& entry : running) kill(entry.first, stop);
      passed_on = true;
    }
    while (!stop && next < mine.size() && static_cast<int>(running.size()) < jobs) {
      const ChildRun& run = runs[mine[next]];
      try {
        // Prepared under the directory's lock, held until the child has started (it waits for
        // its parent's lock, RunLock): nothing is touched in a directory a live run holds.
        const RunLock lock(run.directory);
        fs::remove(run.directory + "/summary.json");
        running[spawn(exe, run.args, run.directory + "/run.log")] = mine[next];
        started[mine[next]] = static_cast<int>(ChildStart::started);
      } catch (const DirectoryHeld& e) {
        std::fprintf(stderr, "brittle: not started: %s\n", e.what());
        started[mine[next]] = static_cast<int>(ChildStart::held);
      }
      ++next;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0 && errno == EINTR) continue;  // a signal: look at the flag again
    BRITTLE_CHECK(pid > 0, "waiting for the runs failed");
    running.erase(pid);
  }
  mpi_max(started);  // every rank learns what became of each run (one rank had it)
  std::vector<ChildStart> outcome;
  for (const int s : started) outcome.push_back(static_cast<ChildStart>(s));
  return outcome;
}

std::vector<std::string> run_or_reuse(const std::vector<ChildRun>& runs, bool reuse, int jobs,
                                      const std::string& batch) {
  std::vector<std::string> why(runs.size(), "not started: the " + batch + " was stopped");
  std::vector<ChildRun> children;
  std::vector<std::size_t> child_of;  // the entry of each child
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (reuse && finished_same_run(runs[i])) {
      why[i].clear();
      if (mpi_rank() == 0)
        std::fprintf(stderr, "brittle study: reusing %s\n", runs[i].directory.c_str());
    } else {
      children.push_back(runs[i]);
      child_of.push_back(i);
    }
  }
  const std::vector<ChildStart> started = run_children(children, jobs);
  for (std::size_t c = 0; c < children.size(); ++c) {
    if (started[c] == ChildStart::started) why[child_of[c]].clear();
    if (started[c] == ChildStart::held)
      why[child_of[c]] = "not started: another run holds " + children[c].directory + " (run.lock)";
  }
  return why;
}

std::optional<nlohmann::json> read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

bool finished_same_run(const ChildRun& run) {
  const auto summary = read_json(run.directory + "/summary.json");
  if (!summary || summary->value("status", std::string()) != "completed") return false;
  std::vector<std::string> sources;
  for (std::size_t i = 1; i < run.args.size(); ++i) {  // args[0] is "run"
    if (run.args[i] == "--out") break;
    if (run.args[i] == "--set" && i + 1 < run.args.size())
      sources.push_back("--set " + run.args[++i]);
    else
      sources.push_back(run.args[i]);
  }
  const auto it = summary->find("scene_sources");
  return it != summary->end() && it->is_array() && *it == nlohmann::json(sources);
}

}  // namespace brittle
