// summary.json (SPEC 9): every RunSummary field, numbers that are not finite as null.

#include "output.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "build_info.hpp"
#include "crack_pattern.hpp"
#include "sensors.hpp"

namespace brittle {

namespace {
/// JSON has no NaN or infinity: a number that is not finite is written as null.
nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}
}  // namespace

void add_branchings_json(nlohmann::ordered_json& j, const std::string& key,
                         const std::vector<BranchingEvent>& branchings,
                         const std::vector<Nucleation>& nucleations) {
  j[key] = nlohmann::ordered_json::array();
  for (const BranchingEvent& b : branchings)
    j[key].push_back({{"t", number(b.t)},
                      {"x", number(b.x)},
                      {"y", number(b.y)},
                      {"angle_deg", number(b.angle_deg)},
                      {"parent", b.parent},
                      {"children", {b.child_a, b.child_b}}});
  j["nucleations"] = nlohmann::ordered_json::array();
  for (const Nucleation& n : nucleations)
    j["nucleations"].push_back(
        {{"t", number(n.t)}, {"x", number(n.x)}, {"y", number(n.y)}, {"tip", n.tip}});
}

std::string summary_json(const Simulation& sim, const RunSummary& s) {
  const Energies& e = s.final_energies;
  nlohmann::ordered_json j;
  j["status"] = s.status;
  // Values every run defines (energies, times, dt, the load): one that is not finite means
  // the run went wrong (a blow-up); it is null, and the status names it. Values that may be
  // undefined (a speed fitted to fewer than 3 samples, a tip that has not moved yet) are
  // null without a word: docs/scenes.md, "When a run fails".
  std::vector<std::string> non_finite;
  auto measured = [&](const std::string& key, double v) {
    if (!std::isfinite(v)) non_finite.push_back(key);
    return number(v);
  };
  j["scene_sources"] = sim.scene().sources;
  j["brittle_version"] = BRITTLE_VERSION;
  const BuildInfo& build = build_info();  // what made this binary
  j["build"] = {{"version", build.version},
                {"commit", build.commit},
                {"compiler", build.compiler},
                {"build_type", build.build_type},
                {"flags", build.flags}};
  if (!sim.scene().resolved.empty()) {  // every key's value, as in the run's scene.ini
    nlohmann::json scene = nlohmann::json::object();
    for (const auto& [key, value] : sim.scene().resolved) scene[key] = value;
    j["scene"] = scene;
  }
  j["nodes"] = s.nodes;
  j["tets"] = s.tets;
  j["fixed_nodes"] = s.fixed_nodes;
  j["sigma"] = measured("sigma", s.sigma);
  j["sigma_over_sigmac"] = measured("sigma_over_sigmac", s.sigma / sim.scene().material.sigma_c);
  j["dt"] = measured("dt", s.dt);
  j["final_dt"] = measured("final_dt", s.final_dt);
  // Where the step comes from (issue 38; docs/performance.md), to 9 significant digits: a
  // decomposed run's part computes a few elements' steps from its own copy of their corners
  // and volumes, which can differ from the serial run's in the last bit (dt itself does not).
  if (const StepDistribution& d = sim.step_distribution(); d.elements > 0) {
    const auto nine = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.9g", v);
      return number(std::strtod(text, nullptr));
    };
    j["step_distribution"] = {
        {"smallest", nine(d.smallest)},
        {"p1", nine(d.p1)},
        {"median", nine(d.median)},
        {"element", d.element},
        {"centroid", {nine(d.centroid[0]), nine(d.centroid[1]), nine(d.centroid[2])}},
        {"altitude", nine(d.altitude)},
        {"damping_ratio", nine(d.xi)},
        {"median_altitude", nine(d.median_altitude)},
        {"within_10_percent", d.within_10_percent}};
  } else {
    j["step_distribution"] = nullptr;
  }
  if (const MassScaling& m = sim.mass_scaling(); m.target > 0)
    j["mass_scaling"] = {{"target_dt", number(m.target)},
                         {"elements", m.elements},
                         {"mass", number(m.mass)},
                         {"added_mass", number(m.added)},
                         {"added_fraction", number(m.added / m.mass)},
                         {"largest_factor", number(m.largest)},
                         {"largest_element", m.element}};
  else
    j["mass_scaling"] = nullptr;
  j["dt_reductions"] = s.dt_reductions;
  j["substep_cap_steps"] = s.substep_cap_steps;
  j["end_time"] = measured("end_time", s.end_time);
  j["time"] = measured("time", s.time);
  j["steps"] = s.steps;
  j["threads"] = s.threads;
  j["wall_seconds"] = measured("wall_seconds", s.wall_seconds);
  j["tet_updates_per_second"] = measured("tet_updates_per_second", s.tet_updates_per_second);
  for (const auto& [name, seconds] : s.phases.named())
    j["phases"][name] = measured(std::string("phases.") + name, seconds);
  if (!s.ranks.empty()) {  // a decomposed run: what each rank held, used and sent
    nlohmann::ordered_json& d = j["decomposition"];
    d["collectives"] = s.collectives;
    d["collectives_per_step"] = s.steps > 0 ? double(s.collectives) / s.steps : 0.0;
    for (std::size_t r = 0; r < s.ranks.size(); ++r) {
      const RunSummary::Rank& k = s.ranks[r];
      d["ranks"].push_back({{"rank", r},
                            {"tets", k.tets},
                            {"peak_rss_mb", k.peak_rss_kb / 1024.0},
                            {"ghost_bytes_per_step", s.steps > 0 ? double(k.bytes_sent) / s.steps : 0.0},
                            {"messages_per_step", s.steps > 0 ? double(k.messages) / s.steps : 0.0}});
    }
  }
  j["initial_energy"] = measured("initial_energy", s.initial_elastic);
  j["final_kinetic"] = measured("final_kinetic", e.kinetic);
  j["final_elastic"] = measured("final_elastic", e.elastic);
  j["viscous_dissipated"] = measured("viscous_dissipated", e.viscous_dissipated);
  j["cohesive_stored"] = measured("cohesive_stored", e.cohesive_stored);
  j["cohesive_dissipated"] = measured("cohesive_dissipated", e.cohesive_dissipated);
  j["damage_dissipated"] = measured("damage_dissipated", e.damage_dissipated);
  j["external_work"] = measured("external_work", e.external_work);
  j["warnings"] = s.warnings;
  j["max_relative_imbalance"] = measured("max_relative_imbalance", s.max_relative_imbalance);
  j["splits"] = s.splits;
  j["live_links"] = s.live_links;
  j["crack_area"] = measured("crack_area", s.crack_area);
  j["tip_x"] = measured("tip_x", s.tip_x);
  j["tip_y"] = measured("tip_y", s.tip_y);
  if (s.cut_through.happened)  // the plate cut through: when, where, and whether the run stopped
    j["cut_through"] = {{"t", number(s.cut_through.t)},
                        {"x", number(s.cut_through.x)},
                        {"y", number(s.cut_through.y)},
                        {"tip", s.cut_through.tip},
                        {"stopped", s.stopped_at_cut}};
  else
    j["cut_through"] = nullptr;
  j["crack_speed"] = number(s.crack_speed.speed);
  j["crack_speed_samples"] = s.crack_speed.samples;
  j["crack_speed_window"] = {number(s.crack_speed.t_begin), number(s.crack_speed.t_end)};
  j["crack_speed_r2"] = number(s.crack_speed.r2);
  j["crack_speed_window_end"] = s.speed_window_end;
  j["max_split_x"] = number(s.max_split_x);
  j["nucleated_cracks"] = nlohmann::ordered_json::array();  // ConnectedCracks: issue 16
  for (const ConnectedCracks::Start& n : sim.cracks().nucleations())
    j["nucleated_cracks"].push_back({{"t", number(n.t)}, {"x", number(n.x)}, {"y", number(n.y)}});
  if (s.super_cp_front.happened)
    j["super_cp_front"] = {{"t", number(s.super_cp_front.t)},
                           {"speed", number(s.super_cp_front.speed)},
                           {"c_p", number(s.super_cp_front.c_p)},
                           {"x", number(s.super_cp_front.x)},
                           {"y", number(s.super_cp_front.y)}};
  else
    j["super_cp_front"] = nullptr;
  j["speed_stop_x"] = measured("speed_stop_x", s.speed_stop_x);
  j["checkpoint"] = nullptr;  // the last checkpoint written (docs/checkpoint.md), if any
  j["checkpoint_time"] = nullptr;
  if (!s.checkpoint.empty()) j["checkpoint"] = s.checkpoint, j["checkpoint_time"] = number(s.checkpoint_time);
  j["checkpoints_written"] = s.checkpoints;
  j["checkpoint_bytes"] = s.checkpoint_bytes;
  j["checkpoint_seconds"] = number(s.checkpoint_seconds);
  j["W"] = measured("W", s.W);
  j["W_clamped"] = measured("W_clamped", s.W_clamped);
  j["zhou_speed"] = measured("zhou_speed", s.zhou_speed);
  // Every crack tip, branching and nucleation (docs/crack_fronts.md); positions reference.
  const CrackFronts& fronts = sim.fronts();
  j["tips"] = nlohmann::ordered_json::array();
  for (const TipTrack& t : fronts.tips()) {
    const TipSample head = fronts.head(t.id);
    const SpeedFit v = fronts.speed(t.id);
    nlohmann::ordered_json tip;
    tip["id"] = t.id;
    tip["origin"] = t.origin == TipTrack::Origin::seed         ? "notch"
                    : t.origin == TipTrack::Origin::nucleation ? "nucleation"
                                                               : "branch";
    tip["parent"] = t.parent;
    tip["start"] = {number(t.t_start), number(t.x_start), number(t.y_start)};
    tip["start_angle_deg"] = number(t.start_angle_deg);
    tip["departure_angle_deg"] = number(fronts.departure_angle_deg(t.id, fronts.separation()));
    tip["head"] = {number(head.t), number(head.x), number(head.y)};
    tip["length"] = number(t.arc.empty() ? 0.0 : t.arc.back());
    tip["speed"] = number(v.speed);
    tip["speed_samples"] = v.samples;
    tip["active"] = t.active;
    j["tips"].push_back(tip);
  }
  j["leading_tip"] = fronts.leading();
  add_branchings_json(j, "branchings", fronts.branchings(), fronts.nucleations());
  if (!non_finite.empty()) {
    std::string names;
    for (const std::string& name : non_finite) names += (names.empty() ? "" : ", ") + name;
    j["status"] = s.status + "; non-finite values written as null: " + names;
  }
  return j.dump(2) + "\n";
}

void SummaryWriter::on_finish(const Simulation& sim, const RunSummary& s) {
  write_file_atomically(directory_ + "/summary.json", summary_json(sim, s));
}

}  // namespace brittle
