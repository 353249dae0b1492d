// Element forces of linear triangles (issue 53; docs/model.md, "Two dimensions"): the paper's
// (B.4)+(B.5) on F = diag(F2, lambda) with the plane state's lambda (plane.hpp), each triangle
// a prism of the body's thickness. The same ElementUpdate as the tets' and the same nodal sums
// in cell order (ForceAssembler), so everything downstream reads one layout.
#pragma once

#include "element_forces.hpp"
#include "plane.hpp"

namespace brittle {

/// Dm^-1 of a triangle (2x2, stored in the 3x3 row-major slots 0, 1, 3, 4; slot 8 = 1), V0 =
/// its reference area x `thickness`, h_e = the edge of the equilateral triangle of that area.
/// Throws brittle::Error for a triangle of non-positive area (the mesh orients them).
ElementData make_triangle_data(const Grid& grid, const ElasticConstants& c, const MaterialParams& m,
                               double thickness);

/// One triangle's update at the grid's current x and v: T_el (B.4) of F = diag(F2, lambda),
/// T_v (B.5) of D = diag(D2, D33), the corner forces f_i = -v T grad N_i (in-plane; z = 0)
/// with v = J V0 the current volume, the viscous power as the tets' (P_v: 2x2 in the 3x3
/// column-major slots). `P_v_old`: the element's P_v of the previous step.
ElementUpdate triangle_update(const Grid& grid, const ElementData& elements,
                              const ElasticConstants& c, MaterialParams::Plane plane, vtkIdType e,
                              const double* P_v_old);

}  // namespace brittle
