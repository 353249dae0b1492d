// The criterion a scene names, and the pieces the criteria share: the paper's split plane
// (SPEC 5) and the splitting order.
#include "criterion.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "coupled_facet_criterion.hpp"
#include "energy_criterion.hpp"
#include "error.hpp"
#include "facet_criterion.hpp"
#include "nodal_stress_criterion.hpp"
#include "nonlocal_facet_criterion.hpp"
#include "recovered_facet_criterion.hpp"

namespace brittle {

std::unique_ptr<Criterion> make_criterion(const Scene& scene, const CriterionContext& context) {
  using Mode = FractureParams::Mode;
  using Name = FractureParams::Criterion;
  const FractureParams& f = scene.fracture;
  if (f.mode == Mode::none) return nullptr;
  if (f.mode == Mode::straight) return std::make_unique<NodalStressCriterion>(scene, context, true);
  switch (f.criterion) {  // fracture.criterion: one line per criterion
    case Name::nodal_stress: return std::make_unique<NodalStressCriterion>(scene, context, false);
    case Name::energy: return std::make_unique<EnergyCriterion>(scene, context);
    case Name::facet: return std::make_unique<FacetCriterion>(scene, context);
    case Name::nonlocal_facet: return std::make_unique<NonlocalFacetCriterion>(scene, context);
    case Name::coupled_facet: return std::make_unique<CoupledFacetCriterion>(scene, context);
    case Name::recovered_facet: return std::make_unique<RecoveredFacetCriterion>(scene, context);
  }
  return nullptr;
}

BodySizes body_sizes(const Grid& grid, const std::vector<double>& h_e) {
  BodySizes b;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = INFINITY, hi[a] = -INFINITY;
  const double* X = grid.X();
  for (vtkIdType p = 0; p < grid.num_points(); ++p)
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], X[3 * p + a]), hi[a] = std::max(hi[a], X[3 * p + a]);
  b.extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (h_e.empty()) return b;
  std::vector<double> h = h_e;
  std::nth_element(h.begin(), h.begin() + h.size() / 2, h.end());
  b.median_h = h[h.size() / 2];
  const auto k = h.size() / 20;  // the finest 5 %
  std::nth_element(h.begin(), h.begin() + k, h.end());
  b.fine_h = h[k];
  return b;
}

GhostReach ghost_reach(const Scene& scene, const BodySizes& body) {
  using Mode = FractureParams::Mode;
  using Name = FractureParams::Criterion;
  const FractureParams& f = scene.fracture;
  if (f.mode != Mode::branching) return {};
  switch (f.criterion) {  // one line per criterion that reads past the cells of its nodes
    case Name::energy: return EnergyCriterion::reach(scene, body);
    case Name::nonlocal_facet: return NonlocalFacetCriterion::reach(scene);
    case Name::coupled_facet: return CoupledFacetCriterion::reach(scene);
    case Name::recovered_facet: return RecoveredFacetCriterion::reach();
    case Name::nodal_stress:
    case Name::facet: break;
  }
  return {};
}

void check_length_fits(const BodySizes& body, const char* key, double length) {
  BRITTLE_CHECK(length <= body.extent, key, " = ", length, " m is longer than the body, whose "
                "largest extent is ", body.extent, " m (expected a length of the material's "
                "scale, well below the body's)");
}

void sort_in_splitting_order(std::vector<SplitCandidate>& c) {
  std::sort(c.begin(), c.end(), [](const SplitCandidate& a, const SplitCandidate& b) {
    return std::tie(b.sigma1, a.node) < std::tie(a.sigma1, b.node);
  });
}

void split_by_plane(const Grid& grid, const ForceAssembler& forces, const SplitCandidate& c,
                    const SplitCells& split) {
  const vtkIdType K = c.node;
  // Cells of K: the node table is from the start of the step; splits of other nodes in this
  // step only renamed *their* corners, so K's cells are still exactly these (in cell order).
  const vtkIdType *start = forces.node_start().data(), *end = forces.node_end().data();
  const std::int32_t* entries = forces.node_entries().data();
  const double* x = grid.x();
  const vtkIdType* cells = grid.cells();
  const Vec3 xK(x[3 * K], x[3 * K + 1], x[3 * K + 2]);
  std::vector<vtkIdType> b_cells;  // those whose centroid lies on the + side
  const int corners = grid.corners();  // (a 2D body's: the plane is a line through K)
  const double share = 1.0 / corners;  // (0.25 for tets: the bits as before)
  for (vtkIdType k = start[K]; k < end[K]; ++k) {
    const vtkIdType e = entries[k] / 4;
    Vec3 centroid = Vec3::Zero();
    for (int j = 0; j < corners; ++j) centroid += Vec3(x + 3 * cells[corners * e + j]);
    if ((share * centroid - xK).dot(c.normal) > 0.0) b_cells.push_back(e);
  }
  if (b_cells.empty() || b_cells.size() == static_cast<std::size_t>(end[K] - start[K]))
    return;  // nothing to split
  split(K, std::move(b_cells), c.sigma1);
}

}  // namespace brittle
