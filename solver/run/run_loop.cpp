// The run loop (SPEC 4): Simulation::run steps to the end time, calls the observers at every
// energy row, frame and checkpoint, shows progress, and stops on a cut-through, a blow-up,
// a signal or a failed writer; the frame times it follows.
#include "simulation.hpp"

#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "error.hpp"

namespace brittle {
namespace {

/// A crack's growth is checked against c_p over stretches of this many join distances: one
/// split may extend a crack by up to one join, which over one join looks fast
/// (docs/crack_fronts.md, "Fronts faster than c_p").
constexpr double kFrontSpeedJoins = 3;

}  // namespace

std::vector<double> frame_times(const Scene& scene) {
  const OutputParams& o = scene.output;
  const double end = scene.run.end_time;
  std::vector<double> times;
  if (!o.frame_times.empty()) {
    times = o.frame_times;
  } else if (o.frame_interval > 0) {
    const long n = static_cast<long>(std::floor(end / o.frame_interval * (1 + 1e-12)));
    // k * interval to 15 significant digits: the decimal a user writes ("5e-6" for the fifth
    // 1 us frame, not 5.000000000000001e-06), so that a frame and an end time meet exactly.
    for (long k = 0; k <= n; ++k) {
      char text[32];
      std::snprintf(text, sizeof text, "%.15g", k * o.frame_interval);
      times.push_back(std::strtod(text, nullptr));
    }
  }
  if (!scene.render.times.empty()) {  // [render] times are frames too
    times.insert(times.end(), scene.render.times.begin(), scene.render.times.end());
    std::sort(times.begin(), times.end());
    times.erase(
        std::unique(times.begin(), times.end(),
                    [](double a, double b) { return std::abs(a - b) <= 1e-12 * std::abs(b); }),
        times.end());
  }
  std::erase_if(times, [end](double t) { return t > end * (1 + 1e-12); });
  return times;
}

std::vector<double> Simulation::frame_times() const { return brittle::frame_times(scene_); }

RunSummary Simulation::run(const std::vector<Observer*>& observers, Checkpointer* checkpointer) {
  RunSummary summary;
  summary.nodes = initial_points_;
  summary.tets = grid_.num_cells();
  summary.fixed_nodes = fixed_nodes_;
  summary.sigma = sigma_;
  summary.dt = initial_dt_;
  summary.end_time = scene_.run.end_time;
  summary.threads = omp_get_max_threads();
  RunProgress& p = progress_;
  const double checkpoint_interval = scene_.output.checkpoint_interval;
  BRITTLE_CHECK(checkpoint_interval <= 0 || checkpointer,
                "output.checkpoint_interval: this run has no checkpoint writer (Simulation::run)");
  if (!resumed_) {
    initial_energy_ = energies().total();
    p.next_checkpoint = checkpoint_interval;
  }
  summary.initial_elastic = initial_energy_;

  const std::vector<double> frames = frame_times();
  const double energy_interval = scene_.output.energy_interval;
  auto due = [this](double t) { return time_ >= t - 0.5 * dt_; };
  auto warn = [&](const std::string& w) {
    // (once in the summary: a resumed run gives its start warnings again)
    if (std::find(p.warnings.begin(), p.warnings.end(), w) == p.warnings.end())
      p.warnings.push_back(w);
    for (Observer* o : observers) o->on_warning(*this, w);
  };
  std::string local_error;  // this rank's first error since the last agreement (below)
  // Observers called on every rank of a decomposed run (some of them collective, e.g. the
  // sensors) must not leave one rank alone on an error: each call's error is kept for the
  // next agreement, and every observer is still called.
  auto each = [&](auto&& call) {
    for (Observer* o : observers) {
      if (!halo_) {
        call(o);
        continue;
      }
      try {
        call(o);
      } catch (const std::exception& e) {
        if (local_error.empty()) local_error = e.what();
      }
    }
  };
  // Energy row and frame if due; returns whether a frame was written.
  auto emit = [&]() {
    PhaseClock clock;
    if (due(p.next_energy)) {
      const Energies e = energies();
      const double imbalance =
          e.reference > 0 ? std::abs(e.total() - initial_energy_) / e.reference : 0.0;
      p.max_relative_imbalance = std::max(p.max_relative_imbalance, imbalance);
      if (imbalance > scene_.output.imbalance_warning && !p.imbalance_warned) {
        p.imbalance_warned = true;
        warn(error_message(
            "energy budget off by ", 100 * imbalance, " % of the energy in the body at t = ", time_,
            " s (threshold ", 100 * scene_.output.imbalance_warning,
            " %): the step may be too large (run.cfl) or a mechanism is mis-accounted"));
      }
      for (Observer* o : observers) o->on_energy(*this, e);
      ++p.energy_rows;
      // The tip is on the crack grown from a notch: a split not connected to it (a crack
      // nucleated ahead) does not move it (docs/crack_fronts.md, "The tip"). On the paper's
      // plate it is that crack's largest x (SPEC 5); with [notch.NAME] sections its split
      // farthest from the notch tip, s the distance.
      TipSample sample{time_, cracks_.tip_x(), cracks_.tip_y(), fracture_.splits(),
                       cracks_.tip_x()};
      if (!scene_.geometry.notches.empty()) {
        const ConnectedCracks::Reached far = cracks_.farthest();
        sample.x = far.x, sample.y = far.y, sample.s = far.reach;
      }
      sample.max_split_x = fracture_.splits() > 0 ? fracture_.tip_x() : sample.x;
      sample.nucleations = static_cast<long>(cracks_.nucleations().size());
      tip_samples_.push_back(sample);
      while (due(p.next_energy)) p.next_energy += energy_interval;
    }
    bool frame = false;
    if (p.next_frame < frames.size() && due(frames[p.next_frame])) {
      update_output_fields();
      each([&](Observer* o) { o->on_frame(*this); });
      ++p.frames_written;
      frame = true;
      while (p.next_frame < frames.size() && due(frames[p.next_frame])) ++p.next_frame;
    }
    clock.lap(own_times_.output);
    return frame;
  };
  auto checkpoint = [&]() {
    if (!checkpointer) return;
    PhaseClock clock;
    const std::string path = checkpointer->path(*this);
    const auto t0 = std::chrono::steady_clock::now();
    summary.checkpoint_bytes = checkpointer->write(*this);  // decomposed: collective
    summary.checkpoint_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++summary.checkpoints;
    summary.checkpoint = path;
    summary.checkpoint_time = time_;
    each([&](Observer* o) { o->on_checkpoint(*this, path); });
    clock.lap(own_times_.output);
  };
  auto stop_requested = [this]() { return stop_flag_ && stop_flag_->load() != 0; };
  // A decomposed run agrees before every step: a stop asked on any rank stops all, and a
  // writer that failed on one rank fails the run on all (the first rank's error is named).
  auto agreed = [&](bool stop) {
    if (!halo_) return stop;
    std::string first;
    stop = halo_->agree(local_error, stop, first);  // one reduction
    if (!first.empty()) throw Error(first);
    return stop;
  };
  auto emit_here = [&]() {
    if (!halo_) return emit();
    try {  // kept for the agreement above; collectives inside emit() ran on every rank
      return emit();
    } catch (const std::exception& e) {
      if (local_error.empty()) local_error = e.what();
      return false;
    }
  };

  if (resumed_) each([&](Observer* o) { o->on_resume(*this); });
  each([&](Observer* o) { o->on_start(*this); });
  agreed(false);  // a decomposed run: an error above, on any rank, ends every rank here
  try {
    bool frame_now = resumed_ ? false : emit_here();
    bool interrupted = false;
    while (time_ < scene_.run.end_time) {
      if (agreed(stop_requested())) {
        interrupted = true;
        break;
      }
      const auto t0 = std::chrono::steady_clock::now();
      // Frames land on their times, and the run on run.end_time (the step before is shorter).
      // (A frame within a millionth of a step of the end is the end's frame: no sliver step.)
      const double end = scene_.run.end_time;
      step_towards(p.next_frame < frames.size() && frames[p.next_frame] < end - 1e-6 * dt_
                       ? frames[p.next_frame]
                       : end);
      p.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      for (const std::string& w : take_step_warnings()) warn(w);
      each([&](Observer* o) { o->on_step(*this); });
      frame_now = emit_here();
      if (checkpoint_interval > 0 && due(p.next_checkpoint)) {
        checkpoint();
        while (due(p.next_checkpoint)) p.next_checkpoint += checkpoint_interval;
      }
      if (cut_.happened && scene_.run.stop_when_cut_through) {
        summary.stopped_at_cut = true;
        break;
      }
    }
    agreed(false);  // a writer's failure at the last row or frame
    if (interrupted) {
      // The checkpoint holds the progress without the last frame below: a resumed run writes
      // its frames as the uninterrupted run would (the writers drop the extra one).
      checkpoint();
      if (!frame_now) {
        update_output_fields();
        each([&](Observer* o) { o->on_frame(*this); });
        ++p.frames_written;
      }
      summary.status = "interrupted";
    } else {
      if (summary.stopped_at_cut && !frame_now) {  // the last frame shows the cut plate
        update_output_fields();
        each([&](Observer* o) { o->on_frame(*this); });
        ++p.frames_written;
      }
      if (checkpoint_interval > 0 &&
          (summary.checkpoint.empty() || summary.checkpoint_time != time_))
        checkpoint();  // so that the run can be extended (--resume with a later run.end_time)
      summary.status = "completed";
    }
  } catch (const std::exception& e) {  // a blow-up, or a writer (disk full, bad_alloc, ...)
    summary.status = std::string("failed: ") + e.what();
    for (const std::string& w : take_step_warnings()) warn(w);  // they may explain the failure
  }
  summary.cut_through = cut_;
  summary.warnings = p.warnings;
  summary.max_relative_imbalance = p.max_relative_imbalance;
  const double wall = p.wall_seconds;
  summary.time = time_;
  summary.steps = steps_;
  summary.wall_seconds = wall;
  summary.final_energies = energies();
  summary.splits = fracture_.splits();
  summary.crack_area = fracture_.crack_area();
  summary.live_links = static_cast<long>(links_.links().size());
  if (halo_) {  // the whole grid's counts (wall times are this rank's)
    summary.nodes = halo_->initial_nodes();
    summary.tets = halo_->cells();
    long fixed = 0;
    for (vtkIdType i = 0; i < initial_points_; ++i)
      fixed += halo_->owned()[i] && (grid_.fixed()[i] & 7) != 0;
    summary.fixed_nodes = halo_->sum(fixed);
    summary.live_links = halo_->sum(summary.live_links);
    const Halo::Traffic t = halo_->traffic();
    summary.collectives = t.collectives;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const std::vector<double> all = halo_->gather_all(
        {double(grid_.num_cells()), double(usage.ru_maxrss), double(t.bytes_sent), double(t.messages)});
    for (std::size_t i = 0; i + 3 < all.size(); i += 4)
      summary.ranks.push_back({long(all[i]), long(all[i + 1]), long(all[i + 2]), long(all[i + 3])});
  }
  summary.tet_updates_per_second = wall > 0 ? double(steps_) * summary.tets / wall : 0.0;
  summary.final_dt = dt_;
  summary.dt_reductions = dt_reductions_;
  summary.substep_cap_steps = substep_cap_steps_;
  if (!tip_samples_.empty()) {
    summary.tip_x = tip_samples_.back().x, summary.tip_y = tip_samples_.back().y;
    summary.max_split_x = tip_samples_.back().max_split_x;
  }
  summary.speed_stop_x = scene_.geometry.L - scene_.fracture.speed_edge_margin;
  if (scene_.geometry.notches.empty()) {
    // The window ends at the far edge, or at the first crack nucleated ahead of the tip:
    // what follows is two cracks (issue 16; docs/crack_fronts.md, "The tip").
    double nucleated_ahead = std::numeric_limits<double>::infinity();
    for (const ConnectedCracks::Start& n : cracks_.nucleations()) {
      double tip = scene_.geometry.notch_depth;  // the tip when it nucleated
      for (const TipSample& s : tip_samples_)
        if (s.t <= n.t) tip = s.x;
      if (n.x > tip) {
        nucleated_ahead = n.t;
        break;
      }
    }
    const double stop_x = summary.speed_stop_x;
    summary.crack_speed = steady_speed_until(
        tip_samples_, scene_.fracture.speed_window_start,
        [&](const TipSample& s) { return s.x >= stop_x || s.t >= nucleated_ahead; });
    if (summary.crack_speed.samples >= 3) {
      const double t_end = summary.crack_speed.t_end;
      const auto last = std::find_if(tip_samples_.begin(), tip_samples_.end(),
                                     [&](const TipSample& s) { return s.t == t_end; });
      summary.speed_window_end = t_end >= nucleated_ahead   ? "nucleation ahead"
                                 : last->x >= stop_x        ? "far edge"
                                                            : "end of run";
    }
  } else {  // the window ends when the leading tip comes within the margin of the outline
    const GeometryParams& g = scene_.geometry;
    const double margin = scene_.fracture.speed_edge_margin;
    summary.crack_speed = steady_speed_until(
        tip_samples_, scene_.fracture.speed_window_start, [&](const TipSample& p) {
          return std::min({p.x, g.L - p.x, p.y + 0.5 * g.H, 0.5 * g.H - p.y}) <= margin;
        });
    if (summary.crack_speed.samples >= 3) {
      const TipSample& last = *std::find_if(
          tip_samples_.begin(), tip_samples_.end(),
          [&](const TipSample& s) { return s.t == summary.crack_speed.t_end; });
      summary.speed_window_end =
          std::min({last.x, g.L - last.x, last.y + 0.5 * g.H, 0.5 * g.H - last.y}) <= margin
              ? "far edge"
              : "end of run";
    }
  }
  // A failure front faster than c_p (issue 16): no crack runs faster than c_R < c_s < c_p; a
  // front that does is the criterion firing wherever the load alone reaches sigma_c
  // (docs/crack_fronts.md, "Fronts faster than c_p").
  const ConnectedCracks::FastGrowth fast =
      cracks_.first_faster_than(constants_.c_p, kFrontSpeedJoins * fronts_.join(), initial_dt_);
  if (fast.t >= 0) {
    summary.super_cp_front = {true, fast.t, fast.speed, constants_.c_p, fast.x, fast.y};
    const std::string w = error_message(
        "a failure front ran faster than c_p at t = ", fast.t * 1e6, " us, (", fast.x * 1e3,
        ", ", fast.y * 1e3, ") mm (", std::lround(fast.speed), " m/s > c_p = ",
        std::lround(constants_.c_p),
        " m/s): not a physical crack; the criterion fires wherever the load alone reaches "
        "sigma_c (docs/crack_fronts.md)");
    summary.warnings.push_back(w);
    for (Observer* o : observers) o->on_warning(*this, w);
  }
  summary.W = strain_energy_per_area(scene_.geometry.H, sigma_, scene_.material.E);
  summary.W_clamped = summary.W * (1 - scene_.material.nu * scene_.material.nu);
  summary.zhou_speed = zhou_speed(summary.W);
  summary.phases = phases();
  // Every observer gets on_finish (the summary is written after the CSVs); the first error
  // is the one reported, in the status of the observers after it and by the throw below.
  for (Observer* o : observers) {
    try {
      o->on_finish(*this, summary);
    } catch (const std::exception& e) {
      if (!summary.status.starts_with("failed: "))
        summary.status = std::string("failed: ") + e.what();
    }
  }
  if (summary.status.starts_with("failed: ")) throw Error(summary.status.substr(8));
  return summary;
}

}  // namespace brittle
