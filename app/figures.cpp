// Figs. 5-6: load sweeps drawn as crack speed against W over the Zhou et al. fit (1.1).
#include "figures.hpp"

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "chart.hpp"
#include "command_line.hpp"
#include "crack_tip.hpp"
#include "error.hpp"
#include "lists.hpp"
#include "parallel.hpp"
#include "paths.hpp"
#include "render_commands.hpp"
#include "scene.hpp"

namespace fs = std::filesystem;
namespace po = boost::program_options;

namespace brittle {
namespace {

using render::ChartSeries;

const std::array<std::array<unsigned char, 3>, 5> kColors = {
    {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}, {255, 127, 14}}};

/// Reads a finished sweep directory back (every load_* run directory in it, in load order).
SweepSeries read_sweep(const std::string& directory, const std::string& label) {
  BRITTLE_CHECK(fs::is_directory(directory), "chart: sweep directory '", directory,
                "' does not exist");
  std::vector<std::string> runs;
  for (const auto& entry : fs::directory_iterator(directory))
    if (entry.is_directory() && entry.path().filename().string().rfind("load_", 0) == 0)
      runs.push_back(entry.path().string());
  std::sort(runs.begin(), runs.end());
  BRITTLE_CHECK(!runs.empty(), "chart: '", directory, "' holds no load_* run directories");
  SweepSeries s{label, {}};
  for (const std::string& run : runs) s.points.push_back(read_run(run));
  return s;
}

/// All points of several series, one CSV (series label first).
void write_series_csv(const std::string& path, const std::vector<SweepSeries>& series) {
  std::ofstream out(path);
  BRITTLE_CHECK(out, "chart: cannot write '", path, "'");
  out << "series,sigma_over_sigmac,W,W_clamped,speed,fitted_speed,fit_r2,arrested,zhou_speed,"
         "relative_error,nucleations,window_end,notes\n"
      << std::setprecision(8);
  for (const SweepSeries& s : series)
    for (const SweepPoint& p : s.points)
      out << s.label << ',' << p.load << ',' << p.W << ',' << p.W_clamped << ',' << p.speed << ','
          << p.fitted_speed << ',' << p.r2 << ',' << (p.arrested ? "yes" : "no") << ','
          << p.zhou_speed << ','
          << (p.zhou_speed > 0 ? (p.speed - p.zhou_speed) / p.zhou_speed : 0.0) << ','
          << p.nucleations << ',' << p.window_end << ",\"" << p.notes << "\"\n";
}

/// Mean |v - v_fit| / v_fit over the loads in [lo, hi] (an arrest counts as speed 0).
double mean_fit_error(const SweepSeries& s, double lo, double hi) {
  double sum = 0;
  int n = 0;
  for (const SweepPoint& p : s.points)
    if (p.load >= lo - 1e-9 && p.load <= hi + 1e-9 && p.zhou_speed > 0 && std::isfinite(p.speed))
      sum += std::abs(p.speed - p.zhou_speed) / p.zhou_speed, ++n;
  return n ? sum / n : std::nan("");
}

/// One line per series: its mean distance from the Zhou fit over 0.5-1.0 sigma_c.
std::string fit_table(const std::vector<SweepSeries>& series) {
  std::ostringstream t;
  t << std::fixed << std::setprecision(1);
  for (const SweepSeries& s : series)
    t << "  " << std::left << std::setw(28) << s.label
      << " mean |v - v_fit|/v_fit (0.5-1.0): " << 100 * mean_fit_error(s, 0.5, 1.0) << " %\n";
  return t.str();
}

}  // namespace

void write_speed_chart(const std::string& path, const std::string& title,
                       const std::vector<SweepSeries>& series) {
  const DamageParams damage;  // v_inf, v_R and (6.6) as the paper gives them
  const double v_R = damage.v_R, v_damped = std::sqrt(1.0 - damage.limit()) * v_R;
  const double W_max = 16000.0;
  std::vector<ChartSeries> lines;
  ChartSeries fit{"Zhou et al. fit (1.1)", {}, {}, ChartSeries::Style::line, {0, 0, 0}, 0};
  for (double W = 1000.0; W <= W_max; W += 50.0) fit.x.push_back(W), fit.y.push_back(zhou_speed(W));
  lines.push_back(fit);
  lines.push_back(
      {"Rayleigh speed", {0, W_max}, {v_R, v_R}, ChartSeries::Style::dashed, {90, 90, 90}, 0});
  lines.push_back({"damped Rayleigh sqrt(1-Omega_d0) v_R",
                   {0, W_max},
                   {v_damped, v_damped},
                   ChartSeries::Style::dashed,
                   {160, 160, 160},
                   0});
  for (std::size_t i = 0; i < series.size(); ++i) {
    ChartSeries s{
        series[i].label,    {}, {}, ChartSeries::Style::points, kColors[i % kColors.size()],
        static_cast<int>(i)};
    for (const SweepPoint& p : series[i].points)
      if (p.status == "completed" && std::isfinite(p.speed))
        s.x.push_back(p.W), s.y.push_back(p.speed);
    lines.push_back(s);
  }
  render::ChartAxes axes;
  axes.title = title;
  axes.x_title = "W = H sigma^2 / (2E)  [N/m]";
  axes.y_title = "crack speed  [m/s]";
  axes.x_min = 0, axes.x_max = W_max, axes.y_min = 0, axes.y_max = 1100;
  render::write_chart_png(path, axes, lines);
}

int chart_command(const std::vector<std::string>& args) {
  std::vector<std::string> sweeps;
  std::string out, title = "Crack speed against strain energy";
  po::options_description opts("brittle chart options");
  opts.add_options()("help,h", "show this help")(
      "out", po::value(&out)->required(),
      "directory (created) for crack_speed.png and crack_speed.csv (the chart's points)")(
      "title", po::value(&title), "chart title");
  po::options_description hidden;
  hidden.add_options()("sweep", po::value(&sweeps)->composing(), "sweep directories");
  auto vm = parse_command_line(args, opts, hidden, "sweep");
  if (vm.count("help")) {
    print_command_help(std::cout, "usage: brittle chart SWEEP_DIR[=LABEL] ... --out DIR [--title T]",
                       "Draws the crack speed of finished sweeps against the strain energy W, over "
                       "the Zhou et al. fit (the paper's Figs. 5-6): DIR/crack_speed.png, and "
                       "DIR/crack_speed.csv with every point (columns: docs/output.md).",
                       opts);
    return 0;
  }
  po::notify(vm);
  BRITTLE_CHECK(!sweeps.empty(), "brittle chart: no sweep directory given");
  check_out_directory("chart", out, "crack_speed.png and crack_speed.csv");
  std::vector<SweepSeries> series;
  for (const std::string& s : sweeps) {
    const auto eq = s.find('=');
    const std::string dir = s.substr(0, eq);
    series.push_back(read_sweep(
        dir, eq == std::string::npos ? fs::path(dir).filename().string() : s.substr(eq + 1)));
  }
  fs::create_directories(out);
  write_speed_chart(out + "/crack_speed.png", title, series);
  write_series_csv(out + "/crack_speed.csv", series);
  std::printf("wrote %s/crack_speed.png and crack_speed.csv\n", out.c_str());
  return 0;
}

namespace {

/// The columns of a run's tip_fields.csv by header name (empty when the run has none).
std::map<std::string, std::vector<double>> read_tip_fields(const std::string& dir) {
  std::map<std::string, std::vector<double>> columns;
  const std::string csv = (fs::path(dir) / "tip_fields.csv").string();
  std::ifstream in(csv);
  std::string line;
  if (!in || !std::getline(in, line)) return columns;
  const std::vector<std::string> names = list_words(line);
  for (int row = 2; std::getline(in, line); ++row) {
    const std::vector<std::string> cells = list_words(line);
    BRITTLE_CHECK(cells.size() == names.size(), "brittle tips: '", csv, "', line ", row,
                  ": expected ", names.size(), " columns");
    for (std::size_t k = 0; k < names.size(); ++k) {
      const auto v = parse_number(cells[k]);
      columns[names[k]].push_back(v ? *v : std::numeric_limits<double>::quiet_NaN());
    }
  }
  return columns;
}

/// tip_fields.png: the angle of the hoop-stress maximum of every running tip, and
/// energy_flux.png: G per unit tip advance and per unit new crack area over 2 gamma
/// (docs/branching.md), and the dynamic J over 2 gamma (docs/j-integral.md), one colour per
/// run.
void write_tip_field_charts(const std::string& out, const std::vector<std::string>& runs) {
  std::vector<render::ChartSeries> angles, fluxes;
  double t_max = 1, g_max = 3;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto eq = runs[i].find('=');
    const std::string dir = runs[i].substr(0, eq);
    const std::string label =
        eq == std::string::npos ? fs::path(dir).filename().string() : runs[i].substr(eq + 1);
    auto c = read_tip_fields(dir);
    if (c["time"].empty()) continue;
    const auto color = kColors[i % kColors.size()];
    render::ChartSeries angle{label, {}, {}, render::ChartSeries::Style::points, color, 0};
    render::ChartSeries tip{label + ": G per tip advance", {}, {},
                            render::ChartSeries::Style::line, color, 0};
    render::ChartSeries area{label + ": G per new area", {}, {},
                             render::ChartSeries::Style::dashed, color, 0};
    // The flux through the J ring (3-10 mm) into the first tip of each row (the run's tip);
    // absent from runs written before the column was.
    render::ChartSeries j{label + ": J, 3-10 mm ring",        {},    {},
                          render::ChartSeries::Style::points, color, 0};
    const std::vector<double>& J = c["J_over_2gamma"];
    for (std::size_t r = 0; r < c["time"].size(); ++r) {
      const double t = c["time"][r] * 1e6, two_gamma = c["two_gamma"][r];
      t_max = std::max(t_max, t);
      if (std::isfinite(c["hoop_theta_max_deg"][r]))
        angle.x.push_back(t), angle.y.push_back(c["hoop_theta_max_deg"][r]);
      if (r > 0 && c["time"][r] == c["time"][r - 1]) continue;  // G: once per energy row
      if (r < J.size() && std::isfinite(J[r])) {
        j.x.push_back(t), j.y.push_back(J[r]);
        g_max = std::max(g_max, std::min(J[r], 10.0));
      }
      for (auto [series, key] : {std::pair{&tip, "G_tip_advance"}, {&area, "G_new_area"}})
        if (std::isfinite(c[key][r])) {
          series->x.push_back(t), series->y.push_back(c[key][r] / two_gamma);
          g_max = std::max(g_max, std::min(c[key][r] / two_gamma, 10.0));
        }
    }
    angles.push_back(std::move(angle));
    fluxes.push_back(std::move(tip));
    fluxes.push_back(std::move(area));
    if (!j.x.empty()) fluxes.push_back(std::move(j));
  }
  if (angles.empty()) return;
  for (double level : {1.0, 2.0})
    fluxes.push_back({level == 1 ? "2 gamma" : "2 x 2 gamma", {0, t_max}, {level, level},
                      render::ChartSeries::Style::dashed, {0, 0, 0}, 0});
  render::ChartAxes a;
  a.title = "Angle of the hoop-stress maximum at 3 element sizes from each running tip";
  a.x_title = "t  [us]";
  a.y_title = "theta_max  [deg from the tip's direction]";
  a.x_min = 0, a.x_max = t_max, a.y_min = -95, a.y_max = 95;
  a.legend = render::ChartAxes::Corner::bottom_left;
  render::write_chart_png(out + "/tip_fields.png", a, angles);
  render::ChartAxes f;
  f.title = "Energy into crack growth over 2 gamma (1 us windows) and J / 2 gamma";
  f.x_title = "t  [us]";
  f.y_title = "G / (2 gamma)";
  f.x_min = 0, f.x_max = t_max, f.y_min = 0, f.y_max = 1.1 * g_max;
  f.legend = render::ChartAxes::Corner::top_left;
  render::write_chart_png(out + "/energy_flux.png", f, fluxes);
  std::printf("wrote %s/tip_fields.png and %s/energy_flux.png\n", out.c_str(), out.c_str());
}

}  // namespace

int tips_command(const std::vector<std::string>& args) {
  std::vector<std::string> runs;
  std::string out, title = "Speed of the leading crack tip";
  double rayleigh = 0, window = 1e-6;
  po::options_description opts("brittle tips options");
  opts.add_options()("help,h", "show this help")(
      "out", po::value(&out)->required(), "directory (created) for tip_speed.png")(
      "title", po::value(&title), "chart title")(
      "rayleigh", po::value(&rayleigh), "draw the Rayleigh speed [m/s] as a dashed line");
  po::options_description hidden;
  hidden.add_options()("run", po::value(&runs)->composing(), "run directories");
  auto vm = parse_command_line(args, opts, hidden, "run");
  if (vm.count("help")) {
    print_command_help(std::cout,
                       "usage: brittle tips RUN_DIR[=LABEL] ... --out DIR [--title T] "
                       "[--rayleigh V]",
                       "Draws the leading crack tip's speed against time from each run's "
                       "crack_tip.csv (a 1 us moving average): DIR/tip_speed.png; from "
                       "tip_fields.csv, the angle of the hoop-stress maximum around every "
                       "running tip (DIR/tip_fields.png) and the energy into crack growth "
                       "over 2 gamma (DIR/energy_flux.png; docs/branching.md).",
                       opts);
    return 0;
  }
  po::notify(vm);
  BRITTLE_CHECK(!runs.empty(), "brittle tips: no run directory given");
  check_out_directory("tips", out, "tip_speed.png");
  std::vector<render::ChartSeries> lines;
  double t_max = 0, v_max = rayleigh;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto eq = runs[i].find('=');
    const std::string dir = runs[i].substr(0, eq);
    const std::string csv = (fs::path(dir) / "crack_tip.csv").string();
    std::ifstream in(csv);
    BRITTLE_CHECK(in.good(), "brittle tips: '", csv,
                  "' cannot be opened (expected a run directory "
                  "of a run with fracture)");
    render::ChartSeries s{
        eq == std::string::npos ? fs::path(dir).filename().string() : runs[i].substr(eq + 1),
        {},
        {},
        render::ChartSeries::Style::line,
        kColors[i % kColors.size()],
        0};
    std::string line;
    std::getline(in, line);  // time,tip_x,tip_y,splits,speed
    for (int row = 2; std::getline(in, line); ++row) {
      const std::vector<std::string> cells = list_words(line);
      const bool tip_row = cells.size() == 5 || cells.size() == 7;  // (7: since max_split_x)
      const auto t = tip_row ? parse_number(cells[0]) : std::nullopt;
      const auto v = tip_row ? parse_number(cells[4]) : std::nullopt;
      BRITTLE_CHECK(t && v, "brittle tips: '", csv, "', line ", row,
                    ": expected time,tip_x,tip_y,splits,speed");
      s.x.push_back(*t * 1e6), s.y.push_back(*v);
      t_max = std::max(t_max, *t * 1e6);
    }
    // Moving average over |t - t_i| <= window: the leading tip advances in bursts of splits.
    std::vector<double> smooth(s.y.size());
    for (std::size_t k = 0, lo = 0, hi = 0; k < s.y.size(); ++k) {
      while (s.x[lo] < s.x[k] - window * 1e6) ++lo;
      while (hi < s.x.size() && s.x[hi] <= s.x[k] + window * 1e6) ++hi;
      double sum = 0;
      for (std::size_t m = lo; m < hi; ++m) sum += s.y[m];
      smooth[k] = sum / static_cast<double>(hi - lo);
      v_max = std::max(v_max, smooth[k]);
    }
    s.y = std::move(smooth);
    lines.push_back(std::move(s));
  }
  if (rayleigh > 0)
    lines.push_back({"Rayleigh speed",
                     {0, t_max},
                     {rayleigh, rayleigh},
                     render::ChartSeries::Style::dashed,
                     {0, 0, 0},
                     0});
  render::ChartAxes axes;
  axes.title = title;
  axes.x_title = "t  [us]";
  axes.y_title = "tip speed  [m/s]";
  axes.x_min = 0, axes.x_max = t_max > 0 ? t_max : 1, axes.y_min = 0;
  axes.y_max = rayleigh > 0 ? std::min(1.6 * rayleigh, 1.1 * v_max) : v_max > 0 ? 1.1 * v_max : 1;
  fs::create_directories(out);
  render::write_chart_png(out + "/tip_speed.png", axes, lines);
  std::printf("wrote %s/tip_speed.png\n", out.c_str());
  write_tip_field_charts(out, runs);
  return 0;
}

namespace {
/// The last non-empty line of a text file ("" if none): a failed run's one-line error.
std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}
}  // namespace

int reproduce_command(const std::vector<std::string>& args) {
  std::string out = "out/figures", scenes, loads = "0.4:1.0:0.05", meshes = "cm,rm";
  int jobs = 0;
  std::string frames_word = "yes";
  po::options_description opts("brittle reproduce options");
  opts.add_options()("help,h", "show this help")(
      "out", po::value(&out),
      "directory (created) for the figures, their CSVs, sweeps/ and runs/ (default out/figures)")(
      "scenes", po::value(&scenes),
      "directory of the shipped scenes (default: the installed or source tree's scenes/)")(
      "loads", po::value(&loads), "loads of every sweep (first:last:step or a list)")(
      "meshes", po::value(&meshes), "meshes to sweep: cm, rm or cm,rm")(
      "jobs", po::value(&jobs), "runs at once (0 = number of cores)")(
      "frames", po::value(&frames_word)->implicit_value("yes"),
      "yes (default): also run and draw Figs. 7-10 from VTU frames; no: Figs. 5-6 only");
  po::options_description hidden;  // the earlier spelling
  hidden.add_options()("no-frames", "same as --frames no");
  auto vm = parse_command_line(args, opts, hidden, nullptr);
  if (vm.count("help")) {
    print_command_help(std::cout,
                       "usage: brittle reproduce [--out DIR] [--loads SPEC] [--meshes cm,rm] "
                       "[--jobs N] [--frames yes|no]",
                       "Regenerates the paper's figures: the eight load sweeps of Figs. 5-6 "
                       "(fig05.png, fig06b.png with their CSVs and fit_errors.txt) and, unless "
                       "--frames no, Figs. 7-10 (fig07.png ... fig10.png). docs/reproduction.md.",
                       opts);
    return 0;
  }
  po::notify(vm);
  const bool no_frames = vm.count("no-frames") || !parse_switch("--frames", frames_word);
  check_out_directory("reproduce", out, "fig05.png ... fig10.png");
  // Options first: bad input stops the command before anything is read or written.
  const std::vector<std::string> chosen = list_words(meshes);
  BRITTLE_CHECK(!chosen.empty(), "--meshes '", meshes,
                "': no mesh given (expected cm, rm or cm,rm)");
  for (const std::string& mesh : chosen)
    BRITTLE_CHECK(mesh == "cm" || mesh == "rm", "--meshes '", meshes, "': '", mesh,
                  "' is not a mesh (expected cm, rm or cm,rm)");
  const auto wanted = [&](const std::string& mesh) {
    return std::find(chosen.begin(), chosen.end(), mesh) != chosen.end();
  };
  const std::vector<double> load_list = parse_loads(loads);
  if (scenes.empty()) scenes = bundled_scenes_directory();
  for (const char* file :
       {"cm.ini", "rm.ini", "rate-dependent.ini", "rate-dependent-calibrated.ini", "damage.ini"})
    BRITTLE_CHECK(fs::is_regular_file(fs::path(scenes) / file), "brittle reproduce: scene '",
                  (fs::path(scenes) / file).string(),
                  "' does not exist (expected the shipped "
                  "scenes in --scenes DIR)");
  const auto start = std::chrono::steady_clock::now();
  fs::create_directories(out);
  // The sweeps: {label, mesh, overlays}; Fig. 5 (= Fig. 6a) without damage, Fig. 6b with it,
  // plus the calibrated rate-dependent links on RM (docs/reproduction.md).
  struct Spec {
    std::string label, mesh;
    std::vector<std::string> overlays;
    bool damage;
  };
  std::vector<Spec> specs;
  for (bool damage : {false, true})
    for (const char* law : {"RI", "RD"})
      for (const char* mesh : {"cm", "rm"}) {
        if (!wanted(mesh)) continue;
        std::vector<std::string> overlays;
        if (std::string(law) == "RD") overlays.push_back("rate-dependent.ini");
        if (damage) overlays.push_back("damage.ini");
        specs.push_back({std::string(law) + "-" + (std::string(mesh) == "cm" ? "CM" : "RM"), mesh,
                         overlays, damage});
      }
  if (wanted("rm"))
    specs.push_back(
        {"RD-RM calibrated", "rm", {"rate-dependent-calibrated.ini", "damage.ini"}, true});
  std::vector<SweepSeries> without, with;
  for (const Spec& spec : specs) {
    SweepOptions o;
    o.scenes = {scenes + "/" + spec.mesh + ".ini"};
    for (const std::string& overlay : spec.overlays) o.scenes.push_back(scenes + "/" + overlay);
    o.loads = load_list;
    o.jobs = jobs;
    std::string dir = spec.label + (spec.damage ? "-damage" : "");
    std::replace(dir.begin(), dir.end(), ' ', '-');
    o.out = out + "/sweeps/" + dir;
    std::fprintf(stderr, "brittle reproduce: sweep %s%s (%zu loads)\n", spec.label.c_str(),
                 spec.damage ? " with damage" : "", o.loads.size());
    std::vector<SweepPoint> points = run_sweep(o);
    // A failed run stops the command at once: a figure with holes, or "nan %" fit errors,
    // would hide it.
    for (std::size_t i = 0; i < points.size(); ++i)
      BRITTLE_CHECK(points[i].status == "completed", "brittle reproduce: sweep ", spec.label,
                    spec.damage ? " with damage" : "", ": the run at sigma/sigma_c = ", o.loads[i],
                    " (", points[i].directory, ") ", points[i].status, ": ",
                    last_line(points[i].directory + "/run.log"));
    (spec.damage ? with : without).push_back({spec.label, std::move(points)});
  }
  // Under mpirun every rank ran its share of each sweep; rank 0 draws and writes the rest.
  if (mpi_rank() != 0) return 0;
  write_speed_chart(out + "/fig05.png", "Fig. 5: RI and RD nodal cohesive forces, no damage",
                    without);
  write_series_csv(out + "/fig05.csv", without);
  write_speed_chart(out + "/fig06b.png", "Fig. 6b: RI and RD nodal cohesive forces with damage",
                    with);
  write_series_csv(out + "/fig06b.csv", with);
  const std::string table =
      "Fig. 5 (no damage):\n" + fit_table(without) + "Fig. 6b (damage):\n" + fit_table(with);
  std::ofstream(out + "/fit_errors.txt") << table;
  std::printf("%s", table.c_str());
  if (!no_frames) {
    // Figs. 7-10 are with damage (paper section 6), straight and branching, 60 % and 90 %.
    std::vector<std::string> figure_args = {
        scenes + "/cm.ini", scenes + "/damage.ini", "--out", out, "--runs", out + "/runs"};
    figure_command(figure_args);
  }
  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60.0;
  std::printf("wrote %s (fig05, fig06b%s) in %.1f min\n", out.c_str(),
              no_frames ? "" : ", fig07-fig10", minutes);
  return 0;
}

}  // namespace brittle
