// `brittle study mesh`: one scene at several element sizes, in several cases, as child runs;
// the results read back from each run's summary.json, pattern.json and sensors.json.
#include "study.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <tuple>

#include <boost/program_options.hpp>
#include <vtkImageData.h>
#include <vtkUnstructuredGrid.h>
#include <nlohmann/json.hpp>

#include "chart.hpp"
#include "frame_renderer.hpp"
#include "image_tools.hpp"
#include "isolated_read.hpp"
#include "child_runs.hpp"
#include "command_line.hpp"
#include "ensemble.hpp"
#include "error.hpp"
#include "lists.hpp"
#include "output.hpp"
#include "parallel.hpp"
#include "scene_options.hpp"
#include "stop_signal.hpp"

namespace fs = std::filesystem;

namespace brittle {
namespace {

/// alpha_t of (6.9): the faces of the five tets of a unit cube, summed.
constexpr double kAlphaT = 12.93;

/// The directory name of a size: h_500um, h_62.5um.
std::string size_label(double h) {
  std::ostringstream s;
  s << "h_" << std::setprecision(6) << h * 1e6 << "um";
  return s.str();
}

std::string number_text(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

/// What one run of the study is: its case, size, layers and the arguments of `brittle run`.
struct PlannedRun {
  std::size_t case_index = 0;
  double size = 0;
  int layers = 0;
  Scene scene;  ///< the merged scene, as the run will load it
  ChildRun child;
};

/// The scene files and --set list of a case at size h (layers 0: the scene's own).
std::pair<std::vector<std::string>, std::vector<std::string>> run_inputs(
    const MeshStudyOptions& o, const StudyCase& c, double h, int layers) {
  std::vector<std::string> files = o.scenes;
  files.insert(files.end(), c.overlays.begin(), c.overlays.end());
  std::vector<std::string> sets = o.sets;
  // A uniform mesh of size h: a refined band would make h mean something else.
  sets.insert(sets.end(), {"mesh.size=" + number_text(h), "mesh.band=0", "mesh.band_size=0",
                           "run.threads=1"});
  if (!o.frames) sets.push_back("output.vtu=false");
  if (layers > 0) sets.push_back("mesh.layers=" + std::to_string(layers));
  return {files, sets};
}

/// Loads and checks every run's scene before any starts: a bad file or key is one error, at
/// once, not one failed run per size.
std::vector<PlannedRun> plan_runs(const MeshStudyOptions& o, const std::vector<StudyCase>& cases) {
  std::vector<PlannedRun> plan;
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    for (const double h : o.sizes) {
      PlannedRun run;
      run.case_index = ci, run.size = h;
      auto context = [&] {
        return error_message("brittle study: case '", cases[ci].label, "' at h = ", h, " m: ");
      };
      try {
        auto [files, sets] = run_inputs(o, cases[ci], h, 0);
        Scene scene = load_scene(files, sets);
        BRITTLE_CHECK(scene.mesh.file.empty(), "mesh.file '", scene.mesh.file,
                      "' is set (expected a generated plate: the study sets mesh.size)");
        BRITTLE_CHECK(scene.fracture.mode != FractureParams::Mode::none,
                      "fracture.mode is none (expected straight or branching: the study "
                      "measures cracks)");
        run.layers = o.auto_layers
                         ? std::max(1, static_cast<int>(std::lround(scene.geometry.T / h)))
                         : scene.mesh.layers;
        std::tie(files, sets) = run_inputs(o, cases[ci], h, o.auto_layers ? run.layers : 0);
        // An acoustic-emission sensor when the scene has none: on the face z = T at
        // (3/4 L, H/4), recording the out-of-plane velocity, as a transducer glued to the plate.
        if (scene.sensors.empty()) {
          const GeometryParams& g = scene.geometry;
          sets.push_back("sensor.ae.position=" + number_text(0.75 * g.L) + "," +
                         number_text(0.25 * g.H) + "," + number_text(g.T));
          sets.push_back("sensor.ae.direction=0,0,1");
        }
        run.scene = load_scene(files, sets);
        run.child.directory = o.out + "/" + cases[ci].label + "/" + size_label(h);
        run.child.args = {"run"};
        run.child.args.insert(run.child.args.end(), files.begin(), files.end());
        for (const std::string& s : sets) run.child.args.insert(run.child.args.end(), {"--set", s});
        run.child.args.insert(run.child.args.end(), {"--out", run.child.directory});
      } catch (const Error& e) {
        throw Error(context() + e.what());
      }
      plan.push_back(std::move(run));
    }
  }
  return plan;
}

/// A number at `key`, NaN when missing or null.
double number_at(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : MeshStudyRow::unknown;
}

/// The length of the array at `key`, NaN when it is not there.
double count_at(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_array() ? static_cast<double>(it->size()) : MeshStudyRow::unknown;
}

/// One run's row from its directory.
MeshStudyRow read_study_run(const PlannedRun& run, const std::string& label) {
  MeshStudyRow r;
  r.label = label, r.size = run.size, r.layers = run.layers, r.directory = run.child.directory;
  const std::string dir = run.child.directory;
  const auto summary = read_json(dir + "/summary.json");
  if (!summary) {
    r.status = "failed: no readable summary.json (see run.log)";
    return r;
  }
  const nlohmann::json& s = *summary;
  r.status = s.value("status", std::string("unknown"));
  r.tets = number_at(s, "tets"), r.steps = number_at(s, "steps");
  r.wall_seconds = number_at(s, "wall_seconds"), r.rate = number_at(s, "tet_updates_per_second");
  r.splits = number_at(s, "splits"), r.crack_area = number_at(s, "crack_area");
  r.U_c = number_at(s, "cohesive_dissipated"), r.U_d = number_at(s, "damage_dissipated");
  r.speed = number_at(s, "crack_speed"), r.speed_r2 = number_at(s, "crack_speed_r2");
  if (run.scene.damage.enabled() && r.U_d > 0) r.ratio = r.U_c / r.U_d;
  r.capacity_ratio = capacity_ratio_6_10(run.scene, run.size);
  if (const auto pattern = read_json(dir + "/pattern.json")) {
    r.branches = number_at(*pattern, "branches");
    r.branching_points = count_at(*pattern, "branching_points");
    r.nucleations = count_at(*pattern, "nucleations");
    // The centre of the fullest bin of the link-failure energies (5 bins per decade).
    const auto d = pattern->find("link_failure_energy_distribution");
    if (d != pattern->end() && d->is_object() && d->contains("count") && (*d)["count"].is_array()) {
      const nlohmann::json &count = (*d)["count"], &low = (*d)["bin_low"], &high = (*d)["bin_high"];
      std::size_t best = count.size();
      for (std::size_t i = 0; i < count.size(); ++i)
        if (count[i].is_number() && (best == count.size() || count[i] > count[best])) best = i;
      if (best < count.size() && low.is_array() && high.is_array() && best < low.size() &&
          best < high.size() && low[best].is_number() && high[best].is_number())
        r.event_energy_peak = std::sqrt(low[best].get<double>() * high[best].get<double>());
    }
    // The last row of area_against_advance: [t, advance, area, area / (2 T advance)].
    const auto it = pattern->find("area_against_advance");
    if (it != pattern->end() && it->is_array() && !it->empty() && it->back().is_array() &&
        it->back().size() == 4) {
      const nlohmann::json& last = it->back();
      if (last[1].is_number()) r.advance = last[1].get<double>();
      if (last[3].is_number()) r.area_ratio = last[3].get<double>();
    }
  }
  if (const auto sensors = read_json(dir + "/sensors.json");
      sensors && sensors->is_array() && !sensors->empty()) {
    r.centroid_frequency = number_at(sensors->front(), "centroid_frequency");
    r.dominant_frequency = number_at(sensors->front(), "dominant_frequency");
  }
  return r;
}

/// A CSV cell: quotes doubled, the field quoted.
std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void write_study_csv(const std::string& path, const std::vector<MeshStudyRow>& rows) {
  std::ostringstream out;
  out << "case,h_m,layers,tets,steps,wall_s,tet_updates_per_s,splits,branches,branching_points,"
         "nucleations,crack_area_m2,advance_m,area_over_2T_advance,U_c_J,U_d_J,U_c_over_U_d,"
         "capacity_ratio_6_10,crack_speed_m_per_s,speed_fit_r2,ae_centroid_Hz,ae_dominant_Hz,"
         "status,directory\n"
      << std::setprecision(10);
  for (const MeshStudyRow& r : rows)
    out << quoted(r.label) << ',' << r.size << ',' << r.layers << ',' << r.tets << ',' << r.steps
        << ',' << r.wall_seconds << ',' << r.rate << ',' << r.splits << ',' << r.branches << ','
        << r.branching_points << ',' << r.nucleations << ',' << r.crack_area << ',' << r.advance
        << ',' << r.area_ratio << ',' << r.U_c << ',' << r.U_d << ',' << r.ratio << ','
        << r.capacity_ratio << ',' << r.speed << ',' << r.speed_r2 << ','
        << r.centroid_frequency << ',' << r.dominant_frequency << ',' << r.event_energy_peak
        << ',' << quoted(r.status) << ','
        << r.directory << '\n';
  write_file_atomically(path, out.str());
}

/// NaN as null (nlohmann writes NaN as null too; said here so the file reads the same).
nlohmann::json value(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

void write_study_json(const std::string& path, const MeshStudyOptions& o,
                      const std::vector<StudyCase>& cases, const std::vector<MeshStudyRow>& rows,
                      const std::vector<StudyExponent>& exponents) {
  nlohmann::json j;
  j["scenes"] = o.scenes;
  j["sets"] = o.sets;
  j["sizes"] = o.sizes;
  j["layers"] = o.auto_layers ? "max(1, round(T / h))" : "the scene's mesh.layers";
  for (const StudyCase& c : cases) j["cases"].push_back({{"label", c.label}, {"overlays", c.overlays}});
  for (const MeshStudyRow& r : rows)
    j["rows"].push_back({{"case", r.label},
                         {"h", r.size},
                         {"layers", r.layers},
                         {"tets", value(r.tets)},
                         {"steps", value(r.steps)},
                         {"wall_seconds", value(r.wall_seconds)},
                         {"tet_updates_per_second", value(r.rate)},
                         {"splits", value(r.splits)},
                         {"branches", value(r.branches)},
                         {"branching_points", value(r.branching_points)},
                         {"nucleations", value(r.nucleations)},
                         {"crack_area", value(r.crack_area)},
                         {"advance", value(r.advance)},
                         {"area_over_2T_advance", value(r.area_ratio)},
                         {"U_c", value(r.U_c)},
                         {"U_d", value(r.U_d)},
                         {"U_c_over_U_d", value(r.ratio)},
                         {"capacity_ratio_6_10", value(r.capacity_ratio)},
                         {"crack_speed", value(r.speed)},
                         {"crack_speed_r2", value(r.speed_r2)},
                         {"ae_centroid_frequency", value(r.centroid_frequency)},
                         {"ae_dominant_frequency", value(r.dominant_frequency)},
                         {"event_energy_peak", value(r.event_energy_peak)},
                         {"status", r.status},
                         {"directory", r.directory}});
  for (const StudyExponent& e : exponents)
    j["ratio_exponents"].push_back(
        {{"case", e.label}, {"exponent", value(e.exponent)}, {"points", e.points}, {"6.10", 1.0}});
  write_file_atomically(path, j.dump(2) + "\n");
}

/// One chart of a quantity against log10 h [mm], a point series per case (and optional
/// extra series), into <out>/<name>.png.
void study_chart(const std::string& out, const std::string& name, const std::string& title,
                 const std::string& y_title, const std::vector<StudyCase>& cases,
                 const std::vector<MeshStudyRow>& rows, double (*y)(const MeshStudyRow&),
                 render::ChartAxes::Corner legend, std::vector<render::ChartSeries> extra = {}) {
  static const std::array<std::array<unsigned char, 3>, 6> colours = {
      {{0, 0, 0}, {200, 30, 30}, {30, 90, 200}, {30, 150, 60}, {180, 120, 0}, {140, 40, 160}}};
  std::vector<render::ChartSeries> series;
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    render::ChartSeries s{cases[ci].label, {}, {}, render::ChartSeries::Style::points,
                          colours[ci % colours.size()], static_cast<int>(ci % 5)};
    for (const MeshStudyRow& r : rows)
      if (r.label == cases[ci].label && std::isfinite(y(r)))
        s.x.push_back(std::log10(r.size * 1e3)), s.y.push_back(y(r));
    if (!s.x.empty()) series.push_back(std::move(s));
  }
  for (auto& s : extra)
    if (!s.x.empty()) series.push_back(std::move(s));
  if (series.empty()) return;
  render::write_chart_png(out + "/" + name + ".png", title, "log10 h [mm]", y_title, series,
                          legend);
}

void write_study_charts(const std::string& out, const std::vector<StudyCase>& cases,
                        const std::vector<MeshStudyRow>& rows) {
  using Corner = render::ChartAxes::Corner;
  // (6.10) as dashed lines, one per damage case.
  std::vector<render::ChartSeries> capacity;
  for (const StudyCase& c : cases) {
    render::ChartSeries s{c.label + ": (6.10) capacity", {}, {}, render::ChartSeries::Style::dashed,
                          {120, 120, 120}};
    for (const MeshStudyRow& r : rows)
      if (r.label == c.label && std::isfinite(r.capacity_ratio) && r.capacity_ratio > 0)
        s.x.push_back(std::log10(r.size * 1e3)), s.y.push_back(std::log10(r.capacity_ratio));
    // Cases with the same material and load share one line.
    const bool repeated = std::any_of(capacity.begin(), capacity.end(), [&](const auto& c) {
      return c.x == s.x && c.y == s.y;
    });
    if (s.x.size() > 1 && !repeated) capacity.push_back(std::move(s));
  }
  if (capacity.size() == 1) capacity.front().name = "(6.10) capacity ratio";
  study_chart(out, "study_ratio", "Dissipation by links over damage, U_c/U_d, against h",
              "log10 U_c / U_d", cases, rows,
              [](const MeshStudyRow& r) { return r.ratio > 0 ? std::log10(r.ratio) : NAN; },
              Corner::top_right, std::move(capacity));
  study_chart(out, "study_branches", "Branches (tracks of at least the minimum length)",
              "branches", cases, rows, [](const MeshStudyRow& r) { return r.branches; },
              Corner::top_right);
  study_chart(out, "study_area", "Crack area per unit advance, area / (2 T advance)",
              "area / (2 T advance)", cases, rows,
              [](const MeshStudyRow& r) { return r.area_ratio; }, Corner::top_right);
  study_chart(out, "study_speed", "Steady crack speed", "speed [m/s]", cases, rows,
              [](const MeshStudyRow& r) { return r.speed; }, Corner::top_right);
  study_chart(out, "study_ae", "Acoustic emission: spectral centroid of the sensor",
              "centroid [kHz]", cases, rows,
              [](const MeshStudyRow& r) { return 1e-3 * r.centroid_frequency; }, Corner::top_right);
  study_chart(out, "study_events", "Acoustic emission: typical link-failure energy",
              "log10 energy of the fullest bin [J]", cases, rows,
              [](const MeshStudyRow& r) {
                return r.event_energy_peak > 0 ? std::log10(r.event_energy_peak) : NAN;
              },
              Corner::bottom_right);
}

/// With --frames: study_cracks.png, a crack frame (docs/rendering.md) of every run at its last
/// stored time, a row per case and a column per size, in the run's own render settings.
void write_crack_panel(const std::string& out, const std::vector<StudyCase>& cases,
                       const std::vector<double>& sizes, const std::vector<PlannedRun>& plan) {
  RenderParams style = plan.front().scene.render;
  style.width = 480, style.height = 320;
  render::FrameRenderer renderer(style);
  std::vector<std::vector<vtkSmartPointer<vtkImageData>>> images(cases.size());
  std::vector<std::vector<vtkImageData*>> cells(cases.size());
  double last_time = 0;
  for (const PlannedRun& run : plan) {
    vtkSmartPointer<vtkImageData> image;
    try {
      const auto series = read_pvd(run.child.directory + "/run.pvd");
      BRITTLE_CHECK(!series.empty(), "no frames");
      auto grid = read_vtu_isolated(series.back().file, "study: frame");
      image = renderer.render(*grid, render::Field::crack);
      last_time = std::max(last_time, series.back().time);
    } catch (const Error&) {  // a failed run: its cell says so, the others still show
      image = render::text_image("no frame", style.width, style.height, style.height / 10);
    }
    images[run.case_index].push_back(image);
    cells[run.case_index].push_back(image);
  }
  std::vector<std::string> rows, columns;
  for (const StudyCase& c : cases) rows.push_back(c.label);
  for (double h : sizes) columns.push_back(error_message("h = ", h * 1e6, " um"));
  char title[96];
  std::snprintf(title, sizeof title, "Cracks at the last frame (%.1f us) against the element size",
                last_time * 1e6);
  render::write_png(*render::panel(cells, rows, columns, title), out + "/study_cracks.png");
}

}  // namespace

std::vector<double> parse_sizes(const std::string& text) {
  std::vector<double> sizes;
  for (const std::string& token : list_words(text)) {
    const auto v = parse_number(token);
    BRITTLE_CHECK(v && *v > 0 && *v < 1, "--sizes '", text, "': '", token,
                  "' is not an element size (expected sizes in m, 0 < h < 1, comma separated)");
    sizes.push_back(*v);
  }
  BRITTLE_CHECK(!sizes.empty(), "--sizes '", text, "': no size given (expected e.g. 1e-3,500e-6)");
  return sizes;
}

StudyCase parse_case(const std::string& text) {
  StudyCase c;
  const auto eq = text.find('=');
  c.label = text.substr(0, eq);
  BRITTLE_CHECK(!c.label.empty() && c.label != "." && c.label != ".." &&
                    c.label.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789+-_.") == std::string::npos,
                "--case '", text, "': expected LABEL or LABEL=A.ini,B.ini with a label of letters, "
                "digits, '+', '-', '_', '.'");
  if (eq != std::string::npos) c.overlays = list_words(text.substr(eq + 1));
  return c;
}

double capacity_ratio_6_10(const Scene& scene, double h) {
  if (!scene.damage.enabled() || scene.initial.state != InitialParams::State::prestress)
    return MeshStudyRow::unknown;
  const double sigma = scene.loading.stress(scene.material);
  return 4 * scene.material.E * scene.material.gamma * kAlphaT /
         (scene.damage.limit() * sigma * sigma * h);
}

std::vector<StudyExponent> study_exponents(const std::vector<MeshStudyRow>& rows) {
  std::vector<StudyExponent> out;
  for (const MeshStudyRow& r : rows) {
    if (std::none_of(out.begin(), out.end(), [&](const StudyExponent& e) { return e.label == r.label; }))
      out.push_back({r.label});
  }
  for (StudyExponent& e : out) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const MeshStudyRow& r : rows)
      if (r.label == e.label && std::isfinite(r.ratio) && r.ratio > 0) {
        const double x = std::log(1 / r.size), y = std::log(r.ratio);
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
      }
    e.points = n;
    const double d = n * sxx - sx * sx;
    if (n >= 2 && d > 0) e.exponent = (n * sxy - sx * sy) / d;
  }
  return out;
}

std::vector<MeshStudyRow> run_mesh_study(const MeshStudyOptions& o) {
  BRITTLE_CHECK(!o.scenes.empty(), "brittle study mesh: no scene file given");
  BRITTLE_CHECK(!o.sizes.empty(), "brittle study mesh: no size given (expected --sizes)");
  std::vector<StudyCase> cases = o.cases;
  if (cases.empty()) cases.push_back({"run", {}});
  for (std::size_t i = 0; i < cases.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      BRITTLE_CHECK(cases[i].label != cases[k].label, "--case '", cases[i].label,
                    "' is given twice (expected distinct labels)");
  const std::vector<PlannedRun> plan = plan_runs(o, cases);
  fs::create_directories(o.out);
  std::vector<ChildRun> runs;
  for (const PlannedRun& run : plan) runs.push_back(run.child);
  const std::vector<std::string> why = run_or_reuse(runs, o.reuse, o.jobs, "study");
  std::vector<MeshStudyRow> rows;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const std::string& label = cases[plan[i].case_index].label;
    if (why[i].empty()) {
      rows.push_back(read_study_run(plan[i], label));
    } else {
      MeshStudyRow r;
      r.label = label, r.size = plan[i].size, r.layers = plan[i].layers;
      r.status = why[i];
      r.directory = plan[i].child.directory;
      rows.push_back(r);
    }
  }
  const auto exponents = study_exponents(rows);
  if (mpi_rank() != 0) return rows;  // under mpirun rank 0 writes
  write_study_csv(o.out + "/study.csv", rows);
  write_study_json(o.out + "/study.json", o, cases, rows, exponents);
  write_study_charts(o.out, cases, rows);
  if (o.frames) write_crack_panel(o.out, cases, o.sizes, plan);
  return rows;
}

int study_command(const std::vector<std::string>& args) {
  namespace po = boost::program_options;
  const char* usage =
      "usage: brittle study mesh SCENE.ini [MORE.ini ...] --sizes 1e-3,500e-6,... "
      "[--case LABEL[=A.ini,B.ini] ...] [--set k=v ...] [--layers auto|scene] [--jobs N] "
      "[--frames yes|no] [--reuse] [--out DIR]";
  const char* about =
      "Runs every case at every element size h (uniform meshes, child processes) into "
      "DIR/<case>/h_<h>/ and tabulates branches, crack area, dissipation, speed and "
      "acoustic emission against h: DIR/study.csv, study.json and study_*.png "
      "(docs/mesh-study.md). Every case and size is checked before any run starts.";
  std::string frames = "no";
  MeshStudyOptions o;
  std::string sizes, layers = "auto";
  std::vector<std::string> cases;
  po::options_description opts("brittle study mesh options");
  opts.add_options()("help,h", "show this help")(
      "sizes", po::value(&sizes)->required(), "element sizes h [m], comma separated")(
      "case", po::value(&cases)->composing(),
      "a case: LABEL, or LABEL=A.ini,B.ini (overlays on the scenes); repeatable (default: one "
      "case 'run')")("set", po::value(&o.sets)->composing(),
                     "override one key for every run: section.key=value (repeatable)")(
      "layers", po::value(&layers)->default_value("auto"),
      "auto: max(1, round(T / h)) element layers through the thickness; scene: mesh.layers")(
      "jobs", po::value(&o.jobs)->default_value(0), "runs at once (0 = number of cores)")(
      "frames", po::value(&frames)->implicit_value("yes"),
      "yes: every run writes its VTU frames (output.vtu = true, for brittle render) and the "
      "study draws study_cracks.png; no (default): none")(
      "reuse", po::bool_switch(&o.reuse),
      "do not re-run a run whose directory holds a completed run of the same scene and keys "
      "(extend a study by sizes or cases)")(
      "out", po::value(&o.out)->default_value("out/study"),
      "directory (created) for the study's tables and charts and one run directory per case "
      "and size");
  po::options_description hidden;
  hidden.add_options()("scene", po::value(&o.scenes)->composing(), "scene INI files");
  const bool asked_help = !args.empty() && (args[0] == "--help" || args[0] == "-h");
  if (args.empty() || asked_help) {
    print_command_help(asked_help ? std::cout : std::cerr, usage, about, opts);
    return asked_help ? 0 : 2;
  }
  if (args[0] == "ensemble") return ensemble_command({args.begin() + 1, args.end()});
  BRITTLE_CHECK(args[0] == "mesh", "brittle study: unknown study '", args[0],
                "' (expected: brittle study mesh SCENE.ini ... --sizes LIST, or brittle study "
                "ensemble SCENE.ini ... --vary mesh|strength|steps)");
  auto vm = parse_command_line({args.begin() + 1, args.end()}, opts, hidden, "scene");
  if (vm.count("help")) {
    print_command_help(std::cout, usage, about, opts);
    return 0;
  }
  po::notify(vm);
  o.frames = parse_switch("--frames", frames);
  o.sizes = parse_sizes(sizes);
  for (const std::string& c : cases) o.cases.push_back(parse_case(c));
  BRITTLE_CHECK(layers == "auto" || layers == "scene", "--layers '", layers,
                "' is not a choice (expected auto or scene)");
  o.auto_layers = layers == "auto";
  BRITTLE_CHECK(o.jobs >= 0, "--jobs ", o.jobs, " is out of range (expected >= 0)");
  install_stop_handlers();
  const auto rows = run_mesh_study(o);
  if (mpi_rank() != 0) return stop_signal().load() ? 128 + stop_signal().load() : 0;
  bool all_completed = true;
  std::printf("%-18s %7s %3s %8s %6s %3s %3s %4s %6s %9s %9s %7s %7s %6s %6s %8s  %s\n", "case",
              "h [um]", "lay", "tets", "splits", "br", "bp", "nuc", "A/2Ta", "U_c [J]", "U_d [J]",
              "Uc/Ud", "(6.10)", "v m/s", "AE kHz", "E_ev [J]", "status");
  for (const MeshStudyRow& r : rows) {
    std::printf("%-18s %7.4g %3d %8.0f %6.0f %3.0f %3.0f %4.0f %6.3f %9.3g %9.3g %7.3g %7.3g %6.0f "
                "%6.0f %8.2g  %s\n",
                r.label.c_str(), r.size * 1e6, r.layers, r.tets, r.splits, r.branches,
                r.branching_points, r.nucleations, r.area_ratio, r.U_c, r.U_d, r.ratio,
                r.capacity_ratio, r.speed, 1e-3 * r.centroid_frequency, r.event_energy_peak,
                r.status.c_str());
    all_completed = all_completed && r.status == "completed";
  }
  for (const StudyExponent& e : study_exponents(rows))
    if (e.points >= 2)
      std::printf("%s: U_c/U_d ~ h^(%.2f) over %d sizes ((6.10): h^(-1))\n", e.label.c_str(),
                  -e.exponent, e.points);
  std::printf("wrote %s/study.csv, study.json and study_*.png\n", o.out.c_str());
  if (const int stop = stop_signal().load()) {
    std::fprintf(stderr, "brittle: study stopped; the runs that were running stopped with a "
                 "checkpoint (brittle run --resume DIR continues one)\n");
    return 128 + stop;
  }
  BRITTLE_CHECK(all_completed, "study: some runs failed (see study.csv and their run.log)");
  return 0;
}

}  // namespace brittle
