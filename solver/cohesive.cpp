// Nodal cohesive forces: creation (2.6)-(2.9), (3.8); weakening (2.8) with (3.5)/(4.4);
// dissipation (3.2)-(3.3); granddaughters (Appendix A).
#include "cohesive.hpp"

#include <algorithm>
#include <cmath>

namespace brittle {
namespace {

double area_of(const std::vector<CrackFace>& faces) {
  double a = 0;
  for (const CrackFace& f : faces) a += f.area;
  return a;
}

/// delta_c = 2 A_c gamma / f0   (3.8); zero when there is no force or no area to stand for.
double critical_opening(double A_c, double f0, double gamma) {
  return f0 > 0 && A_c > 0 ? 2.0 * A_c * gamma / f0 : 0.0;
}

}  // namespace

CohesiveLink make_link(vtkIdType a, vtkIdType b, const Vec3& f0, std::vector<CrackFace> faces,
                       const CohesiveLaw& law) {
  CohesiveLink l;
  l.a = a;
  l.b = b;
  l.f0 = f0.norm();
  l.e0 = l.f0 > 0 ? Vec3(f0 / l.f0) : Vec3::Zero();  // (2.9)
  l.faces = std::move(faces);
  l.A_c = area_of(l.faces);
  l.delta_c = critical_opening(l.A_c, l.f0, law.gamma);
  l.f = l.f0;
  return l;
}

void advance_link(CohesiveLink& l, double delta, double dt, const CohesiveLaw& law) {
  const double f_old = l.f, V_old = l.stored(), delta_old = l.delta;
  const double delta_max = std::max(l.delta_max, delta);
  if (l.delta_c <= 0.0) {
    l.omega = 1.0;  // stands for no area: nothing to dissipate but what it stores
  } else {
    // (4.4): omegadot = <1 - alpha epsilondot>^n epsilondot, epsilon = delta_max / delta_c.
    // With alpha = 0 this is (3.6), whose integral is (3.5); the incremental form stays
    // continuous when a granddaughter split changes delta_c (Appendix A copies omega).
    const double d_eps = (delta_max - l.delta_max) / l.delta_c;
    const double rate = std::max(1.0 - law.alpha * d_eps / dt, 0.0);
    l.omega = std::min(l.omega + (law.alpha == 0.0 ? 1.0 : std::pow(rate, law.n)) * d_eps, 1.0);
  }
  l.delta = delta;
  l.delta_max = delta_max;
  l.f = delta_max > 0 ? l.f0 * (1.0 - l.omega) * delta / delta_max : l.f0 * (1.0 - l.omega);
  // D_c = W_c - Vdot_c (3.2), W_c integrated with the trapezoidal rule.
  l.dissipated += 0.5 * (f_old + l.f) * (delta - delta_old) - (l.stored() - V_old);
}

CohesiveLink split_link(CohesiveLink& link, vtkIdType old_node, vtkIdType new_node, double m1,
                        double m2, const std::vector<vtkIdType>& new_cells,
                        const CohesiveLaw& law) {
  CohesiveLink part = link;  // delta, delta_max, omega and the direction are copied
  (part.a == old_node ? part.a : part.b) = new_node;
  std::vector<CrackFace> stay, move;
  for (const CrackFace& face : link.faces) {
    const vtkIdType cell = link.a == old_node ? face.cell_a : face.cell_b;
    (std::binary_search(new_cells.begin(), new_cells.end(), cell) ? move : stay).push_back(face);
  }
  const double f0 = link.f0, ratio = m1 / (m1 + m2);
  link.f0 = ratio * f0;        // (A.1)
  part.f0 = f0 - link.f0;      // so that f01 + f02 = f0 exactly (A.2)
  link.faces = std::move(stay);
  part.faces = std::move(move);
  link.A_c = area_of(link.faces);
  part.A_c = area_of(part.faces);
  link.delta_c = critical_opening(link.A_c, link.f0, law.gamma);
  part.delta_c = critical_opening(part.A_c, part.f0, law.gamma);
  // The current force and the energy dissipated so far are shared in the same proportion.
  const double f = link.f, dissipated = link.dissipated;
  link.f = ratio * f;
  part.f = f - link.f;
  link.dissipated = ratio * dissipated;
  part.dissipated = dissipated - link.dissipated;
  return part;
}

}  // namespace brittle
