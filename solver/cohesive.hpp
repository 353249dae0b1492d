// Nodal cohesive forces between daughter nodes (paper sections 2-4, Appendix A):
// f = f0 (1 - omega) delta / delta_max (2.8), omega by (3.5) or (4.4), granddaughters (A.1).
#pragma once

#include <vector>

#include <vtkType.h>

#include "material.hpp"

namespace brittle {

/// One triangular face that separated when a link was made: the cells on either side
/// (cell_a adopted node a, cell_b node b) and its share of A_c: 2 (reference area) / 3.
struct CrackFace {
  vtkIdType cell_a = -1, cell_b = -1;
  double area = 0;
};

struct CohesiveLaw {
  double gamma = 150;  ///< surface energy [N/m] (3.7)
  double alpha = 0;    ///< rate parameter [s] (4.4); 0 = rate-independent (3.5)
  double n = 0.2;      ///< exponent of (4.4)
};

/// The force applied by node b on node a is f e, e = (x_b - x_a)/delta; -f e acts on b.
struct CohesiveLink {
  vtkIdType a = -1, b = -1;
  double f0 = 0;          ///< |f0| at creation (2.6)
  Vec3 e0 = Vec3::Zero(); ///< f0 / |f0|: the direction while delta = 0 (2.9)
  double A_c = 0;         ///< crack area the link stands for, both faces (3.7)
  double delta_c = 0;     ///< 2 A_c gamma / f0 (3.8)
  double delta = 0, delta_max = 0, omega = 0;
  double f = 0;           ///< current magnitude (2.8)
  double dissipated = 0;  ///< integral of D_c (3.3) so far
  double opening_rate = 0;  ///< |change of delta| / dt over the last element step
  std::vector<CrackFace> faces;

  /// Stored energy V_c = f delta / 2 (3.1).
  double stored() const { return 0.5 * f * delta; }
  bool broken() const { return omega >= 1.0; }
};

/// A new link between daughters a and b for the initial force vector f0 (2.6), the
/// separated faces and the law; f = f0, omega = 0.
CohesiveLink make_link(vtkIdType a, vtkIdType b, const Vec3& f0, std::vector<CrackFace> faces,
                       const CohesiveLaw& law);

/// Moves the link to opening `delta` over a step dt: delta_max, omega by (3.5) when
/// alpha = 0, else (4.4) with epsilondot = (change of delta_max)/(dt delta_c); f by (2.8);
/// and adds the dissipation W_c - change of V_c (3.2), the work taken with the trapezoidal
/// rule (which is what the central-difference step does to the nodes).
void advance_link(CohesiveLink& link, double delta, double dt, const CohesiveLaw& law);

/// Granddaughters (Appendix A): node `old_node` of `link` split into itself (mass m1) and
/// `new_node` (mass m2); `new_cells` (sorted) are the cells that adopted new_node. The link is
/// cut in two: f0_i = m_i/(m1+m2) f0, A_c split by the faces' cells, delta_c,i = 2 gamma A_c,i
/// / f0_i, delta, delta_max, omega and direction copied (A.1)-(A.4). Returns the new_node part.
CohesiveLink split_link(CohesiveLink& link, vtkIdType old_node, vtkIdType new_node, double m1,
                        double m2, const std::vector<vtkIdType>& new_cells,
                        const CohesiveLaw& law);

}  // namespace brittle
