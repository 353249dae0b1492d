// Acoustic-emission sensors (docs/acoustic_emission.md): [sensor.NAME] nodes record their
// velocity along a direction every step into sensors.csv; at the end, amplitude spectra
// (Hann window, Eigen's FFT) into spectra.csv and a summary per sensor into sensors.json.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "output.hpp"
#include "simulation.hpp"

namespace brittle {

/// An amplitude spectrum of a uniformly sampled signal.
struct Spectrum {
  std::vector<double> frequency, amplitude;  ///< [Hz], signal units
  double dominant = 0;  ///< frequency of the largest amplitude above 0 Hz [Hz]
  double centroid = 0;  ///< sum f A / sum A over f > 0 [Hz]
};

/// The one-sided amplitude spectrum of `values` sampled at `times` (ascending; resampled
/// linearly onto a uniform grid at the smallest interval when the step changed), mean removed,
/// Hann window, amplitude 2 |X_k| / sum(w) (a sine of amplitude A gives A at its frequency).
Spectrum amplitude_spectrum(const std::vector<double>& times, const std::vector<double>& values);

/// Records the scene's sensors: sensors.csv as the run goes (time, one column per sensor:
/// velocity along its direction [m/s]), spectra.csv and sensors.json at the end. In a
/// decomposed run it is an observer of every rank: each sensor is the whole grid's nearest
/// node (the lowest global id on ties, as serial), read by the rank that owns it, and the
/// values reach the rank that writes (`writes`: rank 0) in one gather per step.
class SensorRecorder : public Observer {
 public:
  SensorRecorder(const Scene& scene, std::string directory, bool writes = true);
  void on_start(const Simulation& sim) override;
  void on_resume(const Simulation& sim) override;
  void on_step(const Simulation& sim) override;
  void on_finish(const Simulation& sim, const RunSummary& s) override;
  /// The rows so far reach the file before a checkpoint is taken (a resume reads them).
  void on_checkpoint(const Simulation& sim, const std::string& path) override;
  /// The node each sensor reads (after on_start; in a decomposed run the global id).
  const std::vector<vtkIdType>& nodes() const { return global_; }

 private:
  void record(const Simulation& sim);
  std::vector<SensorParams> sensors_;
  std::string directory_;
  bool writes_ = true;
  std::vector<vtkIdType> nodes_;   // per sensor: the local node it reads, -1 if another rank's
  std::vector<vtkIdType> global_;  // per sensor: its node's serial id
  std::vector<double> positions_;  // per sensor: X of its node (3)
  std::vector<double> read_, value_;  // record()'s buffers, kept between steps
  std::vector<double> times_;
  std::vector<std::vector<double>> values_;  // per sensor
  std::unique_ptr<RowFile> out_;  // sensors.csv, whole rows checked (output.hpp)
  std::string pending_;            // rows not yet appended
};

}  // namespace brittle
