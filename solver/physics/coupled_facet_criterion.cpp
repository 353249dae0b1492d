// Leguillon's coupled criterion on element faces: the facet criterion's stress condition and
// the energy criterion's estimate of G over a ball of radius l.
#include "coupled_facet_criterion.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "error.hpp"
#include "material.hpp"

namespace brittle {

double coupled_length(const Scene& scene) {
  if (scene.fracture.length > 0) return scene.fracture.length;
  const MaterialParams& m = scene.material;
  return m.E * 2.0 * m.gamma / (m.sigma_c * m.sigma_c);
}

namespace {

/// coupled_length, refused (one line) when no body can use it.
double checked_length(const Scene& scene, const BodySizes& body) {
  const double l = coupled_length(scene);
  BRITTLE_CHECK(l > 0 && std::isfinite(l), "fracture.criterion = coupled-facet: the length l = ",
                l, " m (expected fracture.length > 0, or a material with E, gamma and sigma_c > 0)");
  check_length_fits(body, "fracture.length", l);
  return l;
}

}  // namespace

GhostReach CoupledFacetCriterion::reach(const Scene& scene) {
  return {1, coupled_length(scene)};  // (the stress average's c^2 l is shorter)
}

std::string resolution_warning(const BodySizes& body, double length) {
  const double fine = body.fine_h;  // the finest 5 %: where a refined band puts the crack
  if (fine <= 0 || fine <= length) return {};
  std::ostringstream w;
  w << "fracture.length: the material length l = " << length * 1e3
    << " mm is not resolved by this mesh, whose finest elements are " << fine * 1e3
    << " mm (expected elements smaller than l where cracks run: mesh.band_size or mesh.size "
       "below "
    << length * 1e3 << " mm)";
  return w.str();
}

CoupledFacetCriterion::CoupledFacetCriterion(const Scene& scene, const CriterionContext& context)
    : NonlocalFacetCriterion(scene, context,
                             kWilliamsPeak * kWilliamsPeak * checked_length(scene, context.body)),
      G_min_(2.0 * scene.material.gamma * (1.0 + 1e-9)) {
  name_ = "coupled-facet";
  const double l = coupled_length(scene);
  energy_ = std::make_unique<EnergyCriterion>(
      context.grid, context.elements, l, scene.material.E, 2.0 * scene.material.gamma,
      scene.material.sigma_c, plane_stress_rayleigh_speed(scene.material));
  warning_ = NonlocalFacetCriterion::warning();  // (the stress average's, the shorter length)
}

std::vector<SplitCandidate> CoupledFacetCriterion::candidates(const Grid& grid,
                                                              const ForceAssembler& forces,
                                                              const CriterionInputs& in) {
  std::vector<SplitCandidate> over = NonlocalFacetCriterion::candidates(grid, forces, in);
  if (over.empty()) return over;
  energy_->begin_step();
  const vtkIdType* cells = grid.cells();
  const double *X = grid.X(), *x = grid.x();
  const double scale = EnergyCriterion::kCalibration * energy_->epsilon() / energy_->E();
  std::erase_if(over, [&](const SplitCandidate& c) {
    const vtkIdType e = c.face / 4;
    const int j = static_cast<int>(c.face % 4);
    vtkIdType p[3];
    int n = 0;
    for (int k = 0; k < 4; ++k)
      if (k != j) p[n++] = cells[4 * e + k];
    double centre[3];  // reference centroid: daughters keep their mother's position
    for (int a = 0; a < 3; ++a)
      centre[a] = (X[3 * p[0] + a] + X[3 * p[1] + a] + X[3 * p[2] + a]) / 3.0;
    const Vec3 a(x + 3 * p[0]), b(x + 3 * p[1]), d(x + 3 * p[2]);
    const Vec3 normal = (b - a).cross(d - a).normalized();
    double m[6];
    if (!energy_->ball_mean(grid, centre, m)) return true;
    // n . M n with M's components xx yy zz xy yz xz
    const double nMn = normal[0] * normal[0] * m[0] + normal[1] * normal[1] * m[1] +
                       normal[2] * normal[2] * m[2] + 2 * normal[0] * normal[1] * m[3] +
                       2 * normal[1] * normal[2] * m[4] + 2 * normal[0] * normal[2] * m[5];
    return !(scale * nMn >= G_min_);  // G_eps (the energy criterion's estimate)
  });
  return over;
}

}  // namespace brittle
