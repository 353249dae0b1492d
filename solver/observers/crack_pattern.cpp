// Crack pattern metrics and the event catalogue (docs/crack_pattern.md).
#include "crack_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "error.hpp"
#include "output.hpp"

namespace brittle {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

const char* origin_name(TipTrack::Origin o) {
  return o == TipTrack::Origin::seed ? "notch" : o == TipTrack::Origin::nucleation ? "nucleation"
                                                                                  : "branch";
}

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
}

}  // namespace

CrackFronts fronts_from_events(const std::vector<CrackEvent>& events, double join,
                               double separation, const std::vector<FrontSeed>& seeds) {
  CrackFronts fronts(join, separation);
  for (const FrontSeed& s : seeds)
    fronts.add_seed(s.x, s.y, std::cos(s.angle_deg / kDegrees), std::sin(s.angle_deg / kDegrees));
  for (const CrackEvent& e : events)
    if (e.kind == CrackEvent::Kind::split) fronts.on_split(e.t, e.x, e.y);
  return fronts;
}

EnergyDistribution energy_distribution(const std::vector<CrackEvent>& events) {
  EnergyDistribution d;
  std::vector<double> energy, time;
  for (const CrackEvent& e : events)
    if (e.kind == CrackEvent::Kind::link_failure && e.energy > 0)
      energy.push_back(e.energy), time.push_back(e.t);
  if (energy.empty()) return d;
  const auto [lo, hi] = std::minmax_element(energy.begin(), energy.end());
  constexpr double kPerDecade = 5;
  const double first = std::floor(std::log10(*lo) * kPerDecade);
  const int bins = static_cast<int>(std::floor(std::log10(*hi) * kPerDecade) - first) + 1;
  for (int i = 0; i < bins; ++i) {
    d.bin_low.push_back(std::pow(10.0, (first + i) / kPerDecade));
    d.bin_high.push_back(std::pow(10.0, (first + i + 1) / kPerDecade));
  }
  d.count.assign(bins, 0);
  for (double e : energy) {
    const int i = std::clamp(static_cast<int>(std::floor(std::log10(e) * kPerDecade) - first), 0,
                             bins - 1);
    ++d.count[i];
  }
  // dN/dE per bin against the bin's geometric centre, in log-log.
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (int i = 0; i < bins; ++i) {
    if (d.count[i] == 0) continue;
    const double x = std::log10(std::sqrt(d.bin_low[i] * d.bin_high[i]));
    const double y = std::log10(d.count[i] / (d.bin_high[i] - d.bin_low[i]));
    sx += x, sy += y, sxx += x * x, sxy += x * y, syy += y * y, ++d.fitted_bins;
  }
  const double n = d.fitted_bins;
  if (d.fitted_bins >= 3) {
    const double cov = sxy - sx * sy / n, vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
    d.exponent = vx > 0 ? -cov / vx : 0.0;
    d.r2 = vx > 0 && vy > 0 ? cov * cov / (vx * vy) : 0.0;
  }
  d.power_law = d.fitted_bins >= 5 && d.r2 >= 0.9;
  const double t0 = time.front(), t1 = time.back(), width = (t1 - t0) / 20;
  if (width > 0) {
    d.rate.assign(20, 0.0);
    for (double t : time) d.rate[std::min(19, static_cast<int>((t - t0) / width))] += 1 / width;
    for (int i = 0; i < 20; ++i) d.rate_time.push_back(t0 + (i + 0.5) * width);
  }
  return d;
}

namespace {

/// Least-squares slope of the distance of a track's samples from its start against time, over
/// the samples from its start on (fit_speed, as every speed of crack_tip); NaN with fewer than 3.
double chord_speed(const TipTrack& t) {
  std::vector<TipSample> from_start;
  for (const TipSample& s : t.path)
    if (s.t >= t.t_start)
      from_start.push_back({s.t, s.x, s.y, s.splits, std::hypot(s.x - t.x_start, s.y - t.y_start)});
  return fit_speed(from_start, 0, from_start.size()).speed;
}

}  // namespace

Fork find_fork(const CrackFronts& fronts, double min_length) {
  const std::vector<TipTrack>& tips = fronts.tips();
  // The longest line from each tip on through its arms, and the farthest x of its heads:
  // arms are born after their parent (higher ids), so a pass from the last tip down has
  // folded every arm's line into line[i] before tip i adds its own arc.
  std::vector<double> line(tips.size(), 0.0), reach(tips.size(), 0.0);
  std::vector<int> end(tips.size(), -1);
  for (std::size_t i = tips.size(); i-- > 0;) {
    const TipTrack& t = tips[i];
    const TipSample head = fronts.head(t.id);
    line[i] += t.arc.empty() ? 0.0 : t.arc.back();
    reach[i] = std::max(reach[i], head.x);
    if (end[i] < 0) end[i] = static_cast<int>(i);
    if (t.parent >= 0 && t.origin == TipTrack::Origin::branch) {
      const auto p = static_cast<std::size_t>(t.parent);
      if (end[p] < 0 || line[i] > line[p]) line[p] = line[i], end[p] = end[i];
      reach[p] = std::max(reach[p], reach[i]);
    }
  }
  Fork f;
  const BranchingEvent* first = nullptr;
  for (const BranchingEvent& b : fronts.branchings()) {
    if (b.child_a < 0 || b.child_b < 0) continue;
    if (line[b.child_a] < min_length || line[b.child_b] < min_length) continue;
    if (!first || b.t < first->t) first = &b;
  }
  if (!first) return f;
  f.found = true;
  f.t = first->t, f.x = first->x, f.y = first->y, f.angle_deg = first->angle_deg;
  int k = 0;
  for (int arm : {first->child_a, first->child_b}) {
    Fork::Arm& a = f.arms[k++];
    const TipSample head = fronts.head(tips[end[arm]].id);
    a.tip = arm, a.length = line[arm], a.reach_x = reach[arm];
    a.t = head.t, a.x = head.x, a.y = head.y;
  }
  return f;
}

CrackPattern crack_pattern(const CrackFronts& fronts, const std::vector<CrackEvent>& events,
                           const std::vector<TipSample>& tips, double T, double min_length,
                           double rayleigh_speed) {
  CrackPattern p;
  p.rayleigh_speed = rayleigh_speed;
  p.min_length = min_length;
  p.join = fronts.join();
  p.separation = fronts.separation();
  p.thickness = T;
  std::vector<int> branch_of(fronts.tips().size(), -1);
  for (const TipTrack& t : fronts.tips()) {
    if (t.origin == TipTrack::Origin::seed)
      p.seeds.push_back({t.x_start, t.y_start, t.start_angle_deg});
    const double length = t.arc.empty() ? 0.0 : t.arc.back();
    if (length < min_length) {
      ++p.spurs;
      continue;
    }
    const TipSample head = fronts.head(t.id);
    Branch b;
    b.tip = t.id;
    b.origin = origin_name(t.origin);
    b.parent = t.parent;
    b.t_start = t.t_start, b.x_start = t.x_start, b.y_start = t.y_start;
    b.t_end = head.t, b.x_end = head.x, b.y_end = head.y;
    b.length = length;
    b.angle_deg = kDegrees * std::atan2(head.y - t.y_start, head.x - t.x_start);
    b.speed = fronts.speed(t.id).speed;
    b.chord_speed = chord_speed(t);
    // No crack in the model outruns v_R (docs/crack_fronts.md): a faster track is not one tip.
    if (b.speed > rayleigh_speed) {
      std::ostringstream note;
      note << std::lround(b.speed) << " m/s along the path is above v_R = "
           << std::lround(rayleigh_speed) << " m/s: ";
      if (b.chord_speed <= rayleigh_speed)
        note << "the track zigzags through a failure zone wider than the tracker's join (its "
                "head moves away from the start at "
             << std::lround(b.chord_speed) << " m/s)";
      else
        note << "its head also moves away from its start faster than v_R ("
             << std::lround(b.chord_speed)
             << " m/s): a failure front through material already near sigma_c, not one crack tip";
      b.speed_note = note.str();
    }
    p.branches.push_back(b);
  }
  p.branchings = fronts.branchings();
  p.nucleations = fronts.nucleations();
  for (const CrackEvent& e : events) {
    if (e.kind == CrackEvent::Kind::split) ++p.splits, p.split_area += e.area;
    else ++p.link_failures, p.failure_energy += e.energy;
  }
  p.distribution = energy_distribution(events);
  p.fork = find_fork(fronts, min_length);
  // Area made by the splits up to each tip sample (events and samples are both in time order).
  std::size_t next = 0;
  double area = 0;
  const double s0 = tips.empty() ? 0.0 : tips.front().s;
  for (const TipSample& s : tips) {
    for (; next < events.size() && events[next].t <= s.t; ++next)
      if (events[next].kind == CrackEvent::Kind::split) area += events[next].area;
    const double advance = s.s - s0;
    p.area.push_back({s.t, advance, area,
                      advance > 0 && T > 0 ? area / (2 * T * advance)
                                           : std::numeric_limits<double>::quiet_NaN()});
  }
  return p;
}

void write_events_csv(const std::string& path, const std::vector<CrackEvent>& events) {
  std::ostringstream csv;
  csv << "time,kind,x,y,z,energy,area,node_a,node_b\n" << std::setprecision(17);
  for (const CrackEvent& e : events)
    csv << e.t << ',' << (e.kind == CrackEvent::Kind::split ? "split" : "link_failure") << ','
        << e.x << ',' << e.y << ',' << e.z << ',' << e.energy << ',' << e.area << ',' << e.a << ','
        << e.b << '\n';
  write_file_atomically(path, csv.str());
}

std::vector<CrackEvent> read_events_csv(const std::string& path) {
  std::ifstream in(path);
  BRITTLE_CHECK(in, "events '", path, "': cannot be read (expected a run directory's events.csv)");
  std::string line;
  BRITTLE_CHECK(std::getline(in, line) && line.starts_with("time,kind,"), "events '", path,
                "': line 1 is not the events.csv header");
  std::vector<CrackEvent> events;
  long number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    std::istringstream row(line);
    std::string field[9];
    int n = 0;
    while (n < 9 && std::getline(row, field[n], ',')) ++n;
    CrackEvent e;
    try {
      BRITTLE_CHECK(n == 9 && (field[1] == "split" || field[1] == "link_failure"), "");
      e.t = std::stod(field[0]);
      e.kind = field[1] == "split" ? CrackEvent::Kind::split : CrackEvent::Kind::link_failure;
      e.x = std::stod(field[2]), e.y = std::stod(field[3]), e.z = std::stod(field[4]);
      e.energy = std::stod(field[5]), e.area = std::stod(field[6]);
      e.a = std::stoll(field[7]), e.b = std::stoll(field[8]);
    } catch (const std::exception&) {
      throw Error(error_message("events '", path, "': line ", number,
                                " is not time,kind(split|link_failure),x,y,z,energy,area,node_a,"
                                "node_b"));
    }
    BRITTLE_CHECK(std::isfinite(e.t) && std::isfinite(e.x) && std::isfinite(e.y), "events '",
                  path, "': line ", number, " has a time or position that is not finite");
    BRITTLE_CHECK(events.empty() || e.t >= events.back().t, "events '", path, "': line ", number,
                  " goes back in time");
    events.push_back(e);
  }
  return events;
}

void write_pattern(const std::string& directory, const CrackPattern& p) {
  std::ostringstream csv;
  csv << "tip,origin,parent,t_start,x_start,y_start,t_end,x_end,y_end,length,angle_deg,speed,"
         "chord_speed,speed_above_rayleigh\n"
      << std::setprecision(12);
  for (const Branch& b : p.branches)
    csv << b.tip << ',' << b.origin << ',' << b.parent << ',' << b.t_start << ',' << b.x_start << ','
        << b.y_start << ',' << b.t_end << ',' << b.x_end << ',' << b.y_end << ',' << b.length << ','
        << b.angle_deg << ',' << b.speed << ',' << b.chord_speed << ','
        << (b.speed_note.empty() ? 0 : 1) << '\n';
  write_file_atomically(directory + "/branches.csv", csv.str());

  nlohmann::ordered_json j;
  j["branches"] = p.branches.size();
  j["spurs"] = p.spurs;
  j["min_branch_length"] = number(p.min_length);
  add_branchings_json(j, "branching_points", p.branchings, p.nucleations);
  if (p.fork.found) {
    const Fork& f = p.fork;
    nlohmann::ordered_json fork = {{"t", number(f.t)}, {"x", number(f.x)}, {"y", number(f.y)},
                                   {"angle_deg", number(f.angle_deg)}};
    fork["arms"] = nlohmann::ordered_json::array();
    for (const Fork::Arm& a : f.arms)
      fork["arms"].push_back({{"tip", a.tip},
                              {"length", number(a.length)},
                              {"head", {number(a.t), number(a.x), number(a.y)}},
                              {"reach_x", number(a.reach_x)}});
    j["fork"] = fork;
  } else {
    j["fork"] = nullptr;
  }
  j["tips"] = nlohmann::ordered_json::array();
  for (const Branch& b : p.branches)
    j["tips"].push_back({{"tip", b.tip},
                         {"origin", b.origin},
                         {"head", {number(b.t_end), number(b.x_end), number(b.y_end)}},
                         {"length", number(b.length)},
                         {"angle_deg", number(b.angle_deg)},
                         {"speed", number(b.speed)},
                         {"chord_speed", number(b.chord_speed)},
                         {"speed_note", b.speed_note}});
  j["splits"] = p.splits;
  j["link_failures"] = p.link_failures;
  j["crack_area"] = number(p.split_area);
  j["link_failure_energy"] = number(p.failure_energy);
  const EnergyDistribution& d = p.distribution;
  nlohmann::ordered_json dist;
  dist["bins_per_decade"] = 5;
  dist["bin_low"] = d.bin_low;
  dist["bin_high"] = d.bin_high;
  dist["count"] = d.count;
  dist["power_law_exponent"] = number(d.exponent);
  dist["power_law_r2"] = number(d.r2);
  dist["fitted_bins"] = d.fitted_bins;
  dist["power_law"] = d.power_law;
  dist["rate_time"] = d.rate_time;
  dist["rate"] = d.rate;
  j["link_failure_energy_distribution"] = dist;
  j["area_against_advance"] = nlohmann::ordered_json::array();
  for (const AreaSample& a : p.area)
    j["area_against_advance"].push_back(
        {number(a.t), number(a.advance), number(a.area), number(a.effective)});
  j["tracker"] = {{"join", number(p.join)},
                  {"separation", number(p.separation)},
                  {"thickness", number(p.thickness)},
                  {"rayleigh_speed", number(p.rayleigh_speed)}};
  j["seeds"] = nlohmann::ordered_json::array();
  for (const FrontSeed& s : p.seeds)
    j["seeds"].push_back({number(s.x), number(s.y), number(s.angle_deg)});
  write_file_atomically(directory + "/pattern.json", j.dump(2) + "\n");
}

void PatternWriter::on_finish(const Simulation& sim, const RunSummary&) {
  write_events_csv(directory_ + "/events.csv", sim.events());
  const double min_length = sim.scene().fracture.min_branch_length > 0
                                ? sim.scene().fracture.min_branch_length
                                : sim.fronts().join();
  const ElasticConstants c = ElasticConstants::from(sim.scene().material);
  write_pattern(directory_, crack_pattern(sim.fronts(), sim.events(), sim.tip_samples(),
                                          sim.scene().geometry.T, min_length,
                                          rayleigh_speed(c.c_p, c.c_s)));
}

}  // namespace brittle
