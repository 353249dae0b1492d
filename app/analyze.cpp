// `brittle analyze RUN_DIR`: crack pattern metrics from a run's event catalogue.
#include "analyze.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <tuple>
#include <fstream>
#include <nlohmann/json.hpp>

#include "chart.hpp"
#include "command_line.hpp"
#include "crack_pattern.hpp"
#include "error.hpp"

namespace brittle {
namespace {

/// A finite number at `key` of `j`, else an error naming the file and key.
double number_at(const nlohmann::json& j, const char* key, const std::string& file) {
  const auto it = j.find(key);
  BRITTLE_CHECK(it != j.end() && it->is_number() && std::isfinite(it->get<double>()), file,
                ": '", key, "' is missing or not a finite number");
  return it->get<double>();
}

/// events_energy.png, events_rate.png and, with sensors, spectra.png (docs/acoustic_emission.md).
void draw_charts(const std::string& dir, const CrackPattern& p) {
  const EnergyDistribution& d = p.distribution;
  if (!d.count.empty()) {
    render::ChartSeries bins{"link failures per bin", {}, {}, render::ChartSeries::Style::points};
    for (std::size_t i = 0; i < d.count.size(); ++i)
      if (d.count[i] > 0) {
        bins.x.push_back(std::log10(std::sqrt(d.bin_low[i] * d.bin_high[i])));
        bins.y.push_back(std::log10(static_cast<double>(d.count[i])));
      }
    char title[160];
    std::snprintf(title, sizeof title,
                  "Link-failure energies: dN/dE ~ E^-%.2f (r2 %.2f over %d bins; %s)", d.exponent,
                  d.r2, d.fitted_bins, d.power_law ? "a power law fits" : "no power law");
    render::write_chart_png(dir + "/events_energy.png", title, "log10 energy [J]", "log10 events per bin (5/decade)",
          {bins});
  }
  if (!d.rate.empty()) {
    render::ChartSeries rate{"link failures", {}, {}, render::ChartSeries::Style::line};
    for (std::size_t i = 0; i < d.rate.size(); ++i)
      rate.x.push_back(1e6 * d.rate_time[i]), rate.y.push_back(1e-6 * d.rate[i]);
    render::write_chart_png(dir + "/events_rate.png", "Event rate", "time [us]", "link failures per us", {rate});
  }
  std::ifstream in(dir + "/spectra.csv");
  std::string header;
  if (!in || !std::getline(in, header)) return;
  std::vector<std::string> names;
  std::istringstream h(header);
  for (std::string name; std::getline(h, name, ',');) names.push_back(name);
  std::vector<render::ChartSeries> series(names.size() > 1 ? names.size() - 1 : 0);
  const std::array<std::array<unsigned char, 3>, 4> colours = {
      {{0, 0, 0}, {200, 30, 30}, {30, 90, 200}, {30, 150, 60}}};
  for (std::size_t i = 0; i < series.size(); ++i)
    series[i] = {names[i + 1], {}, {}, render::ChartSeries::Style::line, colours[i % 4]};
  for (std::string line; std::getline(in, line);) {
    std::istringstream row(line);
    std::string field;
    std::getline(row, field, ',');
    const double f = std::stod(field) * 1e-3;
    for (auto& s : series) std::getline(row, field, ','), s.x.push_back(f), s.y.push_back(std::stod(field));
  }
  if (!series.empty())
    render::write_chart_png(dir + "/spectra.png", "Sensor amplitude spectra (Hann window)", "frequency [kHz]",
          "amplitude [m/s]", series);
}

}  // namespace

int analyze_command(const std::vector<std::string>& args) {
  namespace po = boost::program_options;
  po::options_description opts("brittle analyze options");
  std::vector<std::string> dirs;
  double min_length = -1;
  opts.add_options()("help,h", "show this help")(
      "min-branch-length", po::value(&min_length),
      "tracks shorter than this are spurs [m] (default: the run's "
      "fracture.min_branch_length)");
  po::options_description hidden;
  hidden.add_options()("run", po::value(&dirs)->composing(), "run directory");
  auto vm = parse_command_line(args, opts, hidden, "run");
  if (vm.count("help")) {
    print_command_help(std::cout, "usage: brittle analyze RUN_DIR [--min-branch-length L]",
                       "Rebuilds the crack pattern of a finished run from its events: writes "
                       "RUN_DIR/branches.csv, RUN_DIR/pattern.json and the acoustic-emission "
                       "charts (docs/crack_pattern.md, docs/acoustic_emission.md).",
                       opts);
    return 0;
  }
  po::notify(vm);
  BRITTLE_CHECK(dirs.size() == 1, "brittle analyze: expected one run directory (usage: brittle "
                                  "analyze RUN_DIR [--min-branch-length L])");
  const std::string dir = dirs.front();
  const std::string file = dir + "/pattern.json";
  nlohmann::json j;
  {
    std::ifstream in(file);
    BRITTLE_CHECK(in, "brittle analyze: '", file,
                  "' cannot be read (expected the directory of a fracture run)");
    try {
      j = nlohmann::json::parse(in);
    } catch (const std::exception&) {
      throw Error(error_message("brittle analyze: '", file, "' is not valid JSON"));
    }
  }
  BRITTLE_CHECK(j.contains("tracker") && j["tracker"].is_object() && j.contains("seeds") &&
                    j["seeds"].is_array() && j.contains("area_against_advance") &&
                    j["area_against_advance"].is_array(),
                "brittle analyze: '", file, "' lacks 'tracker', 'seeds' or 'area_against_advance'");
  const nlohmann::json& tracker = j["tracker"];
  const double join = number_at(tracker, "join", file);
  const double separation = number_at(tracker, "separation", file);
  const double T = number_at(tracker, "thickness", file);
  // v_R for the speed notes; a pattern.json from before it was kept has none: no notes
  const double v_R = tracker.contains("rayleigh_speed") && tracker["rayleigh_speed"].is_number()
                         ? tracker["rayleigh_speed"].get<double>()
                         : std::numeric_limits<double>::quiet_NaN();
  if (min_length < 0) min_length = number_at(j, "min_branch_length", file);
  BRITTLE_CHECK(std::isfinite(min_length), "--min-branch-length ", min_length,
                " is out of range (expected >= 0 m)");
  std::vector<FrontSeed> seeds;
  for (const auto& s : j["seeds"]) {
    BRITTLE_CHECK(s.is_array() && s.size() == 3 && s[0].is_number() && s[1].is_number() &&
                      s[2].is_number(),
                  "brittle analyze: '", file, "': a seed is not [x, y, angle_deg]");
    seeds.push_back({s[0].get<double>(), s[1].get<double>(), s[2].get<double>()});
  }
  std::vector<TipSample> tips;  // the leading tip's advance at the run's sample times
  for (const auto& a : j["area_against_advance"]) {
    BRITTLE_CHECK(a.is_array() && a.size() == 4 && a[0].is_number() && a[1].is_number(),
                  "brittle analyze: '", file, "': an area sample is not [t, advance, area, ratio]");
    tips.push_back({a[0].get<double>(), 0.0, 0.0, 0, a[1].get<double>()});
  }
  const std::vector<CrackEvent> events = read_events_csv(dir + "/events.csv");
  const CrackFronts fronts = fronts_from_events(events, join, separation, seeds);
  const CrackPattern p = crack_pattern(fronts, events, tips, T, min_length, v_R);
  write_pattern(dir, p);
  draw_charts(dir, p);
  std::printf("%zu branches (%d spurs shorter than %.3g m), %zu branching points, %zu "
              "nucleations, %ld splits, %ld link failures; wrote %s/branches.csv, pattern.json "
              "and charts\n",
              p.branches.size(), p.spurs, min_length, p.branchings.size(), p.nucleations.size(),
              p.splits, p.link_failures, dir.c_str());
  for (const Branch& b : p.branches) {
    std::printf("  tip %d (%s): from (%.2f, %.2f) mm at %.2f us, %.2f mm at %.1f deg, %.0f m/s "
                "along the path, %.0f m/s away from its start\n",
                b.tip, b.origin.c_str(), 1e3 * b.x_start, 1e3 * b.y_start, 1e6 * b.t_start,
                1e3 * b.length, b.angle_deg, b.speed, b.chord_speed);
    if (!b.speed_note.empty()) std::printf("    note: %s\n", b.speed_note.c_str());
  }
  return 0;
}

}  // namespace brittle
