// The facet criterion with Leguillon's coupled condition (docs/fracture-criteria.md, "The
// coupled facet criterion"): a face opens when its traction, from stresses averaged over
// 0.367 l, reaches its strength and the energy its plane's tractions hold within a ball of
// radius l, per unit of the crack area a cut through that ball makes, reaches G_c (the energy
// criterion's estimate; Leguillon 2002): both conditions over lengths of the material.
#pragma once

#include <memory>

#include "energy_criterion.hpp"
#include "nonlocal_facet_criterion.hpp"

namespace brittle {

class CoupledFacetCriterion : public NonlocalFacetCriterion {
 public:
  /// fracture.criterion = coupled-facet: l = fracture.length, or (0) the material's
  /// E G_c / sigma_c^2 (its cohesive length, Irwin's and Hillerborg's l_ch). The stress
  /// condition reads stresses averaged over c^2 l (NonlocalFacetCriterion, c = kWilliamsPeak),
  /// so that a straight crack's tip meets both conditions at one K, sqrt(E G_c).
  CoupledFacetCriterion(const Scene& scene, const CriterionContext& context);

  double energy_length() const { return energy_->epsilon(); }
  /// Decomposed (docs/parallel.md, "Ghost depth"): a face's owner reads its two cells and the
  /// ball of radius l about any point of them (the energy's; the stress average's is shorter).
  static GhostReach reach(const Scene& scene);
  /// The facet criterion's faces, then those whose G_eps(face centroid, face normal) =
  /// C l n . <(T+)^2>_l n / E reaches G_c (EnergyCriterion): in the same order.
  std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces,
                                         const CriterionInputs& in) override;
  std::string warning() const override { return warning_; }

 private:
  std::unique_ptr<EnergyCriterion> energy_;
  double G_min_;
  std::string warning_;
};

/// The coupled facet criterion's length for a scene (fracture.length, or E G_c / sigma_c^2).
double coupled_length(const Scene& scene);

/// The one-line warning when the finest 5 % of the elements are coarser than `length` (a
/// material length is resolved only by elements smaller than it), else empty.
std::string resolution_warning(const BodySizes& body, double length);

}  // namespace brittle
