// brittle from any working directory and after `cmake --install`: the shipped scenes are
// found (app/paths.cpp), and `brittle reproduce` stops at the first failed sweep with the reason.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// 'text' for the shell (appended piecewise: GCC 12 warns falsely (-Wrestrict) about
/// "literal" + std::string&&).
std::string shell_quoted(const std::string& text) {
  std::string q = "'";
  q.append(text).append("'");
  return q;
}

/// A shell line: the quoted program, then the rest.
std::string command(const std::string& program, const std::string& rest) {
  std::string c = shell_quoted(program);
  c.append(rest);
  return c;
}

/// Runs `command` (a shell line) in `cwd`, stdout and stderr captured.
Result run_in(const fs::path& cwd, const std::string& command) {
  const fs::path out = cwd / "stdout.txt", err = cwd / "stderr.txt";
  std::string line = "cd ";
  line.append(shell_quoted(cwd.string())).append(" && ").append(command);
  line.append(" >")
      .append(shell_quoted(out.string()))
      .append(" 2>")
      .append(shell_quoted(err.string()));
  line.append(" </dev/null");
  const int status = std::system(line.c_str());
  Result r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("brittle_install_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

const std::string kQuickReproduce =
    " reproduce --meshes cm --loads 0.9 --frames no --jobs 2 --out out";

// Outside the repository (a temporary directory as the working directory) reproduce finds the
// source tree's scenes and completes; its fit errors are numbers.
TEST(Reproduce, FindsTheShippedScenesFromAnyDirectory) {
  const fs::path dir = fresh_dir("anywhere");
  const Result r = run_in(dir, command(BRITTLE_EXE, kQuickReproduce));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string fit = read_text(dir / "out" / "fit_errors.txt");
  EXPECT_NE(fit.find("RI-CM"), std::string::npos) << fit;
  EXPECT_EQ(fit.find("nan"), std::string::npos) << fit;
  EXPECT_TRUE(fs::exists(dir / "out" / "fig05.png"));
}

// A sweep whose runs fail stops the command at once, naming the sweep, the load and the run's
// own error, with exit 2 and no figure.
TEST(Reproduce, StopsAtTheFirstFailedSweepWithTheReason) {
  const fs::path dir = fresh_dir("failing");
  fs::copy(fs::path(BRITTLE_SOURCE_DIR) / "scenes", dir / "scenes");
  std::ofstream(dir / "scenes" / "cm.ini", std::ios::app) << "\n[run]\nbogus_key = 1\n";
  const Result r = run_in(dir, command(BRITTLE_EXE, kQuickReproduce + " --scenes scenes"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sweep RI-CM"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bogus_key"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "fig05.png"));
  // A scenes directory without the shipped scenes is refused before anything runs.
  const Result missing = run_in(dir, command(BRITTLE_EXE, kQuickReproduce + " --scenes nowhere"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nowhere/cm.ini"), std::string::npos) << missing.err;
}

// Bad --meshes or --loads stop reproduce with one line naming the option, before it writes
// anything.
TEST(Reproduce, RejectsBadOptionsBeforeRunning) {
  const fs::path dir = fresh_dir("bad_options");
  for (const auto& [args, parts] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {" --meshes cm,xx", {"--meshes 'cm,xx'", "'xx' is not a mesh", "expected cm, rm"}},
           {" --meshes ,", {"--meshes ','", "no mesh given"}},
           {" --meshes cm --loads 0.4:x:0.1", {"--loads '0.4:x:0.1'", "'x' is not a number"}}}) {
    const Result r = run_in(dir, command(BRITTLE_EXE, " reproduce --out out" + args));
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not one line: " << r.err;
    for (const std::string& part : parts)
      EXPECT_NE(r.err.find(part), std::string::npos) << part << " not in " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// cmake --install puts bin/brittle and share/brittle/scenes under the prefix; the installed
// executable reports and uses the installed scenes from any directory.
TEST(Install, InstalledBrittleUsesTheInstalledScenes) {
  const fs::path dir = fresh_dir("prefix"), prefix = dir / "prefix";
  std::string args = " --install ";
  args.append(shell_quoted(BRITTLE_BINARY_DIR))
      .append(" --prefix ")
      .append(shell_quoted(prefix.string()));
  const Result install = run_in(dir, command(CMAKE_COMMAND, args));
  ASSERT_EQ(install.exit_code, 0) << install.err << install.out;
  const fs::path scenes = prefix / "share" / "brittle" / "scenes";
  for (const char* f : {"cm.ini", "rm.ini", "damage.ini", "branching.ini", "rate-dependent.ini",
                        "rate-dependent-calibrated.ini"})
    EXPECT_TRUE(fs::is_regular_file(scenes / f)) << f;
  const std::string exe = (prefix / "bin" / "brittle").string();
  const Result version = run_in(dir, command(exe, " --version"));
  ASSERT_EQ(version.exit_code, 0) << version.err;
  EXPECT_NE(version.out.find("shipped scenes: " + scenes.string()), std::string::npos)
      << version.out;
  const Result r = run_in(dir, command(exe, kQuickReproduce));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace
