// The paper's Figs. 5-6 (crack speed against strain energy for load sweeps, over the Zhou et
// al. fit) and the one command that regenerates every reproduced figure.
#pragma once

#include <string>
#include <vector>

#include "sweep.hpp"

namespace brittle {

/// One sweep as a chart series: its label and its points.
struct SweepSeries {
  std::string label;
  std::vector<SweepPoint> points;
};

/// Draws speed against W: the series as points over the Zhou fit (1.1), the Rayleigh speed and
/// the damped Rayleigh speed sqrt(1 - Omega_d0) v_R as lines; writes a PNG.
void write_speed_chart(const std::string& path, const std::string& title,
                       const std::vector<SweepSeries>& series);

/// `brittle chart SWEEP_DIR[=LABEL] ... --out FIG.png [--title T]`: redraws a chart from
/// finished sweeps (their run directories and sweep.csv).
int chart_command(const std::vector<std::string>& args);

/// `brittle tips RUN_DIR[=LABEL]... --out FIG.png`: the leading tip's speed against time from
/// each run's crack_tip.csv, as a VTK chart (docs/benchmarks.md).
int tips_command(const std::vector<std::string>& args);

/// `brittle reproduce [--out DIR] [--scenes DIR] [--loads SPEC] [--meshes cm,rm] [--jobs N]
/// [--no-frames]`: the eight sweeps of Figs. 5-6 (RI/RD links x damage off/on x CM/RM),
/// fig05.png (no damage; the paper's Fig. 6a shows the same runs) and fig06b.png (with
/// damage) with their CSV, and Figs. 7-10 (`brittle figure`).
int reproduce_command(const std::vector<std::string>& args);

}  // namespace brittle
