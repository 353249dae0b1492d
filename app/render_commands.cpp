// `brittle render`, `brittle figure` and the [render] observer of `brittle run`
// (docs/rendering.md).
#include "render_commands.hpp"

#include "isolated_read.hpp"

#include <vtkImageData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>

#include "command_line.hpp"
#include "error.hpp"
#include "frame_renderer.hpp"
#include "image_tools.hpp"
#include "lists.hpp"
#include "output.hpp"
#include "plate_mesh.hpp"
#include "run_scene.hpp"
#include "scene_options.hpp"

namespace brittle {
namespace {

namespace po = boost::program_options;
namespace fs = std::filesystem;
using render::Field;

/// A stored frame is taken for a requested time when it is at most this far away.
constexpr double kTimeTolerance = 0.25e-6;  // [s]; frames fire within half a step of their time

std::vector<Field> fields_of(const std::vector<std::string>& words) {
  std::vector<Field> fields;
  for (const std::string& w : words) fields.push_back(render::parse_field(w));
  return fields;
}

std::string render_directory(const Scene& scene) {
  return scene.render.directory.empty() ? scene.output.directory + "/render"
                                        : scene.render.directory;
}

/// Times in s from an option value ("1e-6,15e-6 30e-6"), each >= 0.
std::vector<double> parse_times(const std::string& text, const std::string& option) {
  const NumberList list = parse_number_list(text);
  BRITTLE_CHECK(!list.bad, option, " '", text, "': '", list.bad.value_or(""),
                "' is not a time in s (expected e.g. 1e-6,15e-6,30e-6)");
  for (double t : list.values)
    BRITTLE_CHECK(t >= 0, option, " '", text, "': ", t, " is not a time in s (expected >= 0)");
  BRITTLE_CHECK(!list.values.empty(), option, " '", text, "': no times given");
  return list.values;
}

/// Scene files + --set overrides for their [render] keys only. The load is irrelevant to the
/// picture (labels take it from the frames) but a scene must have one to be valid.
Scene render_scene(const std::vector<std::string>& files, const std::vector<std::string>& sets) {
  std::vector<std::string> overrides = {"loading.sigma_over_sigmac=0.5"};
  overrides.insert(overrides.end(), sets.begin(), sets.end());
  return load_scene(files, overrides);
}

/// A frame read in a child process (isolated_read.hpp): a damaged file is a message, not a crash.
vtkSmartPointer<vtkUnstructuredGrid> read_frame(const std::string& path) {
  return read_vtu_isolated(path, "render: frame");
}

/// The stored frame nearest to `time`; throws when none is within kTimeTolerance.
const PvdEntry& frame_at(const std::vector<PvdEntry>& series, double time, const std::string& pvd) {
  BRITTLE_CHECK(!series.empty(), "render: time series '", pvd, "' has no frames");
  const auto nearest = std::min_element(series.begin(), series.end(), [&](auto& a, auto& b) {
    return std::abs(a.time - time) < std::abs(b.time - time);
  });
  BRITTLE_CHECK(std::abs(nearest->time - time) <= kTimeTolerance, "render: time series '", pvd,
                "' has no frame at t = ", time, " s (nearest: ", nearest->time, " s; frames from ",
                series.front().time, " to ", series.back().time, " s)");
  return *nearest;
}

/// Renders frames during a run at render.times, one PNG per field.
class RenderObserver : public Observer {
 public:
  explicit RenderObserver(const Scene& scene)
      : renderer_(scene.render),
        times_(scene.render.times),
        fields_(fields_of(scene.render.fields)),
        directory_(render_directory(scene)) {}

  void on_frame(const Simulation& sim) override {
    // Frames fire within half a step of their time (Simulation::run); a frame may cover several.
    const std::size_t first = next_;
    while (next_ < times_.size() && sim.time() >= times_[next_] - 0.5 * sim.dt()) ++next_;
    if (next_ == first) return;
    const auto t0 = std::chrono::steady_clock::now();
    for (Field f : fields_) {
      auto image = renderer_.render(*sim.grid().vtk(), f);
      render::write_png(*image, directory_ + "/" + render::frame_file_name(f, times_[next_ - 1]));
      ++frames_;
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  /// The render times up to the checkpoint were rendered by the run that wrote it.
  void on_resume(const Simulation& sim) override {
    while (next_ < times_.size() && sim.time() >= times_[next_] - 0.5 * sim.dt()) ++next_;
  }

  void on_finish(const Simulation&, const RunSummary&) override {
    if (frames_ > 0)
      std::fprintf(stderr, "brittle: %d PNG frames in %s (%.3f s per frame)\n", frames_,
                   directory_.c_str(), seconds_ / frames_);
  }

 private:
  render::FrameRenderer renderer_;
  std::vector<double> times_;
  std::vector<Field> fields_;
  std::string directory_;
  std::size_t next_ = 0;
  int frames_ = 0;
  double seconds_ = 0;
};

/// "60" for 0.6: the load as a whole percentage, for directory names and titles.
std::string percent(double load) {
  return std::to_string(static_cast<int>(std::lround(100 * load)));
}

}  // namespace


std::unique_ptr<Observer> make_render_observer(const Scene& scene) {
  if (scene.render.times.empty()) return nullptr;
  return std::make_unique<RenderObserver>(scene);
}

int render_command(const std::vector<std::string>& args) {
  const char* usage =
      "usage: brittle render RUN_DIR[/run.pvd] [SCENE.ini ...] [--times T1,T2,...] "
      "[--fields sigma1,damage,crack] [--set render.key=value ...] [--out DIR] "
      "[--panel NAME.png [--title T]]";
  po::options_description opts("brittle render options");
  std::vector<std::string> inputs, sets, field_options;
  std::string times_text, out, panel_path, title;
  opts.add_options()("help,h", "this help")(
      "times", po::value(&times_text),
      "times in s, comma separated (as render.times; default: render.times, else every stored "
      "frame)")("fields", po::value(&field_options)->composing(),
                "sigma1, damage and/or crack, comma separated or repeated (as render.fields; "
                "default: render.fields)")(
      "set", po::value(&sets)->composing(), "override one [render] key: render.key=value")(
      "out", po::value(&out),
      "directory (created) for the PNGs (as render.directory; default: render.directory, else "
      "RUN_DIR/render)")("panel", po::value(&panel_path),
                         "also lay the frames out in DIR/NAME.png: a row per field, a column "
                         "per time")("title", po::value(&title), "title across the top of the panel");
  po::options_description hidden;
  hidden.add_options()("input", po::value(&inputs)->composing(), "the .pvd, then scene files")(
      "field", po::value(&field_options)->composing(), "the earlier spelling of --fields");
  auto vm = parse_command_line(args, opts, hidden, "input");
  if (vm.count("help")) {
    print_command_help(std::cout, usage,
                       "Renders stored frames of a run (RUN_DIR or RUN_DIR/run.pvd; a decomposed "
                       "run's .pvtu pieces are joined) into PNGs named <field>_<time>us.png, in "
                       "the style of the [render] keys of the scene files given after it and of "
                       "--set (docs/rendering.md).",
                       opts);
    return 0;
  }
  po::notify(vm);
  BRITTLE_CHECK(!inputs.empty(), "brittle render: no time series given (", usage, ")");
  // A run directory means its run.pvd; links.pvd holds lines, not the plate's cells.
  std::string pvd = inputs.front();
  std::error_code ec;
  if (fs::is_directory(pvd, ec)) pvd = (fs::path(pvd) / "run.pvd").string();
  BRITTLE_CHECK(fs::path(pvd).filename() != "links.pvd", "brittle render '", pvd,
                "': the cohesive links are lines for ParaView, not frames of the plate "
                "(expected RUN_DIR or RUN_DIR/run.pvd)");
  const Scene scene = render_scene({inputs.begin() + 1, inputs.end()}, sets);
  const std::vector<PvdEntry> series = read_pvd(pvd);
  BRITTLE_CHECK(!series.empty(), "render: time series '", pvd, "' has no frames");

  std::vector<std::pair<double, const PvdEntry*>> picks;  // (name time, frame)
  if (!times_text.empty() || !scene.render.times.empty()) {
    const auto times = times_text.empty() ? scene.render.times : parse_times(times_text, "--times");
    for (double t : times) picks.emplace_back(t, &frame_at(series, t, pvd));
  } else {
    for (const PvdEntry& e : series) picks.emplace_back(e.time, &e);
  }
  const std::vector<Field> fields =
      fields_of(field_options.empty() ? scene.render.fields : list_words(field_options));
  const std::string directory = !out.empty() ? out
                                : !scene.render.directory.empty()
                                    ? scene.render.directory
                                    : (fs::path(pvd).parent_path() / "render").string();
  if (!out.empty()) check_out_directory("render", out, "the PNG frames");
  BRITTLE_CHECK(panel_path.empty() || fs::path(panel_path).extension() == ".png", "--panel '",
                panel_path, "': expected a PNG file name (NAME.png, written in the --out directory)");
  if (!panel_path.empty() && !fs::path(panel_path).has_parent_path())
    panel_path = (fs::path(directory) / panel_path).string();

  render::FrameRenderer renderer(scene.render);
  double seconds = 0;
  int frames = 0;
  std::vector<std::vector<vtkSmartPointer<vtkImageData>>> cells(fields.size());
  for (const auto& [t, entry] : picks) {
    auto grid = read_frame(entry->file);
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < fields.size(); ++i) {
      auto image = renderer.render(*grid, fields[i]);
      render::write_png(*image, directory + "/" + render::frame_file_name(fields[i], t));
      if (!panel_path.empty()) cells[i].push_back(image);
      ++frames;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::cout << "wrote " << frames << " PNG frames to " << directory << " ("
            << (frames ? seconds / frames : 0) << " s per frame)\n";
  if (!panel_path.empty()) {
    std::vector<std::vector<vtkImageData*>> raw(fields.size());
    std::vector<std::string> rows, columns;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      rows.push_back(fields.size() == 1          ? ""
                     : fields[i] == Field::sigma1 ? "sigma1"
                     : fields[i] == Field::damage ? "Omega"
                                                  : "crack");
      for (auto& image : cells[i]) raw[i].push_back(image);
    }
    for (const auto& pick : picks) columns.push_back(error_message(pick.first * 1e6, " us"));
    auto composed = render::panel(raw, rows, columns, title);
    render::write_png(*composed, panel_path);
    std::cout << "wrote " << panel_path << "\n";
  }
  return 0;
}

int figure_command(const std::vector<std::string>& args) {
  const char* usage =
      "usage: brittle figure SCENE.ini [MORE.ini ...] [--set section.key=value ...] "
      "[--runs DIR] [--out DIR] [--reuse]";
  po::options_description opts("brittle figure options");
  std::vector<std::string> files, sets;
  std::string runs = "out/figures", out = "figures";
  opts.add_options()("help,h", "this help")("set", po::value(&sets)->composing(),
                                            "override one key for all four runs")(
      "runs", po::value(&runs), "directory (created) for the four runs (default out/figures)")(
      "out", po::value(&out), "directory (created) for fig07.png ... fig10.png (default figures)")(
      "reuse", "take existing runs in --runs when they hold frames at every row time");
  po::options_description hidden;
  hidden.add_options()("scene", po::value(&files)->composing(), "base scene and overlays");
  auto vm = parse_command_line(args, opts, hidden, "scene");
  if (vm.count("help")) {
    print_command_help(std::cout, usage,
                       "Runs straight and branching fracture at 60 % and 90 % of sigma_c (rows: "
                       "render.times, default 1, 15, 30 us) and lays the frames out as the "
                       "paper's Figs. 7-10.",
                       opts);
    return 0;
  }
  po::notify(vm);
  check_out_directory("figure", out, "fig07.png ... fig10.png");
  BRITTLE_CHECK(!files.empty(), "brittle figure: no scene file given (", usage, ")");

  const Scene base = load_scene(files, sets);
  std::vector<double> times = base.render.times;
  if (times.empty()) times = {1e-6, 15e-6, 30e-6};
  const std::string times_text = join_numbers(times);

  const std::vector<std::string> modes = {"straight", "branching"};
  const std::vector<double> loads = {0.6, 0.9};
  // The four runs: base scene + mode + load, frames only at the row times, up to the last.
  std::map<std::pair<std::string, double>, std::vector<PvdEntry>> series;
  for (const std::string& mode : modes) {
    for (double load : loads) {
      const std::string dir = runs + "/" + mode + "-" + percent(load);
      const std::string pvd = dir + "/run.pvd";
      bool have = false;
      if (vm.count("reuse") && fs::is_regular_file(pvd)) {
        const auto stored = read_pvd(pvd);
        have = std::all_of(times.begin(), times.end(), [&](double t) {
          return std::any_of(stored.begin(), stored.end(), [&](const PvdEntry& e) {
            return std::abs(e.time - t) <= kTimeTolerance;
          });
        });
      }
      if (have) {
        std::cerr << "brittle figure: reusing " << dir << "\n";
      } else {
        std::vector<std::string> overrides = sets;
        overrides.insert(
            overrides.end(),
            {"fracture.mode=" + mode, "loading.sigma_over_sigmac=" + error_message(load),
             "output.directory=" + dir, "output.frame_times=" + times_text, "output.vtu=true",
             "run.end_time=" + error_message(times.back()), "render.times=",
             "run.stop_when_cut_through=false"});  // every row time has its frame
        const Scene scene = load_scene(files, overrides);
        std::cerr << "brittle figure: " << mode << " fracture at " << percent(load)
                  << " % of sigma_c -> " << dir << "\n";
        const RunSummary s = run_scene(scene);
        std::fprintf(stderr,
                     "brittle figure:   %s, %ld steps in %.1f s, %ld splits, tip x = %.2f mm\n",
                     s.status.c_str(), s.steps, s.wall_seconds, s.splits, s.tip_x * 1e3);
      }
      series[{mode, load}] = read_pvd(pvd);
    }
  }

  // Frames: [mode][field][row][column], rendered once per stored grid.
  render::FrameRenderer renderer(base.render);
  std::map<std::tuple<std::string, int, std::size_t, std::size_t>, vtkSmartPointer<vtkImageData>>
      frames;
  int count = 0;
  double seconds = 0;
  for (const std::string& mode : modes) {
    for (std::size_t c = 0; c < loads.size(); ++c) {
      const std::string pvd = runs + "/" + mode + "-" + percent(loads[c]) + "/run.pvd";
      for (std::size_t r = 0; r < times.size(); ++r) {
        auto grid = read_frame(frame_at(series[{mode, loads[c]}], times[r], pvd).file);
        const auto t0 = std::chrono::steady_clock::now();
        for (Field f : {Field::sigma1, Field::damage}) {
          frames[{mode, static_cast<int>(f), r, c}] = renderer.render(*grid, f);
          ++count;
        }
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
    }
  }

  std::vector<std::string> row_titles, column_titles;
  for (double t : times) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g µs", t * 1e6);
    row_titles.push_back(buf);
  }
  for (double load : loads) column_titles.push_back(percent(load) + " % of sigma_c");
  struct Figure {
    const char* file;
    std::string mode;
    Field field;
    const char* title;
  };
  const Figure figures[] = {
      {"fig07.png", "straight", Field::sigma1, "Fig. 7: sigma1 / sigma_c, straight crack"},
      {"fig08.png", "straight", Field::damage, "Fig. 8: Omega (damage), straight crack"},
      {"fig09.png", "branching", Field::sigma1, "Fig. 9: sigma1 / sigma_c, branching"},
      {"fig10.png", "branching", Field::damage, "Fig. 10: Omega (damage), branching"},
  };
  for (const Figure& fig : figures) {
    std::vector<std::vector<vtkImageData*>> cells(times.size());
    for (std::size_t r = 0; r < times.size(); ++r)
      for (std::size_t c = 0; c < loads.size(); ++c)
        cells[r].push_back(frames[{fig.mode, static_cast<int>(fig.field), r, c}]);
    auto image = render::panel(cells, row_titles, column_titles, fig.title);
    render::write_png(*image, out + "/" + fig.file);
  }
  std::cout << "wrote " << out << "/fig07.png ... fig10.png (" << count << " frames, "
            << seconds / std::max(count, 1) << " s per frame)\n";
  return 0;
}

}  // namespace brittle
