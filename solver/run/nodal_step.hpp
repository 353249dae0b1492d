// The nodal bound of the stable step (issue 38, docs/model.md "Stable step: the nodal bound"):
// the largest frequency of the assembled grid bounded node by node from the elements' exact
// stiffness eigenvalues and the nodes' lumped masses, so that a node split (which takes mass
// from a node and leaves the elements as they were) moves the bound where it moves the physics.
#pragma once

#include <vector>

#include "element_forces.hpp"
#include "grid.hpp"
#include "integrator.hpp"
#include "material.hpp"

namespace brittle {

/// The largest eigenvalue of the stiffness V B^T D B of a linear tetrahedron of volume V in an
/// isotropic material with Lame constants (lambda, mu), in closed form: with h_1 <= h_2 <= h_3
/// the eigenvalues of G^T G (G: the 4 x 3 gradients of the shape functions),
///   lambda_max = V max(lambda_max(2 mu diag(h) + lambda sqrt(h) sqrt(h)^T), mu (h_2 + h_3)),
/// the first for the gradients' diagonal (stretch) part, the second for a shear pair.
/// The same for a linear triangle (Dim = 2: G the 3 x 2 in-plane gradients, V = area x
/// thickness, (lambda, mu) the in-plane moduli: lambda itself in plane strain, 2 lambda mu /
/// (lambda + 2 mu) in plane stress): one formula, the dimension its parameter (docs/model.md).
template <int Dim>
double stiffness_eigenvalue(const Eigen::Matrix<double, Dim, Dim>& GtG, double V, double lambda,
                            double mu);
inline double tet_stiffness_eigenvalue(const Mat3& GtG, double V, double lambda, double mu) {
  return stiffness_eigenvalue<3>(GtG, V, lambda, mu);
}

/// The step's nodal bound: for every vector u, u^T K u = sum_e u_e^T K_e u_e <= sum_i |u_i|^2
/// sum_{e at i} k_e (k_e = lambda_max(K_e)), so omega_max^2 <= max_i (sum_{e at i} k_e) / m_i;
/// the same for the viscous matrix C (B.5) gives c_i = (sum_{e at i} c_e) / m_i. Node i's step
/// is dt_i = (2 / omega_i)(sqrt(1 + xi_i^2) - xi_i), xi_i = c_i / (2 omega_i), the run's step
/// cfl min_i dt_i. Elements at their current shape, small-strain moduli (the nonlinear law's
/// stiffening and damage's softening are left to cfl). Unlike the altitude bound, cfl = 1 is
/// the limit of the linear viscous grid, and an element whose node is split off alone gets its
/// own exact limit.
class NodalStepBound {
 public:
  /// What changed since the last call: the masses only (node splits: the elements' k_e and c_e
  /// are kept, the nodal sums redone), or the shapes too. k_e and c_e are computed exactly
  /// (closed form) on the first call and follow later shapes by the ratio of
  /// V sum_a |g_a|^2 (no eigenvalues: one pass as cheap as the altitude bound's).
  enum class Update { shapes, masses };
  /// One pass over the elements (threads; none for masses) and one over the nodes in order:
  /// the same bits on any thread count. Scratch arrays grow with the grid, never shrink.
  /// dt = cfl min_i dt_i, with the node that sets it (the lowest id on ties), its frequency
  /// bound omega_i and damping ratio xi_i; element and altitude are not set. `counted`, if
  /// given, is 1 for the nodes to take the minimum over: a decomposed run's owned nodes, which
  /// hold all their cells (a ghost's sums miss other ranks' cells); each owned node's sum runs
  /// over its cells in the serial cell order, so it has the serial bits.
  StableStep operator()(const Grid& grid, const ElementData& elements, const ElasticConstants& c,
                        double cfl, Update update = Update::shapes,
                        const std::vector<char>* counted = nullptr);

 private:
  std::vector<double> k0_, c0_, t0_;     // per element, at the first call: k_e, c_e, V sum |g|^2
  std::vector<double> k_, c_;            // per element, at the latest shapes
  std::vector<double> node_k_, node_c_;  // per node: their sums
};

}  // namespace brittle
