// Helpers of the tests that run the brittle executable: temporary directories, running it
// with captured output (to completion or in the background), reading files.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace brittle_test {

/// Whether this build runs under AddressSanitizer (GCC defines __SANITIZE_ADDRESS__, clang
/// answers __has_feature): timings are not checked there.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

namespace fs = std::filesystem;

/// The minimal valid scene: only the load is required.
inline constexpr const char* kLoad = "[loading]\nsigma_over_sigmac = 0.6\n";

/// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "brittle_test_XXXXXX").string();
    const char* made = mkdtemp(pattern.data());
    if (!made) throw std::runtime_error("mkdtemp failed");
    path_ = made;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// Writes `text` to `name` (relative to the dir, subdirectories created) and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path operator/(const std::string& name) const { return path_ / name; }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct Result {
  int exit_code = -1;
  std::string out, err;
};

/// Runs the brittle executable with `args`, stdout and stderr captured to files in `dir`.
inline Result run_brittle(const TempDir& dir, const std::vector<std::string>& args) {
  std::string cmd = quote(BRITTLE_EXE);
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict) about "literal" + std::string&&.
  for (const auto& a : args) cmd.append(" ").append(quote(a));
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  cmd.append(" >").append(quote(out.string()));
  cmd.append(" 2>").append(quote(err.string())).append(" </dev/null");
  const int status = std::system(cmd.c_str());
  Result r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

/// The brittle executable started in the background with `args` (stdout and stderr to files in
/// `dir`); wait() returns its exit code (128 + signal if a signal ended it).
class Background {
 public:
  /// `launcher`: a command that starts brittle (e.g. mpiexec -np 2), its program first.
  Background(const TempDir& dir, const std::vector<std::string>& args,
             const std::vector<std::string>& env = {},
             const std::vector<std::string>& launcher = {})
      : out_(dir / "bg_stdout.txt"), err_(dir / "bg_stderr.txt") {
    std::vector<std::string> argv_s = launcher;
    argv_s.push_back(BRITTLE_EXE);
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_s;
    for (char** e = environ; *e; ++e) env_s.emplace_back(*e);
    env_s.insert(env_s.end(), env.begin(), env.end());
    std::vector<char*> envp;
    for (auto& e : env_s) envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    const int rc = posix_spawn(&pid_, argv_s[0].c_str(), &actions, nullptr, argv.data(),
                               envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("posix_spawn failed");
  }
  ~Background() {
    if (pid_ > 0) kill(pid_, SIGKILL), wait();
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  void signal(int sig) const { kill(pid_, sig); }
  int wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::string err() const { return read_text(err_); }

 private:
  pid_t pid_ = -1;
  fs::path out_, err_;
};

}  // namespace brittle_test
