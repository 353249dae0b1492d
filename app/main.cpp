// brittle: command line entry point. Parses the scene, builds the simulation, attaches the
// writers, runs, and maps errors to a one-line message and a non-zero exit code.
#include <sys/stat.h>
#include <unistd.h>
#include <vtkObject.h>

#include <atomic>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "analyze.hpp"
#include "build_info.hpp"
#include "isolated_read.hpp"
#include "command_line.hpp"
#include "error.hpp"
#include "figures.hpp"
#include "parallel.hpp"
#include "paths.hpp"
#include "render_commands.hpp"
#include "run_scene.hpp"
#include "scene_options.hpp"
#include "simulation.hpp"
#include "stop_signal.hpp"
#include "study.hpp"
#include "sweep.hpp"

namespace po = boost::program_options;

namespace {

const char* kUsage =
    "usage: brittle COMMAND [ARGUMENTS] [--out DIR]    (brittle COMMAND --help: its options)\n"
    "\n"
    "  run SCENE.ini [MORE.ini ...] [--set section.key=value ...]   one simulation\n"
    "  run --resume RUN_DIR [--set run.end_time=T]                   continue a stopped run\n"
    "  render RUN_DIR [SCENE.ini ...] [--times T,...] [--fields F,...]  PNG frames of a run\n"
    "  analyze RUN_DIR                      crack pattern and acoustic emission of a run\n"
    "  sweep SCENE.ini ... --loads 0.4:1.0:0.05   one run per load, crack speeds\n"
    "  study mesh SCENE.ini ... --sizes 1e-3,500e-6   the mesh-size study\n"
    "  study ensemble SCENE.ini ... --vary mesh|strength|steps   N members: fork rate, medians\n"
    "  chart SWEEP_DIR[=LABEL] ...          crack speed against W of finished sweeps\n"
    "  tips RUN_DIR[=LABEL] ...             tip speed against time of finished runs\n"
    "  figure SCENE.ini [MORE.ini ...]      the paper's Figs. 7-10 for a scene\n"
    "  reproduce                            every reproduced figure (Figs. 5-10)\n"
    "  partition SCENE.ini --ranks 2,4,8    how mpirun would split the plate\n"
    "  --version\n"
    "\n"
    "--out is always a directory (created): the run's directory for run, one run directory per\n"
    "load or size for sweep and study, the PNGs for render, figure, chart and tips.\n"
    "Under mpirun, run, sweep, study and reproduce share the ranks (docs/parallel.md).\n";

/// Progress on stderr (steps, simulated time, crack tip, ETA): rewritten in place every 0.5 s
/// when stderr is a terminal, and as a line every `every` steps when asked (--progress: batch
/// logs). Everything but the in-place line also goes to <dir>/run.log, unless stderr already is
/// that file (a sweep's or study's child).
class Progress : public brittle::Observer {
 public:
  Progress(bool profile, long every) : profile_(profile), every_(every) {}
  ~Progress() override {
    if (log_) std::fclose(log_);
  }
  void on_start(const brittle::Simulation& sim) override {
    start_ = last_ = std::chrono::steady_clock::now();
    open_log(sim.scene().output.directory + "/run.log", sim.resumed());
    if (sim.resumed())
      say("brittle: resumed from the checkpoint at t = %.4g s, step %ld\n", sim.time(), sim.steps());
    const brittle::Halo* halo = sim.halo();  // a decomposed run: the whole grid's counts
    cells_ = sim.grid().corners() == 3 ? "triangle" : "tet";
    say("brittle: %lld nodes, %lld %ss%s, dt = %.4g s, %ld steps to %.4g s\n",
        static_cast<long long>(halo ? halo->initial_nodes() : sim.grid().num_points()),
        static_cast<long long>(halo ? halo->cells() : sim.grid().num_cells()), cells_,
        halo ? (" over " + std::to_string(halo->size()) + " ranks").c_str() : "", sim.dt(),
        static_cast<long>(sim.scene().run.end_time / sim.dt() + 0.5), sim.scene().run.end_time);
    if (const brittle::MassScaling& m = sim.mass_scaling(); m.target > 0)
      say("brittle: mass scaling to dt = %.4g s: %lld elements scaled, %.3g %% of the mass added "
          "(largest factor %.3g)\n",
          m.target, static_cast<long long>(m.elements), 100.0 * m.added / m.mass, m.largest);
  }
  void on_step(const brittle::Simulation& sim) override {
    const bool line = every_ > 0 && sim.steps() % every_ == 0;
    if (!tty_ && !line) return;
    const auto now = std::chrono::steady_clock::now();
    if (!line && now - last_ < std::chrono::milliseconds(500)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fraction = sim.time() / sim.scene().run.end_time;
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    const auto& f = sim.fracture();
    const double tip = f.splits() > 0 ? f.tip_x() : sim.scene().geometry.notch_depth;
    char text[160];
    std::snprintf(text, sizeof text,
                  "step %ld  t = %.3f us (%.0f%%)  tip x = %.2f mm  splits %ld  ETA %.0f s",
                  sim.steps(), sim.time() * 1e6, 100 * fraction, tip * 1e3, f.splits(), eta);
    if (line) {  // a whole line, in the log too
      if (tty_) std::fputc('\n', stderr);
      say("brittle: %s\n", text);
    } else {
      std::fprintf(stderr, "\r  %s   ", text);
    }
  }
  void on_warning(const brittle::Simulation&, const std::string& message) override {
    if (tty_) std::fputc('\n', stderr);
    say("brittle: warning: %s\n", message.c_str());
  }
  void on_finish(const brittle::Simulation& sim, const brittle::RunSummary& s) override {
    if (tty_) std::fputc('\n', stderr);
    say("brittle: %s: %ld steps in %.2f s, %.3g %s-updates/s\n", s.status.c_str(), s.steps,
        s.wall_seconds, s.tet_updates_per_second, cells_);
    if (profile_) {  // shares of the stepping time; output is outside it
      const double total = s.phases.stepping();
      std::string text = "brittle: phases (s, share of stepping):";
      for (const auto& [name, seconds] : s.phases.named()) {
        char part[96];
        std::snprintf(part, sizeof part, "%s %s %.3f (%.1f%%)",
                      name == std::string("kick_drift") ? "" : ",", name, seconds,
                      total > 0 ? 100 * seconds / total : 0.0);
        text += part;
      }
      say("%s\n", text.c_str());
    }
    if (s.stopped_at_cut)
      say("brittle: the crack cut the plate through at t = %.3f us, (%.2f, %.2f) mm: stopped at "
          "t = %.3f us of %.3f (--set run.stop_when_cut_through=false runs on)\n",
          s.cut_through.t * 1e6, s.cut_through.x * 1e3, s.cut_through.y * 1e3, s.time * 1e6,
          s.end_time * 1e6);
    if (s.splits == 0) return;
    const auto& fronts = sim.fronts();
    // A run too short for the speed window has no steady speed: say so, not "nan m/s".
    char speed[160];
    if (std::isfinite(s.crack_speed.speed))
      std::snprintf(speed, sizeof speed, "steady speed %.0f m/s", s.crack_speed.speed);
    else
      std::snprintf(speed, sizeof speed,
                    "no steady speed (fewer than 3 tip samples in the window from %.3g us)",
                    sim.scene().fracture.speed_window_start * 1e6);
    if (s.speed_window_end == "nucleation ahead")
      std::snprintf(speed + std::strlen(speed), sizeof speed - std::strlen(speed),
                    " up to a crack nucleated ahead");
    if (sim.scene().initial.state == brittle::InitialParams::State::prestress)
    {
      char farthest[64] = "";  // a crack nucleated ahead: SPEC 5's largest-x split is there
      if (s.max_split_x > s.tip_x + 1e-9)
        std::snprintf(farthest, sizeof farthest, ", farthest split at x = %.2f mm",
                      s.max_split_x * 1e3);
      say("brittle: %ld splits, tip at x = %.2f mm%s; %s (Zhou fit at W = %.0f N/m: %.0f m/s; "
          "W(1-nu^2) = %.0f N/m)\n",
          s.splits, s.tip_x * 1e3, farthest, speed, s.W, s.zhou_speed, s.W_clamped);
    }
    else
      say("brittle: %ld splits, leading tip at (%.2f, %.2f) mm; %s\n", s.splits, s.tip_x * 1e3,
          s.tip_y * 1e3, speed);
    say("brittle: %zu crack tips, %zu branchings, %zu nucleations (summary.json)\n",
        fronts.tips().size(), fronts.branchings().size(), fronts.nucleations().size());
  }

 private:
  /// To stderr and to the log.
  void say(const char* format, ...) __attribute__((format(printf, 2, 3))) {
    char text[2048];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof text, format, args);
    va_end(args);
    std::fputs(text, stderr);
    if (log_) std::fputs(text, log_), std::fflush(log_);
  }
  void open_log(const std::string& path, bool append) {
    struct stat err{}, file{};
    if (::fstat(STDERR_FILENO, &err) == 0 && ::stat(path.c_str(), &file) == 0 &&
        err.st_dev == file.st_dev && err.st_ino == file.st_ino)
      return;  // stderr is the log already
    log_ = std::fopen(path.c_str(), append ? "a" : "w");  // (a log that cannot open: none)
  }
  bool profile_;
  long every_;
  bool tty_ = isatty(STDERR_FILENO);
  const char* cells_ = "tet";  // what the counts count: tets, or a 2D body's triangles
  std::FILE* log_ = nullptr;
  std::chrono::steady_clock::time_point start_, last_;
};

int finish_run(const brittle::RunSummary& summary, const std::string& directory) {
  std::cout << "wrote " << directory << " (" << summary.status << ")\n";
  if (summary.status != "interrupted") return 0;
  std::cerr << "brittle: stopped at t = " << summary.time << " s (step " << summary.steps
            << "); checkpoint " << summary.checkpoint << "; continue with: "
            << (brittle::launched_by_mpi()
                    ? "mpirun -np " + std::to_string(brittle::mpi_size()) + " "
                    : std::string())
            << "brittle run --resume " << directory << "\n";
  return 128 + brittle::stop_signal().load();
}


int run_command(const std::vector<std::string>& args) {
  po::options_description opts("brittle run options");
  std::vector<std::string> files, sets;
  std::string out;
  opts.add_options()("help,h", "list every scene key with its default, unit and meaning")(
      "set", po::value(&sets)->composing(), "override one key: section.key=value (repeatable)")(
      "out", po::value(&out), "directory (created) of the run (as output.directory)")(
      "profile", "print the wall time of each phase of the step (also in summary.json)")(
      "progress", po::value<long>()->implicit_value(100),
      "print a progress line every N steps (default 100), also when stderr is not a terminal "
      "(batch logs); run.log gets them too")(
      "dry-run", "mesh and check the scene, print counts, dt, steps, frames and estimates of "
                 "memory, disk and time; write nothing")(
      "show-scene",
      "print the resolved scene (every key after the files, --set and --out; what the run "
      "writes as DIR/scene.ini) and write nothing")(
      "resume", po::value<std::string>(),
      "continue the run in DIR from DIR/checkpoint.bin (with --set run.end_time=T to extend "
      "it); no scene files");
  po::options_description hidden;
  hidden.add_options()("scene", po::value(&files)->composing(), "scene INI files");
  auto vm = brittle::parse_command_line(args, opts, hidden, "scene");
  if (vm.count("help")) {
    brittle::print_command_help(
        std::cout,
        "usage: brittle run SCENE.ini [MORE.ini ...] [--set section.key=value ...] [--out DIR]\n"
        "       brittle run --resume RUN_DIR [--set run.end_time=T]",
        "Runs one simulation. Later scene files override earlier ones, --set overrides them "
        "all. The run directory gets scene.ini, summary.json, run.log, the CSVs and the frames "
        "(docs/output.md). Under mpirun the run is decomposed over the ranks (docs/parallel.md).",
        opts);
    std::cout << "\nScene keys (INI sections [section], key = value):\n";
    brittle::print_scene_keys(std::cout);
    return 0;
  }
  po::notify(vm);
  const long every = vm.count("progress") ? vm["progress"].as<long>() : 0;
  BRITTLE_CHECK(every >= 0, "--progress ", every, ": expected a number of steps >= 1");
  Progress progress(vm.count("profile") > 0, every);
  const bool decomposed = brittle::launched_by_mpi();  // mpirun -np N brittle run
  if (decomposed) brittle::begin_decomposed_run();
  if (vm.count("resume")) {
    const std::string dir = vm["resume"].as<std::string>();
    BRITTLE_CHECK(files.empty() && out.empty() && !vm.count("dry-run"), "brittle run --resume ",
                  dir, ": scene files, --out and --dry-run do not go with --resume (the scene is "
                  "the checkpoint's; expected only --set run.end_time=T / run.threads=N)");
    brittle::install_stop_handlers();
    if (decomposed) {  // every rank its piece (docs/checkpoint.md)
      brittle::Scene scene = brittle::resume_scene(dir, sets);
      const brittle::RunSummary s =
          brittle::run_decomposed(scene, {&progress}, &brittle::stop_signal(), true);
      if (brittle::mpi_rank() != 0)
        return s.status == "interrupted" ? 128 + brittle::stop_signal().load() : 0;
      return finish_run(s, dir);
    }
    return finish_run(brittle::resume_run(dir, sets, {&progress}, &brittle::stop_signal()), dir);
  }
  BRITTLE_CHECK(!files.empty(), "brittle run: no scene file given (",
                "usage: brittle run "
                "SCENE.ini [MORE.ini ...] [--set section.key=value ...] [--out DIR])");
  brittle::Scene scene = brittle::load_scene(files, sets);
  if (!out.empty()) scene.output.directory = out;
  if (vm.count("show-scene")) {
    std::cout << brittle::scene_ini(scene);
    return 0;
  }
  if (vm.count("dry-run")) {  // under mpirun: rank 0 reports every rank's part
    if (brittle::mpi_rank() == 0) brittle::dry_run(scene, std::cout, brittle::mpi_size());
    return 0;
  }
  brittle::install_stop_handlers();
  if (decomposed) {
    const brittle::RunSummary s =
        brittle::run_decomposed(scene, {&progress}, &brittle::stop_signal());
    if (brittle::mpi_rank() != 0) return s.status == "interrupted" ? 128 + brittle::stop_signal().load() : 0;
    return finish_run(s, scene.output.directory);
  }
  return finish_run(brittle::run_scene(scene, {&progress}, &brittle::stop_signal()), scene.output.directory);
}

}  // namespace

int main(int argc, char** argv) {
  // VTK's own multi-line error log would break the one-line error contract: every VTK
  // failure that matters is turned into a brittle::Error by the code that called VTK.
  vtkObject::GlobalWarningDisplayOff();
  try {
    brittle::MpiSession mpi(argc, argv);  // MPI only under mpirun (docs/parallel.md)
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
      std::cerr << kUsage;
      return 2;
    }
    if (args[0] == "--version" || args[0] == "version") {
      const brittle::BuildInfo& build = brittle::build_info();
      std::cout << "brittle " << build.version << " (commit " << build.commit << ", "
                << build.compiler << ", " << build.build_type << " " << build.flags << ")\n";
      try {
        std::cout << "shipped scenes: " << brittle::bundled_scenes_directory() << "\n";
      } catch (const brittle::Error&) {
        std::cout << "shipped scenes: not found\n";
      }
      return 0;
    }
    if (args[0] == "--help" || args[0] == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (args[0] == "run") return run_command({args.begin() + 1, args.end()});
    if (args[0] == "render") return brittle::render_command({args.begin() + 1, args.end()});
    if (args[0] == "figure") return brittle::figure_command({args.begin() + 1, args.end()});
    if (args[0] == "chart") return brittle::chart_command({args.begin() + 1, args.end()});
    if (args[0] == "tips") return brittle::tips_command({args.begin() + 1, args.end()});
    if (args[0] == "analyze") return brittle::analyze_command({args.begin() + 1, args.end()});
    if (args[0] == "reproduce") return brittle::reproduce_command({args.begin() + 1, args.end()});
    if (args[0] == "sweep") return brittle::sweep_command({args.begin() + 1, args.end()});
    if (args[0] == "study") return brittle::study_command({args.begin() + 1, args.end()});
    if (args[0] == "partition")
      return brittle::partition_command({args.begin() + 1, args.end()});
    std::cerr << "brittle: error: unknown command '" << args[0] << "'\n" << kUsage;
    return 2;
  } catch (const std::exception& e) {  // control bytes of a binary input are escaped
    if (!brittle::silent_rank())  // a decomposed run: every rank has the same error
      std::cerr << "brittle: error: " << brittle::escape_control(e.what()) << "\n";
    return 2;
  } catch (...) {  // nothing may end the program with std::terminate
    std::cerr << "brittle: error: an unknown failure (a library threw something that is not an "
                 "exception)\n";
    return 2;
  }
}
