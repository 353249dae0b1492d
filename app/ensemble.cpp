// `brittle study ensemble`: one scene as N members differing in one named thing, as child runs;
// the forks read back from each member's pattern.json, the statistics over the members, and a
// picture of every member's crack on one plate (docs/ensembles.md).
#include "ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <boost/program_options.hpp>
#include <vtkImageData.h>
#include <vtkImageResize.h>
#include <vtkSmartPointer.h>

#include "chart.hpp"
#include "child_runs.hpp"
#include "command_line.hpp"
#include "crack_pattern.hpp"
#include "error.hpp"
#include "image_tools.hpp"
#include "output.hpp"
#include "parallel.hpp"
#include "scene_options.hpp"
#include "simulation.hpp"
#include "stop_signal.hpp"

namespace fs = std::filesystem;

namespace brittle {

EnsembleVary parse_vary(const std::string& word) {
  if (word == "mesh") return EnsembleVary::mesh;
  if (word == "strength") return EnsembleVary::strength;
  if (word == "steps") return EnsembleVary::steps;
  throw Error(error_message("--vary '", word,
                            "' is not a variation (expected mesh, strength or steps)"));
}

namespace {

const char* vary_name(EnsembleVary v) {
  switch (v) {
    case EnsembleVary::mesh: return "mesh";
    case EnsembleVary::strength: return "strength";
    case EnsembleVary::steps: return "steps";
  }
  return "";
}

/// The nodal perturbation a mesh ensemble uses when the scene has none (a fraction of each
/// node's shortest in-plane edge; docs/ensembles.md).
constexpr double kDefaultPerturb = 0.25;

std::string number_text(double v, int digits = 17) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

/// The keys that make member i (1..N) differ from the scene.
std::vector<std::string> variation_of(const EnsembleOptions& o, const Scene& scene, int i) {
  switch (o.vary) {
    case EnsembleVary::mesh: {
      std::vector<std::string> keys;
      if (scene.mesh.perturb == 0) keys.push_back("mesh.perturb=" + number_text(kDefaultPerturb));
      keys.push_back("mesh.perturb_seed=" + std::to_string(i));
      return keys;
    }
    case EnsembleVary::strength:
      return {"material.strength_seed=" + std::to_string(i)};
    case EnsembleVary::steps: {
      if (i == 1) return {};  // the scene's own frames
      // Frames every interval, offset by (i - 1) / N of it: each frame ends a step, so the
      // members' steps end at different times (as the 15-digit decimals frame_times() uses).
      const double interval = scene.output.frame_interval, end = scene.run.end_time;
      const double offset = interval * (i - 1) / o.members;
      std::string list;
      for (long k = 0;; ++k) {
        const double t = std::strtod(number_text(offset + k * interval, 15).c_str(), nullptr);
        if (t > end * (1 + 1e-12)) break;
        list += (list.empty() ? "" : ",") + number_text(t, 15);
      }
      return {"output.frame_times=" + list};
    }
  }
  return {};
}

double number_at(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : EnsembleMember::unknown;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

struct PlannedMember {
  ChildRun child;
  std::string variation;
};

}  // namespace

EnsembleMember read_member(const std::string& directory, int index, const std::string& variation,
                           double reach) {
  EnsembleMember m;
  m.index = index, m.variation = variation, m.directory = directory;
  const auto summary = read_json(directory + "/summary.json");
  if (!summary) {
    m.status = "failed: no readable summary.json (see run.log)";
    return m;
  }
  m.status = summary->value("status", std::string("unknown"));
  m.splits = number_at(*summary, "splits");
  m.crack_area = number_at(*summary, "crack_area");
  m.max_imbalance = number_at(*summary, "max_relative_imbalance");
  m.wall = number_at(*summary, "wall_seconds");
  const auto pattern = read_json(directory + "/pattern.json");
  if (!pattern) {
    m.status += " (no readable pattern.json)";
    return m;
  }
  const auto f = pattern->find("fork");
  if (f == pattern->end() || !f->is_object()) return m;
  m.fork = true;
  m.fork_t = number_at(*f, "t"), m.fork_x = number_at(*f, "x"), m.fork_y = number_at(*f, "y");
  m.fork_angle = number_at(*f, "angle_deg");
  const auto arms = f->find("arms");
  if (arms != f->end() && arms->is_array() && arms->size() == 2) {
    for (int k = 0; k < 2; ++k) {
      const nlohmann::json& a = (*arms)[k];
      m.arm_length[k] = number_at(a, "length");
      m.arm_reach_x[k] = number_at(a, "reach_x");
      const auto head = a.find("head");
      if (head != a.end() && head->is_array() && head->size() == 3 && (*head)[0].is_number() &&
          (*head)[1].is_number() && (*head)[2].is_number()) {
        m.arm_head_t[k] = (*head)[0].get<double>();
        m.arm_head_x[k] = (*head)[1].get<double>();
        m.arm_head_y[k] = (*head)[2].get<double>();
      }
    }
  }
  m.both_reach = m.arm_reach_x[0] >= reach && m.arm_reach_x[1] >= reach;
  return m;
}

Quartiles quartiles(std::vector<double> values) {
  std::erase_if(values, [](double v) { return !std::isfinite(v); });
  Quartiles q;
  q.n = static_cast<int>(values.size());
  if (values.empty()) return q;
  std::sort(values.begin(), values.end());
  const auto at = [&](double p) {  // R's type 7
    const double h = (values.size() - 1) * p;
    const auto lo = static_cast<std::size_t>(std::floor(h));
    const std::size_t hi = std::min(lo + 1, values.size() - 1);
    return values[lo] + (h - lo) * (values[hi] - values[lo]);
  };
  q.q1 = at(0.25), q.median = at(0.5), q.q3 = at(0.75);
  return q;
}

std::pair<double, double> wilson_90(int k, int n) {
  if (n <= 0) return {EnsembleMember::unknown, EnsembleMember::unknown};
  const double z = 1.6448536269514722, z2 = z * z, p = static_cast<double>(k) / n;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z / (1.0 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

void write_ensemble_tables(const std::string& out, const EnsembleOptions& o,
                           const std::vector<EnsembleMember>& members, double reach) {
  std::ostringstream csv;
  csv << "member,variation,fork,fork_x_m,fork_y_m,fork_t_s,fork_angle_deg";
  for (int k = 1; k <= 2; ++k)
    csv << ",arm" << k << "_length_m,arm" << k << "_head_x_m,arm" << k << "_head_y_m,arm" << k
        << "_head_t_s,arm" << k << "_reach_x_m";
  csv << ",both_arms_reach,splits,crack_area_m2,max_relative_imbalance,wall_s,status,directory\n";
  const auto num = [](double v) { return std::isfinite(v) ? number_text(v, 12) : std::string(); };
  const auto quoted = [](const std::string& text) {
    std::string q = "\"";
    for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  for (const EnsembleMember& m : members) {
    csv << m.index << ',' << quoted(m.variation) << ',' << (m.fork ? 1 : 0) << ','
        << num(m.fork_x) << ',' << num(m.fork_y) << ',' << num(m.fork_t) << ','
        << num(m.fork_angle);
    for (int k = 0; k < 2; ++k)
      csv << ',' << num(m.arm_length[k]) << ',' << num(m.arm_head_x[k]) << ','
          << num(m.arm_head_y[k]) << ',' << num(m.arm_head_t[k]) << ',' << num(m.arm_reach_x[k]);
    csv << ',' << (m.both_reach ? 1 : 0) << ',' << num(m.splits) << ',' << num(m.crack_area)
        << ',' << num(m.max_imbalance) << ',' << num(m.wall) << ',' << quoted(m.status) << ','
        << quoted(m.directory) << '\n';
  }
  write_file_atomically(out + "/ensemble.csv", csv.str());

  int forks = 0, ys = 0, completed = 0;
  for (const EnsembleMember& m : members) {
    forks += m.fork;
    ys += m.fork && m.both_reach;
    completed += m.status == "completed";
  }
  const int n = static_cast<int>(members.size());
  const auto stats = [&](auto value, bool forked_only) {
    std::vector<double> v;
    for (const EnsembleMember& m : members)
      if (!forked_only || m.fork) v.push_back(value(m));
    const Quartiles q = quartiles(v);
    const auto j = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
    return nlohmann::ordered_json{{"median", j(q.median)}, {"q1", j(q.q1)}, {"q3", j(q.q3)},
                                  {"n", q.n}};
  };
  nlohmann::ordered_json j;
  j["scenes"] = o.scenes;
  j["sets"] = o.sets;
  j["vary"] = vary_name(o.vary);
  j["members"] = n;
  j["completed"] = completed;
  j["fork_rule"] = "the first branching point both of whose arms are branches: each arm's line "
                   "at least the pattern's min_branch_length (pattern.json 'fork'; "
                   "docs/crack_pattern.md)";
  j["forks"] = forks;
  const auto [lo, hi] = wilson_90(forks, n);
  j["fork_rate"] = n > 0 ? nlohmann::json(static_cast<double>(forks) / n) : nlohmann::json();
  j["fork_rate_ci90"] = {lo, hi};
  j["reach_x"] = reach;
  j["both_arms_reach"] = ys;
  const auto [ylo, yhi] = wilson_90(ys, n);
  j["both_arms_reach_rate_ci90"] = {ylo, yhi};
  nlohmann::ordered_json q;
  q["fork_x"] = stats([](const EnsembleMember& m) { return m.fork_x; }, true);
  q["fork_y"] = stats([](const EnsembleMember& m) { return m.fork_y; }, true);
  q["fork_t"] = stats([](const EnsembleMember& m) { return m.fork_t; }, true);
  q["fork_angle_deg"] = stats([](const EnsembleMember& m) { return m.fork_angle; }, true);
  q["shorter_arm_length"] = stats(
      [](const EnsembleMember& m) { return std::min(m.arm_length[0], m.arm_length[1]); }, true);
  q["longer_arm_length"] = stats(
      [](const EnsembleMember& m) { return std::max(m.arm_length[0], m.arm_length[1]); }, true);
  q["splits"] = stats([](const EnsembleMember& m) { return m.splits; }, false);
  q["crack_area"] = stats([](const EnsembleMember& m) { return m.crack_area; }, false);
  q["max_relative_imbalance"] =
      stats([](const EnsembleMember& m) { return m.max_imbalance; }, false);
  q["wall_s"] = stats([](const EnsembleMember& m) { return m.wall; }, false);
  j["quartiles"] = q;
  write_file_atomically(out + "/ensemble.json", j.dump(2) + "\n");
}

namespace {

/// ensemble.png: every member's splits (events.csv, reference x-y) as faint points on one
/// plate, the median fork marked; with `beside`, that picture to its right.
void write_overlay(const EnsembleOptions& o, const Scene& scene,
                   const std::vector<EnsembleMember>& members) {
  const GeometryParams& g = scene.geometry;
  std::vector<render::ChartSeries> series;
  static const std::array<unsigned char, 3> colours[] = {
      {31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189},
      {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}};
  int drawn = 0;
  for (const EnsembleMember& m : members) {
    std::vector<CrackEvent> events;
    try {
      events = read_events_csv(m.directory + "/events.csv");
    } catch (const Error&) {
      continue;  // (a member that failed early: its row says so)
    }
    render::ChartSeries s;
    s.name = "members' splits";
    s.legend = drawn == 0;
    s.color = colours[(m.index - 1) % 8];
    s.alpha = 70;
    s.marker_size = 3;
    for (const CrackEvent& e : events)
      if (e.kind == CrackEvent::Kind::split) s.x.push_back(1e3 * e.x), s.y.push_back(1e3 * e.y);
    series.push_back(std::move(s));
    ++drawn;
  }
  std::vector<double> fx, fy;
  for (const EnsembleMember& m : members)
    if (m.fork) fx.push_back(m.fork_x), fy.push_back(m.fork_y);
  if (!fx.empty()) {
    render::ChartSeries forks;
    forks.name = "each member's fork";
    forks.color = {0, 0, 0};
    forks.marker = 0;
    forks.marker_size = 7;
    for (std::size_t i = 0; i < fx.size(); ++i)
      forks.x.push_back(1e3 * fx[i]), forks.y.push_back(1e3 * fy[i]);
    series.push_back(forks);
    render::ChartSeries median;
    median.name = "median fork";
    median.color = {0, 0, 0};
    median.marker = 3;
    median.marker_size = 18;
    median.x = {1e3 * quartiles(fx).median};
    median.y = {1e3 * quartiles(fy).median};
    series.push_back(median);
  }
  render::ChartAxes axes;
  int forks = 0;
  for (const EnsembleMember& m : members) forks += m.fork;
  axes.title = std::to_string(members.size()) + " members (--vary " + vary_name(o.vary) +
               "), forks: " + std::to_string(forks) + " of " + std::to_string(members.size());
  axes.x_title = "x [mm]";
  axes.y_title = "y [mm]";
  axes.x_min = 0, axes.x_max = 1e3 * g.L;
  axes.y_min = -0.5e3 * g.H, axes.y_max = 0.5e3 * g.H;
  axes.width = 1000;
  axes.height = std::clamp(static_cast<int>(1000 * g.H / g.L) + 150, 300, 1100);
  axes.legend = render::ChartAxes::Corner::top_left;
  const std::string path = o.out + "/ensemble.png";
  render::write_chart_png(path, axes, series);
  if (o.beside.empty()) return;
  vtkSmartPointer<vtkImageData> overlay = render::read_png(path), peer = render::read_png(o.beside);
  int d[3], e[3];
  overlay->GetDimensions(d);
  peer->GetDimensions(e);
  auto resize = vtkSmartPointer<vtkImageResize>::New();  // the panel's cells are of one size
  resize->SetInputData(peer);
  resize->SetOutputDimensions(d[0], d[1], 1);
  resize->Update();
  vtkSmartPointer<vtkImageData> fitted = resize->GetOutput();
  render::write_png(*render::panel({{overlay.Get(), fitted.Get()}}, {""},
                                   {"brittle", fs::path(o.beside).filename().string()},
                                   "ensemble and peer"),
                    path);
}

}  // namespace

std::vector<EnsembleMember> run_ensemble(const EnsembleOptions& o) {
  BRITTLE_CHECK(!o.scenes.empty(), "brittle study ensemble: no scene file given");
  BRITTLE_CHECK(o.members >= 1 && o.members <= 1000, "--members ", o.members,
                " is out of range (expected 1 to 1000)");
  BRITTLE_CHECK(o.beside.empty() || fs::is_regular_file(o.beside), "--beside '", o.beside,
                "' is not a file (expected a PNG to draw beside the overlay)");
  // Every member runs on one thread unless the user says otherwise: the members share the cores.
  std::vector<std::string> sets = {"run.threads=1"};
  sets.insert(sets.end(), o.sets.begin(), o.sets.end());
  if (!o.frames) sets.push_back("output.vtu=false");
  const Scene scene = load_scene(o.scenes, sets);
  BRITTLE_CHECK(scene.fracture.mode != FractureParams::Mode::none,
                "brittle study ensemble: fracture.mode is none (expected straight or branching: "
                "the ensemble counts forks)");
  if (o.vary == EnsembleVary::strength)
    BRITTLE_CHECK(scene.material.weibull_modulus > 0,
                  "--vary strength: the scene has one strength everywhere "
                  "(material.weibull_modulus = 0; expected a Weibull modulus > 0, or --vary "
                  "mesh or steps)");
  if (o.vary == EnsembleVary::steps)
    BRITTLE_CHECK(scene.output.frame_interval > 0 && scene.output.frame_times.empty(),
                  "--vary steps offsets the frames of output.frame_interval (expected "
                  "output.frame_interval > 0 and no output.frame_times)");
  const double reach = o.reach > 0 ? o.reach : 0.9 * scene.geometry.L;
  std::vector<PlannedMember> plan;
  for (int i = 1; i <= o.members; ++i) {
    std::vector<std::string> member_sets = sets;
    const std::vector<std::string> keys = variation_of(o, scene, i);
    member_sets.insert(member_sets.end(), keys.begin(), keys.end());
    load_scene(o.scenes, member_sets);  // (every member's scene checked before any runs)
    char name[32];
    std::snprintf(name, sizeof name, "member_%02d", i);
    PlannedMember m;
    m.variation = keys.empty() ? "(the scene)" : join(keys, " ");
    m.child.directory = o.out + "/" + name;
    m.child.args = {"run"};
    m.child.args.insert(m.child.args.end(), o.scenes.begin(), o.scenes.end());
    for (const std::string& s : member_sets) m.child.args.insert(m.child.args.end(), {"--set", s});
    m.child.args.insert(m.child.args.end(), {"--out", m.child.directory});
    plan.push_back(std::move(m));
  }
  fs::create_directories(o.out);
  std::vector<ChildRun> runs;
  for (const PlannedMember& m : plan) runs.push_back(m.child);
  const std::vector<std::string> why = run_or_reuse(runs, o.reuse, o.jobs, "ensemble");
  std::vector<EnsembleMember> members;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    if (why[i].empty()) {
      members.push_back(read_member(plan[i].child.directory, static_cast<int>(i) + 1,
                                    plan[i].variation, reach));
    } else {
      EnsembleMember m;
      m.index = static_cast<int>(i) + 1, m.variation = plan[i].variation;
      m.directory = plan[i].child.directory;
      m.status = why[i];
      members.push_back(m);
    }
  }
  if (mpi_rank() != 0) return members;  // under mpirun rank 0 writes
  write_ensemble_tables(o.out, o, members, reach);
  write_overlay(o, scene, members);
  return members;
}

int ensemble_command(const std::vector<std::string>& args) {
  namespace po = boost::program_options;
  const char* usage =
      "usage: brittle study ensemble SCENE.ini [MORE.ini ...] --vary mesh|strength|steps "
      "[--members N] [--set k=v ...] [--reach X] [--jobs N] [--frames yes|no] [--reuse] "
      "[--beside PEER.png] [--out DIR]";
  const char* about =
      "Runs the scene as N members that differ only in --vary: mesh (mesh.perturb_seed = 1..N; "
      "mesh.perturb = 0.25 when the scene has none), strength (material.strength_seed = 1..N) "
      "or steps (the frames of output.frame_interval offset by (i-1)/N of it, so the steps end "
      "elsewhere). Writes DIR/member_NN/, DIR/ensemble.csv (each member's fork, arms, splits, "
      "crack area, energy balance, wall time), ensemble.json (fork rate with its 90 % Wilson "
      "interval, medians and quartiles) and ensemble.png (every member's crack on one plate, "
      "the median fork marked) (docs/ensembles.md).";
  EnsembleOptions o;
  std::string vary, frames = "no";
  po::options_description opts("brittle study ensemble options");
  opts.add_options()("help,h", "show this help")(
      "vary", po::value(&vary)->required(), "what the members differ in: mesh, strength or steps")(
      "members", po::value(&o.members)->default_value(8), "how many members (1 to 1000)")(
      "set", po::value(&o.sets)->composing(),
      "override one key for every member: section.key=value (repeatable)")(
      "reach", po::value(&o.reach)->default_value(0),
      "an arm reaches when its head gets to x >= this [m] (0: 0.9 geometry.L)")(
      "jobs", po::value(&o.jobs)->default_value(0), "members at once (0 = number of cores)")(
      "frames", po::value(&frames)->implicit_value("yes"),
      "yes: the members write their VTU frames; no (default): none")(
      "reuse", po::bool_switch(&o.reuse),
      "do not re-run a member whose directory holds a completed run of the same scene and keys")(
      "beside", po::value(&o.beside), "a PNG (e.g. a peer's damage field) drawn beside the overlay")(
      "out", po::value(&o.out)->default_value("out/ensemble"),
      "directory (created) for the tables, the picture and one directory per member");
  po::options_description hidden;
  hidden.add_options()("scene", po::value(&o.scenes)->composing(), "scene INI files");
  const bool asked_help = !args.empty() && (args[0] == "--help" || args[0] == "-h");
  if (args.empty() || asked_help) {
    print_command_help(asked_help ? std::cout : std::cerr, usage, about, opts);
    return asked_help ? 0 : 2;
  }
  auto vm = parse_command_line(args, opts, hidden, "scene");
  if (vm.count("help")) {
    print_command_help(std::cout, usage, about, opts);
    return 0;
  }
  po::notify(vm);
  o.vary = parse_vary(vary);
  o.frames = parse_switch("--frames", frames);
  BRITTLE_CHECK(o.jobs >= 0, "--jobs ", o.jobs, " is out of range (expected >= 0)");
  BRITTLE_CHECK(o.reach >= 0, "--reach ", o.reach, " is out of range (expected >= 0)");
  install_stop_handlers();
  const std::vector<EnsembleMember> members = run_ensemble(o);
  if (mpi_rank() != 0) return stop_signal().load() ? 128 + stop_signal().load() : 0;
  int forks = 0, ys = 0;
  bool all_completed = true;
  std::printf("%-6s %-5s %9s %9s %8s %7s %9s %9s %7s %9s %8s  %s\n", "member", "fork", "x [mm]",
              "y [mm]", "t [us]", "angle", "arm1 [mm]", "arm2 [mm]", "splits", "imbalance",
              "wall [s]", "variation");
  for (const EnsembleMember& m : members) {
    forks += m.fork, ys += m.fork && m.both_reach;
    all_completed = all_completed && m.status == "completed";
    std::printf("%-6d %-5s %9.2f %9.2f %8.2f %7.1f %9.2f %9.2f %7.0f %9.2e %8.1f  %s%s\n", m.index,
                m.fork ? (m.both_reach ? "Y" : "yes") : "no", 1e3 * m.fork_x, 1e3 * m.fork_y,
                1e6 * m.fork_t, m.fork_angle, 1e3 * m.arm_length[0], 1e3 * m.arm_length[1],
                m.splits, m.max_imbalance, m.wall, m.variation.substr(0, 60).c_str(),
                m.status == "completed" ? "" : ("  [" + m.status + "]").c_str());
  }
  const auto [lo, hi] = wilson_90(forks, static_cast<int>(members.size()));
  std::printf("forks: %d of %zu (90 %% interval %.2f-%.2f); both arms to the reach: %d\n", forks,
              members.size(), lo, hi, ys);
  std::printf("wrote %s/ensemble.csv, ensemble.json and ensemble.png\n", o.out.c_str());
  if (const int stop = stop_signal().load()) {
    std::fprintf(stderr, "brittle: ensemble stopped; the members that were running stopped with "
                 "a checkpoint (brittle run --resume DIR continues one)\n");
    return 128 + stop;
  }
  BRITTLE_CHECK(all_completed, "ensemble: some members failed (see ensemble.csv and their run.log)");
  return 0;
}

}  // namespace brittle
