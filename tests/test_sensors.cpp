// Acoustic-emission sensors (docs/acoustic_emission.md): the spectrum of a known signal, and a
// sensor on a bar driven by a sine burst at one end recovers the burst's frequency.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "sensors.hpp"

using namespace brittle_test;

// A sine of amplitude 0.3 at 400 kHz sampled every 20 ns for 40 us with an offset: the Hann
// spectrum peaks at 400 kHz with the sine's amplitude (one bin is 25 kHz); a step change of the
// sampling interval half-way (resampled) changes nothing.
TEST(Sensors, SpectrumOfASine) {
  std::vector<double> t, v;
  for (double time = 0; time <= 40e-6 + 1e-15; time += time < 20e-6 ? 20e-9 : 10e-9) {
    t.push_back(time);
    v.push_back(1.5 + 0.3 * std::sin(2 * M_PI * 400e3 * time));
  }
  const brittle::Spectrum s = brittle::amplitude_spectrum(t, v);
  EXPECT_NEAR(s.dominant, 400e3, 12.5e3);
  double peak = 0;
  for (double a : s.amplitude) peak = std::max(peak, a);
  EXPECT_NEAR(peak, 0.3, 0.03) << "the Hann window's scalloping loss is at most 15 %, here < 10 %";
  EXPECT_NEAR(s.frequency[1], 1 / 40e-6, 1e3);
}

// A PMMA bar 64 x 4 x 0.5 mm at rest, every node held in y and z (uniaxial strain: a plane wave
// at c_p without physical dispersion); its end x = 0 moves along x as 3 cycles of a 200 kHz sine
// (20 elements per wavelength). Sensors at x = 8 and 24 mm record v_x for 30 us, before the
// reflection from the free end comes back: both spectra peak at 200 kHz within one bin
// (1 / 30 us = 33 kHz).
TEST(Sensors, BarSensorRecoversTheBurstFrequency) {
  TempDir dir;
  std::ostringstream table;
  table << std::setprecision(10);
  const double f0 = 200e3;
  for (int k = 0; k <= 60; ++k) {
    const double t = k * (3 / f0) / 60;
    table << (k ? ", " : "") << t << ", " << std::sin(2 * M_PI * f0 * t);
  }
  const std::string scene = dir.write("bar.ini",
                                      "[geometry]\nL = 64e-3\nH = 4e-3\nnotch_depth = 0\n"
                                      "[initial]\nstate = rest\n"
                                      "[boundary.drive]\ntype = velocity\n"
                                      "box = -inf, 1e-9, -inf, inf, -inf, inf\n"
                                      "components = x\nvelocity = 0.1, 0, 0\nhistory = table\n"
                                      "table = " + table.str() + "\n"
                                      "[boundary.lateral]\ntype = fixed\ncomponents = y, z\n"
                                      "box = -inf, inf, -inf, inf, -inf, inf\n"
                                      "[sensor.mid]\nposition = 8e-3, 2e-3, 0.5e-3\n"
                                      "direction = 1, 0, 0\n"
                                      "[sensor.far]\nposition = 24e-3, 0, 0.25e-3\n"
                                      "direction = 1, 0, 0\n"
                                      "[run]\nend_time = 30e-6\n[output]\nvtu = false\n");
  const Result r = run_brittle(dir, {"run", scene, "--out", (dir / "out").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto sensors = nlohmann::json::parse(read_text(dir / "out/sensors.json"));
  ASSERT_EQ(sensors.size(), 2u);
  for (const auto& s : sensors) {
    EXPECT_NEAR(s.at("dominant_frequency").get<double>(), f0, 1 / 30e-6) << s.at("name");
    EXPECT_GT(s.at("samples").get<int>(), 500);
  }
  EXPECT_NEAR(sensors[0].at("position")[0].get<double>(), 8e-3, 0.5e-3);
  const std::string csv = read_text(dir / "out/sensors.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time,mid,far");
  EXPECT_TRUE(fs::exists(dir / "out/spectra.csv"));
}
