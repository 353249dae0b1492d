// Acoustic-emission sensors and their spectra (docs/acoustic_emission.md).
#include "sensors.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <cstdio>
#include <sstream>
#include <utility>

#include "error.hpp"
#include "output.hpp"

namespace brittle {

Spectrum amplitude_spectrum(const std::vector<double>& times, const std::vector<double>& values) {
  Spectrum s;
  if (times.size() < 4) return s;
  // The median spacing: the steps are nearly even (a step before a frame or the end is up to
  // half as long), and a short one must not multiply the samples (nor the memory).
  std::vector<double> gaps;
  for (std::size_t i = 1; i < times.size(); ++i) gaps.push_back(times[i] - times[i - 1]);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const double step = gaps[gaps.size() / 2];
  if (!(step > 0)) return s;
  const double span = times.back() - times.front();
  const std::size_t n = static_cast<std::size_t>(std::floor(span / step * (1 + 1e-12))) + 1;
  std::vector<double> u(n);
  std::size_t j = 0;
  for (std::size_t k = 0; k < n; ++k) {  // linear interpolation onto t0 + k step
    const double t = times.front() + k * step;
    while (j + 2 < times.size() && times[j + 1] < t) ++j;
    const double w = (t - times[j]) / (times[j + 1] - times[j]);
    u[k] = values[j] + std::clamp(w, 0.0, 1.0) * (values[j + 1] - values[j]);
  }
  double mean = 0;
  for (double v : u) mean += v;
  mean /= n;
  double window_sum = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double w = 0.5 - 0.5 * std::cos(2 * M_PI * k / (n - 1));  // Hann
    u[k] = (u[k] - mean) * w;
    window_sum += w;
  }
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> X;
  fft.fwd(X, u);
  double best = -1, weighted = 0, total = 0;
  for (std::size_t k = 0; k <= n / 2; ++k) {
    const double f = k / (n * step), a = (k == 0 ? 1.0 : 2.0) * std::abs(X[k]) / window_sum;
    s.frequency.push_back(f);
    s.amplitude.push_back(a);
    if (k == 0) continue;
    if (a > best) best = a, s.dominant = f;
    weighted += f * a, total += a;
  }
  s.centroid = total > 0 ? weighted / total : 0.0;
  return s;
}

SensorRecorder::SensorRecorder(const Scene& scene, std::string directory, bool writes)
    : sensors_(scene.sensors), directory_(std::move(directory)), writes_(writes),
      values_(scene.sensors.size()) {}

void SensorRecorder::on_start(const Simulation& sim) {
  const Grid& g = sim.grid();
  const Halo* halo = sim.halo();
  nodes_.clear(), global_.clear(), positions_.assign(3 * sensors_.size(), 0.0);
  std::vector<double> mine;  // (sensor, X) of the sensors this rank reads
  for (std::size_t k = 0; k < sensors_.size(); ++k) {
    const SensorParams& p = sensors_[k];
    // The nearest node of the reference configuration, the first on ties (nodes are in serial
    // order on every rank); a decomposed run's ranks look at their own nodes and agree.
    vtkIdType best = -1;
    double d_best = std::numeric_limits<double>::infinity();
    for (vtkIdType i = 0; i < g.num_points(); ++i) {
      if (halo && !halo->owned()[i]) continue;
      const double* X = g.X() + 3 * i;
      const double d = (X[0] - p.position[0]) * (X[0] - p.position[0]) +
                       (X[1] - p.position[1]) * (X[1] - p.position[1]) +
                       (X[2] - p.position[2]) * (X[2] - p.position[2]);
      if (d < d_best) d_best = d, best = i;
    }
    vtkIdType id = best >= 0 && halo ? halo->global_node()[best] : best;
    if (halo) {
      const vtkIdType here = id;
      halo->min_with_id(d_best, id);
      if (here != id) best = -1;
    }
    nodes_.push_back(best);
    global_.push_back(id);
    if (best >= 0) mine.insert(mine.end(), {double(k), g.X()[3 * best], g.X()[3 * best + 1],
                                            g.X()[3 * best + 2]});
  }
  const std::vector<double> all = halo ? halo->gather_all(mine) : mine;
  for (std::size_t i = 0; i + 3 < all.size(); i += 4)
    std::copy(&all[i + 1], &all[i + 4], &positions_[3 * static_cast<std::size_t>(all[i])]);
  if (sim.resumed()) return;  // on_resume kept the rows so far
  if (writes_) {
    out_ = std::make_unique<RowFile>(directory_ + "/sensors.csv", /*truncate=*/true);
    std::string header = "time";
    for (const SensorParams& p : sensors_) header += ',' + p.name;
    out_->append(header + "\n");
  }
  record(sim);
}

void SensorRecorder::on_resume(const Simulation& sim) {
  if (!writes_) return;
  // One row per step and the row at t = 0: keep what the run wrote up to its checkpoint.
  const std::string path = directory_ + "/sensors.csv";
  std::ifstream in(path);
  BRITTLE_CHECK(in, "resume: cannot read '", path, "'");
  std::string header, line, text;
  std::getline(in, header);
  text = header + "\n";
  const std::size_t keep = static_cast<std::size_t>(sim.steps()) + 1;
  while (times_.size() < keep && std::getline(in, line)) {
    std::istringstream row(line);
    std::string field;
    std::getline(row, field, ',');
    times_.push_back(std::stod(field));
    for (auto& v : values_) std::getline(row, field, ','), v.push_back(std::stod(field));
    text += line + "\n";
  }
  BRITTLE_CHECK(times_.size() == keep, "resume: '", path, "' has ", times_.size(),
                " rows, the checkpoint was taken after ", keep);
  in.close();
  write_file_atomically(path, text);
  out_ = std::make_unique<RowFile>(path, /*truncate=*/false);
}

void SensorRecorder::record(const Simulation& sim) {
  const double* v = sim.grid().v();
  std::vector<double>& mine = read_;  // (sensor, value) of the sensors this rank reads
  mine.clear();
  for (std::size_t k = 0; k < sensors_.size(); ++k) {
    if (nodes_[k] < 0) continue;
    const double* n = sensors_[k].direction;
    const double* vi = v + 3 * nodes_[k];
    mine.insert(mine.end(), {double(k), vi[0] * n[0] + vi[1] * n[1] + vi[2] * n[2]});
  }
  std::vector<double> gathered;  // a decomposed run: every rank's, on every rank
  if (sim.halo()) gathered = sim.halo()->gather_all(mine);
  if (!writes_) return;
  const std::vector<double>& all = sim.halo() ? gathered : mine;
  std::vector<double>& value = value_;
  value.resize(sensors_.size());
  for (std::size_t i = 0; i + 1 < all.size(); i += 2) value[static_cast<std::size_t>(all[i])] = all[i + 1];
  times_.push_back(sim.time());
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", sim.time());
  pending_ += text;
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    values_[i].push_back(value[i]);
    std::snprintf(text, sizeof text, ",%.17g", value[i]);
    pending_ += text;
  }
  pending_ += '\n';
  if (pending_.size() > (1 << 16)) {
    out_->append(pending_);
    pending_.clear();
  }
}

void SensorRecorder::on_step(const Simulation& sim) { record(sim); }

void SensorRecorder::on_checkpoint(const Simulation&, const std::string&) {
  if (out_ && !pending_.empty()) out_->append(std::exchange(pending_, {}));
}

void SensorRecorder::on_finish(const Simulation&, const RunSummary&) {
  if (!writes_) return;
  if (out_ && !pending_.empty()) out_->append(std::exchange(pending_, {}));
  std::vector<Spectrum> spectra;
  for (const auto& v : values_) spectra.push_back(amplitude_spectrum(times_, v));
  std::ostringstream csv;
  csv << "frequency";
  for (const SensorParams& p : sensors_) csv << ',' << p.name;
  csv << '\n' << std::setprecision(12);
  const std::size_t rows = spectra.empty() ? 0 : spectra.front().frequency.size();
  for (std::size_t k = 0; k < rows; ++k) {
    csv << spectra.front().frequency[k];
    for (const Spectrum& s : spectra) csv << ',' << s.amplitude[k];
    csv << '\n';
  }
  write_file_atomically(directory_ + "/spectra.csv", csv.str());
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    const double* X = &positions_[3 * i];
    j.push_back({{"name", sensors_[i].name},
                 {"node", global_[i]},
                 {"position", {X[0], X[1], X[2]}},
                 {"direction",
                  {sensors_[i].direction[0], sensors_[i].direction[1], sensors_[i].direction[2]}},
                 {"samples", times_.size()},
                 {"dominant_frequency", spectra[i].dominant},
                 {"centroid_frequency", spectra[i].centroid},
                 {"window", "Hann, mean removed, resampled at the smallest step"}});
  }
  write_file_atomically(directory_ + "/sensors.json", j.dump(2) + "\n");
}

}  // namespace brittle
