// A fracture criterion decided on element faces (docs/fracture-criteria.md), after the
// extrinsic cohesive insertion of Camacho & Ortiz 1996 and Pandolfi & Ortiz 2002 as Akantu does
// it: a face opens when the effective traction of the mean stress of its two cells reaches the
// face's strength; a node splits when the open faces through it cut its cells in two or more
// groups, and each group beyond the first takes a new node. The links keep their law (2.6)-(2.8).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "element_forces.hpp"
#include "grid.hpp"

namespace brittle {

/// A face over its strength: face = 4 e + j is the face of cell e opposite its corner j (e the
/// smaller of the two cells), ratio = effective traction / strength.
struct FacetOpening {
  vtkIdType face = -1;
  double ratio = 0;
};

/// Faces of the tets: which cell lies across each, each interior face's strength, and the
/// open ones (Fracture's state). Face 4 e + j is opposite corner j of cell e; splits rename
/// corners in place, so a face keeps its id for the whole run.
///
/// Effective traction (Camacho & Ortiz 1996, eq. 27): t = T n with T the mean of the two
/// cells' stresses and n the face's current unit normal, t_n = n . t, t_s = |t - t_n n|;
/// t_eff = sqrt(<t_n>^2 + t_s^2 / beta^2), and beta = 0 counts t_n alone (Akantu's default).
class FacetCriterion {
 public:
  /// strength(face_centroid X) gives a face's strength from its reference centroid.
  FacetCriterion(double beta, std::function<double(const double X[3])> strength);

  double beta() const { return beta_; }
  /// The weakest face's strength (the element loop's hot threshold when beta = 0: t_n of the
  /// mean stress is at most the larger of the two cells' sigma1 bounds).
  double weakest(const Grid& grid, const std::vector<vtkIdType>& root);

  /// The closed faces over their strength, with the element stresses of the last force
  /// computation, on faces whose three corners `may_open` allows: largest ratio first, ties by
  /// face id. `open` is 4 bytes per cell (1: open).
  std::vector<FacetOpening> over(const Grid& grid, const ForceAssembler& forces,
                                 const std::vector<vtkIdType>& root,
                                 const std::vector<std::uint8_t>& open,
                                 const std::function<bool(vtkIdType)>& may_open);

  /// The cell across face 4 e + j (-1 on the boundary).
  vtkIdType across(vtkIdType face) const { return across_[face]; }
  /// The face of the other cell that is the same face as `face`.
  vtkIdType twin(vtkIdType face) const { return twin_[face]; }
  /// An interior face's strength.
  double strength(vtkIdType face) const { return strength_[face]; }
  /// The face of cell a that cell b lies across (-1 if they share none).
  vtkIdType face_between(vtkIdType a, vtkIdType b) const {
    for (int j = 0; j < 4; ++j)
      if (across_[4 * a + j] == b) return 4 * a + j;
    return -1;
  }

  /// K's cells (its node-table entries, in table order) in groups joined through closed faces
  /// that hold K: group[i] of entry i, groups numbered in order of their first entry. Returns
  /// the number of groups.
  int groups(const ForceAssembler& forces, const std::vector<std::uint8_t>& open, vtkIdType K,
             std::vector<int>& group) const;

  /// Forgets the face tables (after a re-cut renumbers cells); rebuilt on next use.
  void reset() { across_.clear(); }

 private:
  void build(const Grid& grid, const std::vector<vtkIdType>& root);

  double beta_;
  std::function<double(const double X[3])> strength_of_;
  std::vector<vtkIdType> across_, twin_;  // 4 per cell
  std::vector<double> strength_;          // 4 per cell (both sides of a face: the same)
  double weakest_ = 0;
  std::vector<vtkIdType> faces_;  // scratch of over()
};

}  // namespace brittle
