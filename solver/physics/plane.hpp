// The paper's law in two dimensions (issue 53; docs/model.md, "Two dimensions"): a triangle's
// in-plane deformation F2 with the out-of-plane stretch F33 = lambda set by the plane state,
// plane strain (lambda = 1) or plane stress (T33 = 0 of (B.4), and of (B.5) for the viscous
// stress). The 3D formulas (material.hpp) take F = diag(F2, lambda): one law, the dimension and
// the plane state its parameters.
#pragma once

#include "material.hpp"
#include "scene.hpp"

namespace brittle {

/// lambda = F33 of a 2D element with in-plane det F2 = j and tr(F2 F2^T) = a (both > 0):
/// 1 in plane strain; in plane stress the root of T33(lambda) = -K (1/(lambda j) - 1) + mu
/// (lambda j)^(-5/3) (2 lambda^2 - a) / 3 = 0 by Newton's iteration from the small-strain value
/// 1 - nu/(1-nu) (j - 1) (to a relative step of 1e-15, at most 30 iterations: 3 to 5 near the
/// reference; J^(-5/3) from inverse_cbrt, no pow()). T33 is increasing in lambda, so the root
/// is unique. The damage factor (1 - Omega) does not move it.
double out_of_plane_stretch(MaterialParams::Plane plane, double j, double a, double K, double mu);

/// D33 of a 2D element's rate of deformation with in-plane trace tr2: 0 in plane strain; in
/// plane stress the value that makes T_v33 of (B.5) vanish, -(eta_dil - 2/3 eta_dev) tr2 /
/// (eta_dil + 4/3 eta_dev) (0 when both viscosities are 0).
double out_of_plane_rate(MaterialParams::Plane plane, double tr2, double eta_dil, double eta_dev);

}  // namespace brittle
