// The step is second order in dt for every mechanism (SPEC 4, 7): the largest energy imbalance
// of a 20 us run on CM at 0.9 sigma_c falls by at least 3x (4x ideal) each time run.cfl halves,
// 0.5 -> 0.25 -> 0.125. Measured values and the first-order cases this replaced: docs/model.md.
#include <gtest/gtest.h>

#include <functional>
#include <iostream>
#include <string>

#include "fixtures.hpp"

namespace brittle {
namespace {

using testing::paper_damage;
using testing::plate_scene;

struct Mechanism {
  std::string name;
  std::function<void(Scene&)> setup;
};

void PrintTo(const Mechanism& m, std::ostream* os) {
  *os << m.name;
}

class Convergence : public ::testing::TestWithParam<Mechanism> {};

TEST_P(Convergence, ImbalanceIsSecondOrderInDt) {
  std::vector<double> imbalance;
  for (double cfl : {0.5, 0.25, 0.125}) {
    Scene s = plate_scene(0.9, 20e-6);
    s.run.cfl = cfl;
    GetParam().setup(s);
    const RunSummary r = testing::run_plate(s).summary;
    imbalance.push_back(r.max_relative_imbalance);
  }
  std::cout << "[ " << GetParam().name
            << " ] max imbalance at cfl 0.5 / 0.25 / 0.125: " << imbalance[0] << " / "
            << imbalance[1] << " / " << imbalance[2] << " (ratios " << imbalance[0] / imbalance[1]
            << ", " << imbalance[1] / imbalance[2] << ")\n";
  EXPECT_GE(imbalance[0] / imbalance[1], 3.0);
  EXPECT_GE(imbalance[1] / imbalance[2], 3.0);
  EXPECT_LT(imbalance[0], 1e-3);  // and small to begin with
}

const Mechanism kMechanisms[] = {
    {"elastic_viscous", [](Scene&) {}},
    {"ri_links", [](Scene& s) { s.fracture.mode = FractureParams::Mode::straight; }},
    {"rd_links",
     [](Scene& s) {
       s.fracture.mode = FractureParams::Mode::straight;
       s.fracture.alpha = testing::kPaperAlpha;
     }},
    {"damage", [](Scene& s) { s.damage = paper_damage(); }},
    {"damage_ri_links",
     [](Scene& s) {
       s.fracture.mode = FractureParams::Mode::straight;
       s.damage = paper_damage();
     }},
    {"branching_everything",
     [](Scene& s) {
       s.fracture.mode = FractureParams::Mode::branching;
       s.fracture.alpha = testing::kPaperAlpha;
       s.damage = paper_damage();
     }},
};

INSTANTIATE_TEST_SUITE_P(Mechanisms, Convergence, ::testing::ValuesIn(kMechanisms),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace brittle
