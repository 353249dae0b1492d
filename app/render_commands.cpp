// `brittle render`, `brittle figure` and the [render] observer of `brittle run`
// (docs/rendering.md).
#include "render_commands.hpp"

#include "isolated_read.hpp"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
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

/// The name a single frame shows: the scene files' stems in order ("cm + damage"), else the run
/// directory's name. Not the directory with the files: the same scene run into two directories
/// (serial and decomposed, test_parallel) gives the same pictures.
std::string scene_name(const std::vector<std::string>& sources, const std::string& run_directory) {
  std::string name;
  for (const std::string& s : sources)
    if (!s.starts_with("--set ")) name += (name.empty() ? "" : " + ") + fs::path(s).stem().string();
  if (!name.empty()) return name;
  fs::path dir = fs::absolute(run_directory).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();
  return dir.filename().string();
}

/// What a run directory's scene.ini (written by every run: the resolved scene) says about the
/// run: its scene's name (the "# source:" lines) and whether damage was on (damage.beta1 > 0).
struct RunInfo {
  std::string name;
  std::optional<bool> damage;  ///< nothing: no scene.ini, decide from the frames
};

RunInfo read_run_info(const std::string& run_directory) {
  RunInfo info;
  std::vector<std::string> sources;
  std::ifstream in(fs::path(run_directory) / "scene.ini");
  std::string line, section;
  while (std::getline(in, line)) {
    if (line.starts_with("# source: "))
      sources.push_back(line.substr(10));
    else if (line.starts_with("["))
      section = line.substr(1, line.find(']') - 1);
    else if (section == "damage" && line.starts_with("beta1 = "))
      info.damage = std::strtod(line.c_str() + 8, nullptr) > 0;
  }
  info.name = scene_name(sources, run_directory);
  return info;
}

/// A frame has damage when its Omega is anywhere above 0. Omega never decreases (5.2), so a
/// run's last frame tells for all earlier ones.
bool has_damage(vtkUnstructuredGrid& grid) {
  vtkDataArray* omega = grid.GetCellData()->GetArray(field::damage);
  if (!omega) return false;
  double range[2];
  omega->GetRange(range, 0);
  return range[1] > 0;
}

constexpr const char* kNoDamage = "no damage in this run: damage frames skipped";

/// The fields to draw: `fields` without damage when the run has none (the caller says so on
/// stderr once it has succeeded: an error stays the only line).
std::vector<Field> drop_damage(const std::vector<Field>& fields, bool damage) {
  std::vector<Field> kept;
  for (Field f : fields)
    if (damage || f != Field::damage) kept.push_back(f);
  return kept;
}

/// Renders frames during a run at render.times, one PNG per field.
class RenderObserver : public Observer {
 public:
  explicit RenderObserver(const Scene& scene)
      : renderer_(scene.render, scene_name(scene.sources, scene.output.directory)),
        times_(scene.render.times),
        fields_(drop_damage(fields_of(scene.render.fields), scene.damage.enabled())),
        skipped_damage_(fields_.size() < scene.render.fields.size()),
        directory_(render_directory(scene)) {}

  void on_frame(const Simulation& sim) override {
    // Frames fire within half a step of their time (Simulation::run); a frame may cover several.
    const std::size_t first = next_;
    while (next_ < times_.size() && sim.time() >= times_[next_] - 0.5 * sim.dt()) ++next_;
    if (next_ == first) return;
    const auto t0 = std::chrono::steady_clock::now();
    // A decomposed run: every rank's piece joined on rank 0, which draws (collective).
    const vtkSmartPointer<vtkUnstructuredGrid> grid = whole_grid(sim);
    if (!grid) return;
    for (Field f : fields_) {
      auto image = renderer_.render(*grid, f);
      render::write_png(*image, directory_ + "/" + render::frame_file_name(f, times_[next_ - 1]));
      ++frames_;
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  /// The render times up to the checkpoint were rendered by the run that wrote it.
  void on_resume(const Simulation& sim) override {
    while (next_ < times_.size() && sim.time() >= times_[next_] - 0.5 * sim.dt()) ++next_;
  }

  void on_finish(const Simulation& sim, const RunSummary&) override {
    if (sim.halo() && sim.halo()->rank() != 0) return;  // rank 0 drew the frames
    if (skipped_damage_) std::cerr << "brittle: " << kNoDamage << "\n";
    if (frames_ > 0)
      std::fprintf(stderr, "brittle: %d PNG frames in %s (%.3f s per frame)\n", frames_,
                   directory_.c_str(), seconds_ / frames_);
  }

 private:
  render::FrameRenderer renderer_;
  std::vector<double> times_;
  std::vector<Field> fields_;
  bool skipped_damage_;
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

  // Damage only where the run has it: its scene.ini says, else its last frame (has_damage).
  const std::string run_directory = fs::path(pvd).parent_path().string();
  const RunInfo run = read_run_info(run_directory.empty() ? "." : run_directory);
  bool damage = true;
  if (std::find(fields.begin(), fields.end(), Field::damage) != fields.end() && run.damage)
    damage = *run.damage;
  else if (std::find(fields.begin(), fields.end(), Field::damage) != fields.end())
    damage = has_damage(*read_frame(
        std::max_element(picks.begin(), picks.end(), [](auto& a, auto& b) {
          return a.second->time < b.second->time;
        })->second->file));
  const std::vector<Field> shown = drop_damage(fields, damage);

  render::FrameRenderer renderer(scene.render, run.name);
  double seconds = 0;
  int frames = 0;
  std::vector<std::vector<vtkSmartPointer<vtkImageData>>> cells(shown.size());
  for (const auto& [t, entry] : picks) {
    if (shown.empty()) break;
    auto grid = read_frame(entry->file);
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < shown.size(); ++i) {
      auto image = renderer.render(*grid, shown[i]);
      render::write_png(*image, directory + "/" + render::frame_file_name(shown[i], t));
      if (!panel_path.empty())
        cells[i].push_back(renderer.render(*grid, shown[i], render::Layout::cell));
      ++frames;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::cout << "wrote " << frames << " PNG frames to " << directory << " ("
            << (frames ? seconds / frames : 0) << " s per frame)\n";
  if (shown.size() < fields.size()) std::cerr << "brittle: " << kNoDamage << "\n";
  if (!panel_path.empty() && shown.empty())
    std::cerr << "brittle: no panel written to " << panel_path << ": no field left to show\n";
  if (!panel_path.empty() && !shown.empty()) {
    // One colour bar per coloured row, right of it (crack rows have none): not one per frame.
    std::vector<std::vector<vtkImageData*>> raw(shown.size());
    std::vector<std::string> rows, columns;
    std::vector<vtkSmartPointer<vtkImageData>> bar_images;
    std::vector<render::PanelBar> bars;
    const bool coloured =
        std::any_of(shown.begin(), shown.end(), [](Field f) { return f != Field::crack; });
    for (std::size_t i = 0; i < shown.size(); ++i) {
      rows.push_back(shown.size() == 1          ? ""
                     : shown[i] == Field::sigma1 ? "sigma1"
                     : shown[i] == Field::damage ? "Omega"
                                                  : "crack");
      for (auto& image : cells[i]) raw[i].push_back(image);
      if (!coloured) continue;
      const int bar_w = renderer.colour_bar_width(), h = scene.render.height;
      bar_images.push_back(shown[i] == Field::crack ? render::text_image(" ", bar_w, h, 12)
                                                    : renderer.colour_bar(shown[i], bar_w, h));
      bars.push_back({bar_images.back(), 1});
    }
    for (const auto& pick : picks) columns.push_back(error_message(pick.first * 1e6, " us"));
    auto composed = render::panel(raw, rows, columns, title, bars);
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
                       "paper's Figs. 7-10 (with a fracture.criterion other than nodal-stress: the "
                       "branching runs and Figs. 9-10 only).",
                       opts);
    return 0;
  }
  po::notify(vm);
  check_out_directory("figure", out, "fig07.png ... fig10.png");
  BRITTLE_CHECK(!files.empty(), "brittle figure: no scene file given (", usage, ")");

  // (Each run sets its own mode; the base is read in branching mode, which every criterion
  // accepts.)
  std::vector<std::string> base_sets = sets;
  base_sets.push_back("fracture.mode=branching");
  const Scene base = load_scene(files, base_sets);
  std::vector<double> times = base.render.times;
  if (times.empty()) times = {1e-6, 15e-6, 30e-6};
  const std::string times_text = join_numbers(times);

  // Straight mode has one criterion, the normal stress on y = 0 (6.7): with another
  // fracture.criterion (facet, energy: branching mode only) the straight runs and Figs. 7-8
  // are not made.
  const bool straight = base.fracture.criterion == FractureParams::Criterion::nodal_stress;
  std::vector<std::string> modes = {"straight", "branching"};
  if (!straight) {
    modes.erase(modes.begin());
    std::cerr << "brittle figure: fracture.criterion is not nodal-stress, which straight mode "
                 "needs: branching runs only, fig07.png and fig08.png skipped\n";
  }
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

  // Frames: [mode][field][row][column], rendered once per stored grid as panel cells (the
  // figure has one colour bar). Omega only when the runs have damage.
  const bool damage = base.damage.enabled();
  std::vector<Field> fields = {Field::sigma1};
  if (damage) fields.push_back(Field::damage);
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
        for (Field f : fields) {
          frames[{mode, static_cast<int>(f), r, c}] =
              renderer.render(*grid, f, render::Layout::cell);
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
  const int rows = static_cast<int>(times.size());
  std::vector<std::string> written;
  for (const Figure& fig : figures) {
    if (!damage && fig.field == Field::damage) continue;
    if (!straight && fig.mode == "straight") continue;
    std::vector<std::vector<vtkImageData*>> cells(times.size());
    for (std::size_t r = 0; r < times.size(); ++r)
      for (std::size_t c = 0; c < loads.size(); ++c)
        cells[r].push_back(frames[{fig.mode, static_cast<int>(fig.field), r, c}]);
    auto bar = renderer.colour_bar(fig.field, renderer.colour_bar_width(),
                                   rows * base.render.height);
    auto image = render::panel(cells, row_titles, column_titles, fig.title, {{bar, rows}});
    render::write_png(*image, out + "/" + fig.file);
    written.push_back(fig.file);
  }
  std::cout << "wrote";
  for (const std::string& f : written) std::cout << " " << out << "/" << f;
  std::cout << " (" << count << " frames, " << seconds / std::max(count, 1) << " s per frame)\n";
  if (!damage)
    std::cerr << "brittle figure: no damage in these runs (damage.beta1 = 0): fig08.png and "
                 "fig10.png (Omega) skipped\n";
  return 0;
}

}  // namespace brittle
