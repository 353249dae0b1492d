// Load sweeps: parallel `brittle run` processes, results collected into sweep.csv.
#include "sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include "child_runs.hpp"
#include "command_line.hpp"
#include "error.hpp"
#include "figures.hpp"
#include "lists.hpp"
#include "output.hpp"
#include "parallel.hpp"
#include "paths.hpp"
#include "scene_options.hpp"
#include "stop_signal.hpp"

namespace fs = std::filesystem;

namespace brittle {
namespace {

double number(const std::string& token, const std::string& text) {
  const auto v = parse_number(token);
  BRITTLE_CHECK(v, "--loads '", text, "': '", token,
                "' is not a number (expected first:last:step or a comma list)");
  return *v;
}

std::string load_label(double load) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << load;
  return s.str();
}

}  // namespace

std::vector<double> parse_loads(const std::string& text) {
  std::vector<double> loads;
  const bool is_range = text.find(':') != std::string::npos;  // first:last:step
  std::string fields = text;
  std::replace(fields.begin(), fields.end(), ':', ',');
  const std::vector<std::string> range = list_words(fields);
  if (is_range) {
    BRITTLE_CHECK(range.size() == 3 && text.find(',') == std::string::npos, "--loads '", text,
                  "': expected first:last:step or a comma list");
    const double first = number(range[0], text), last = number(range[1], text),
                 step = number(range[2], text);
    BRITTLE_CHECK(step > 0 && last >= first, "--loads '", text,
                  "': expected first:last:step with step > 0 and last >= first");
    const long n = std::lround(std::floor((last - first) / step + 1e-9));
    for (long k = 0; k <= n; ++k) loads.push_back(first + k * step);
  } else {
    for (const std::string& token : range) loads.push_back(number(token, text));
  }
  BRITTLE_CHECK(!loads.empty(), "--loads '", text, "': no load given");
  for (double l : loads)
    BRITTLE_CHECK(l > 0 && l < 3, "--loads '", text, "': load ", l,
                  " is out of range (expected 0 < sigma/sigma_c < 3)");
  return loads;
}

SweepPoint read_run(const std::string& directory) {
  SweepPoint p;
  p.directory = directory;
  const std::string summary = directory + "/summary.json";
  if (!fs::exists(summary)) {
    p.status = "failed: no summary.json (see run.log)";
    return p;
  }
  nlohmann::json json;
  try {
    std::ifstream in(summary);
    json = nlohmann::json::parse(in);
  } catch (const std::exception& e) {  // the row stays, marked: the other loads still count
    p.status = error_message("failed: '", summary, "' cannot be read: ", e.what());
    return p;
  }
  // null (not finite when written) and missing keys read as NaN
  auto value = [&](const char* key) {
    const auto it = json.find(key);
    return it != json.end() && it->is_number() ? it->get<double>() : std::nan("");
  };
  p.status = json.value("status", std::string("unknown"));
  p.load = value("sigma_over_sigmac");
  p.W = value("W");
  p.W_clamped = value("W_clamped");
  if (const auto n = json.find("nucleated_cracks"); n != json.end() && n->is_array())
    p.nucleations = static_cast<int>(n->size());
  if (const auto w = json.find("crack_speed_window_end"); w != json.end() && w->is_string())
    p.window_end = w->get<std::string>();
  if (const auto f = json.find("super_cp_front"); f != json.end() && f->is_object()) {
    const auto field = [&](const char* key) {
      return f->contains(key) && (*f)[key].is_number() ? (*f)[key].get<double>() : std::nan("");
    };
    p.notes = error_message("failure front faster than c_p at t = ", field("t") * 1e6, " us (",
                            std::lround(field("speed")), " m/s > ", std::lround(field("c_p")),
                            " m/s): not a physical crack");
  }
  p.fitted_speed = value("crack_speed");
  p.r2 = value("crack_speed_r2");
  const double samples = value("crack_speed_samples");
  p.samples = std::isfinite(samples) ? static_cast<int>(samples) : 0;
  p.tip_x = value("tip_x");
  p.zhou_speed = value("zhou_speed");
  // Arrest: the crack stopped short of the far edge. Read the tip series: its farthest split
  // (max_split_x; tip_x in files before it) did not move over the last 5 us of the run
  // although it is more than the speed window's margin away from x = L, or nothing split.
  const double reach = value("speed_stop_x");
  std::ifstream csv(directory + "/crack_tip.csv");
  std::string line;
  std::getline(csv, line);
  std::vector<std::pair<double, double>> tip;
  while (std::getline(csv, line)) {
    const NumberList cells = parse_number_list(line);
    if (!cells.bad && cells.values.size() >= 6)
      tip.emplace_back(cells.values[0], cells.values[5]);
    else if (!cells.bad && cells.values.size() >= 2)
      tip.emplace_back(cells.values[0], cells.values[1]);
  }
  if (!tip.empty() && tip.back().second < reach) {
    const double t_end = tip.back().first;
    double x_then = tip.front().second;
    for (const auto& [t, x] : tip)
      if (t <= t_end - 5e-6) x_then = x;
    p.arrested = tip.back().second <= x_then;
  }
  p.speed = p.arrested ? 0.0 : p.fitted_speed;
  return p;
}

void write_sweep_csv(const std::string& path, const std::vector<SweepPoint>& points) {
  std::ostringstream out;
  out << "sigma_over_sigmac,W,W_clamped,speed,fitted_speed,fit_r2,fit_samples,window_end,arrested,"
         "tip_x,nucleations,zhou_speed,status,notes,directory\n"
      << std::setprecision(10);
  for (const SweepPoint& p : points) {
    std::string status;  // a quoted CSV field: quotes doubled
    for (char c : p.status) status += c == '"' ? std::string("\"\"") : std::string(1, c);
    out << p.load << ',' << p.W << ',' << p.W_clamped << ',' << p.speed << ',' << p.fitted_speed
        << ',' << p.r2 << ',' << p.samples << ',' << p.window_end << ','
        << (p.arrested ? "yes" : "no") << ',' << p.tip_x << ',' << p.nucleations << ','
        << p.zhou_speed << ',' << '"' << status << '"' << ',' << '"' << p.notes << '"' << ','
        << p.directory << '\n';
  }
  write_file_atomically(path, out.str());
}

std::vector<SweepPoint> run_sweep(const SweepOptions& o) {
  BRITTLE_CHECK(!o.scenes.empty(), "brittle sweep: no scene file given");
  std::vector<ChildRun> runs;
  for (const double load : o.loads) {
    ChildRun run;
    run.directory = o.out + "/load_" + load_label(load);
    std::vector<std::string> sets = o.sets;
    sets.insert(sets.end(), {"loading.sigma_over_sigmac=" + load_label(load), "run.threads=1"});
    if (!o.frames) sets.push_back("output.vtu=false");
    // Every run's scene is loaded and checked before anything starts or is written: a bad
    // file or key is one error now, not one failed run per load.
    try {
      load_scene(o.scenes, sets);
    } catch (const Error& e) {
      throw Error(error_message("brittle sweep: load ", load_label(load), ": ", e.what()));
    }
    run.args = {"run"};
    run.args.insert(run.args.end(), o.scenes.begin(), o.scenes.end());
    for (const std::string& s : sets) run.args.insert(run.args.end(), {"--set", s});
    run.args.insert(run.args.end(), {"--out", run.directory});
    runs.push_back(std::move(run));
  }
  fs::create_directories(o.out);
  const std::vector<ChildStart> started = run_children(runs, o.jobs);
  std::vector<SweepPoint> points;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (started[i] == ChildStart::started) {
      points.push_back(read_run(runs[i].directory));
      if (std::isnan(points.back().load)) points.back().load = o.loads[i];  // no summary
    } else {
      SweepPoint p;
      p.load = o.loads[i];
      p.status = "not started: the sweep was stopped";
      if (started[i] == ChildStart::held) {
        p.status = "not started: another run holds " + runs[i].directory + " (run.lock)";
        p.directory = runs[i].directory;
      }
      points.push_back(p);
    }
  }
  if (mpi_rank() == 0) write_sweep_csv(o.out + "/sweep.csv", points);
  return points;
}

int sweep_command(const std::vector<std::string>& args) {
  namespace po = boost::program_options;
  SweepOptions o;
  std::string loads;
  std::string frames = "no";
  po::options_description opts("brittle sweep options");
  opts.add_options()("help,h", "show this help")(
      "loads", po::value(&loads)->required(),
      "loads sigma/sigma_c: first:last:step (last included) or a comma list")(
      "set", po::value(&o.sets)->composing(), "override one key: section.key=value (repeatable)")(
      "jobs", po::value(&o.jobs)->default_value(0), "runs at once (0 = number of cores)")(
      "out", po::value(&o.out)->default_value("out/sweep"),
      "directory (created) for sweep.csv and one run directory per load")(
      "frames", po::value(&frames)->implicit_value("yes"),
      "yes: every run writes its VTU frames (output.vtu = true); no (default): none");
  po::options_description hidden;
  hidden.add_options()("scene", po::value(&o.scenes)->composing(), "scene INI files");
  auto vm = parse_command_line(args, opts, hidden, "scene");
  if (vm.count("help")) {
    print_command_help(std::cout,
                       "usage: brittle sweep SCENE.ini [MORE.ini ...] --loads 0.4:1.0:0.05 "
                       "[--set k=v ...] [--jobs N] [--out DIR] [--frames yes|no]",
                       "Runs the scene once per load sigma/sigma_c (child processes, --jobs at "
                       "once) into DIR/load_0.400/... and tabulates the crack speeds in "
                       "DIR/sweep.csv (columns: docs/output.md). Every load's scene is checked "
                       "before any run starts.",
                       opts);
    return 0;
  }
  po::notify(vm);
  o.frames = parse_switch("--frames", frames);
  o.loads = parse_loads(loads);
  BRITTLE_CHECK(o.jobs >= 0, "--jobs ", o.jobs, " is out of range (expected >= 0)");
  install_stop_handlers();
  const auto points = run_sweep(o);
  if (mpi_rank() != 0) return stop_signal().load() ? 128 + stop_signal().load() : 0;
  bool all_completed = true;
  for (const SweepPoint& p : points) {
    std::printf("sigma/sigma_c = %.3f  W = %7.0f N/m  speed = %6.1f m/s  (fit r2 %.3f)%s  Zhou fit "
                "%5.1f m/s  %s%s%s\n",
                p.load, p.W, p.speed, p.r2, p.arrested ? "  arrested" : "", p.zhou_speed,
                p.status.c_str(), p.notes.empty() ? "" : "; ", p.notes.c_str());
    all_completed = all_completed && p.status == "completed";
  }
  std::string label = fs::path(o.scenes.front()).stem().string();
  for (std::size_t i = 1; i < o.scenes.size(); ++i) label += "+" + fs::path(o.scenes[i]).stem().string();
  write_speed_chart(o.out + "/sweep.png", "Crack speed against strain energy: " + label,
                    {{label, points}});
  std::printf("wrote %s/sweep.csv and sweep.png\n", o.out.c_str());
  if (const int stop = stop_signal().load()) {
    std::fprintf(stderr, "brittle: sweep stopped; the runs that were running stopped with a "
                 "checkpoint (brittle run --resume DIR continues one)\n");
    return 128 + stop;
  }
  BRITTLE_CHECK(all_completed, "sweep: some runs failed (see sweep.csv and their run.log)");
  return 0;
}

}  // namespace brittle
