// A fracture criterion decided on element faces (docs/fracture-criteria.md), after the
// extrinsic cohesive insertion of Camacho & Ortiz 1996 and Pandolfi & Ortiz 2002 as Akantu does
// it: a face opens when the effective traction of the mean stress of its two cells reaches the
// face's strength; a node splits when the open faces through it cut its cells in two or more
// groups, and each group beyond the first takes a new node. The links keep their law (2.6)-(2.8).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "criterion.hpp"
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
/// open ones (its state). Face 4 e + j is opposite corner j of cell e; splits rename corners
/// in place, so a face keeps its id for the whole run.
///
/// Effective traction (Camacho & Ortiz 1996, eq. 27): t = T n with T the mean of the two
/// cells' stresses and n the face's current unit normal, t_n = n . t, t_s = |t - t_n n|;
/// t_eff = sqrt(<t_n>^2 + t_s^2 / beta^2), and beta = 0 counts t_n alone (Akantu's default).
class FacetCriterion : public Criterion {
 public:
  /// fracture.criterion = facet: fracture.beta, fracture.facet_link, the strengths of the
  /// material; the face tables of the grid.
  FacetCriterion(const Scene& scene, const CriterionContext& context);

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
  virtual void reset() { across_.clear(); }

  // The Criterion interface
  /// The weakest strength with beta = 0, else infinite (every face is scanned).
  double hot_threshold(const Grid& grid, const std::vector<vtkIdType>& root) override;
  /// over() on the open faces so far: a candidate per face (node: a corner of it).
  std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces,
                                         const CriterionInputs& in) override;
  /// Opens the candidates' faces, then splits each of their corners whose cells the open
  /// faces cut into groups: every group but the first adopts a new node.
  void split(Grid& grid, const ForceAssembler& forces,
             const std::vector<SplitCandidate>& candidates, const CriterionInputs& in,
             const SplitCells& split) override;
  /// fracture.facet_link = traction: sum over the faces of t_open x (area / 3), t_open the
  /// traction its face opened at (Akantu's extrinsic insertion); imbalance: NaN, (2.6).
  double link_force(const std::vector<CrackFace>& faces) const override;
  void state(StateWriter& ar) override;
  void state(StateReader& ar) override;
  void recut(const Criterion& src, const std::vector<vtkIdType>& cell_from,
             vtkIdType num_points) override;
  /// Decomposed (docs/parallel.md, "The facet criterion on many ranks"): each face is decided
  /// by the owner of its corner with the smallest global id (it holds both cells, and the cells
  /// the criterion's reach adds, with the serial stresses); the faces that open are gathered on
  /// every rank in the serial order, every rank opens the sides it holds, and the owner of a
  /// node splits it.
  void decompose(const Decomposition& d) override { decomposition_ = d; }
  bool decided_by_node_owner() const override { return false; }
  bool splits_in_node_order() const override { return true; }

  /// Per face 4 e + j: open (1) or not, and the effective traction it opened at [Pa].
  const std::vector<std::uint8_t>& open_faces() const { return face_open_; }

 protected:
  /// The faces over() looks at this step into faces_ (each once, by its side in the smaller
  /// cell, ascending), and the stresses of the cells it reads (6 per cell, xx yy zz xy yz xz):
  /// the cells' own, T_e. One call per step.
  virtual const double* gather(const Grid& grid, const ForceAssembler& forces,
                               const std::vector<std::uint8_t>& open);
  /// The faces of cell e that are closed and interior, appended to faces_.
  void add_faces_of(vtkIdType e, const std::vector<std::uint8_t>& open) {
    for (int j = 0; j < corners_; ++j) {
      const vtkIdType f = 4 * e + j, n = across_[f];
      if (n >= 0 && !open[f]) faces_.push_back(n > e ? f : twin_[f]);
    }
  }

  std::string name_ = "facet";
  int corners_ = 4;                       // per cell: 4 (tets), 3 (a 2D body's triangles)
  std::vector<vtkIdType> across_, twin_;  // 4 per cell
  std::vector<vtkIdType> faces_;          // scratch of over()

 private:
  void build(const Grid& grid, const std::vector<vtkIdType>& root);
  /// over()'s scan of faces_ with the cells' stresses: the faces over their strength (on
  /// cells of Corners corners: 4, tets; 3, a 2D body's triangles, whose faces are edges).
  template <int Corners>
  std::vector<FacetOpening> scan(const Grid& grid, const double* stress,
                                 const std::function<bool(vtkIdType)>& may_open);
  /// The reference centroid of face f from its corners' roots in ascending order (an edge's
  /// midpoint in 2D): the same bits from either side.
  void face_centroid(const Grid& grid, const std::vector<vtkIdType>& root, vtkIdType f,
                     double out[3]) const;

  double beta_;
  std::function<double(const double X[3])> strength_of_;
  std::vector<double> strength_;          // 4 per cell (both sides of a face: the same)
  double weakest_ = 0;
  double sigma_c_ = 0;                    // a link face with no face of its own (link_force)
  bool traction_link_ = false;            // fracture.facet_link = traction
  /// The faces over their strength of every rank, in the serial order, by their local sides.
  std::vector<FacetOpening> agree(const Grid& grid, const std::vector<FacetOpening>& mine) const;
  Decomposition decomposition_;           // (owned == nullptr: one process)
  std::vector<std::uint8_t> face_open_;   // 4 per cell, face 4 e + j open (both sides)
  std::vector<double> face_traction_;     // the effective traction it opened at [Pa]
};

}  // namespace brittle
