// Where a crack grows: one interface for every fracture criterion (docs/fracture-criteria.md),
// the paper's nodal stress (2.10)-(2.12), (6.7), the energy over a length, the facet criterion
// and its nonlocal form. Fracture owns one and makes the splits it asks for (SPEC 5).
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "archive.hpp"
#include "cohesive.hpp"
#include "element_forces.hpp"
#include "grid.hpp"
#include "scene.hpp"

namespace brittle {

/// A node over the criterion this step: its sigma1 and the normal of its split plane. The
/// facet criteria's candidates are faces that open (face >= 0, sigma1 = its effective
/// traction over its strength; node: a corner).
struct SplitCandidate {
  vtkIdType node = -1;
  double sigma1 = 0;
  Vec3 normal = Vec3::UnitY();
  vtkIdType face = -1;
};

/// What Fracture tells a criterion of the run each step.
struct CriterionInputs {
  const std::vector<vtkIdType>& root;   ///< per node: the mesh node it descends from
  const double* split_time;             ///< per node: when it split (NaN: never)
  double time;                          ///< the time of the step's splits
  /// Whether node p may break: not fixed, inside fracture.region.
  const std::function<bool(vtkIdType)>& may_break;
};

/// Where a criterion's splits go: node K's cells `b_cells` (ascending, some but not all of
/// K's) adopt a new node; sigma1 is the candidate's value (SplitRecord::sigma1). Fracture
/// makes the split (masses, forces, crack faces, the link) and rebuilds K's node table.
using SplitCells = std::function<void(vtkIdType K, std::vector<vtkIdType> b_cells, double sigma1)>;

/// The whole body's sizes a criterion reads: the same on every rank of a decomposed run (a
/// rank's part carries its whole mesh's, extract_part), so that a length defaulted from the
/// mesh, a length refused as longer than the body and a resolution warning are the serial
/// ones.
struct BodySizes {
  double extent = 0;    ///< largest extent of the reference positions [m]
  double median_h = 0;  ///< median element size h_e [m] (ElementData::h_e)
  double fine_h = 0;    ///< the finest 5 %'s largest h_e [m]: where a refined band puts cracks
};

/// The sizes of a whole grid with element sizes h_e (one per cell).
BodySizes body_sizes(const Grid& grid, const std::vector<double>& h_e);

/// How far past a rank's own nodes a criterion reads (issue 52, item 2; docs/parallel.md,
/// "Ghost depth"): a rank holds the cells within `layers` rings of cells around its owned nodes
/// (1: the cells touching them, the layer every run holds; 2: also the cells touching a node of
/// those), and besides every cell whose reference centroid lies within `distance` of a point of
/// a cell of the last ring (a ball of that radius about any point the criterion reads there).
struct GhostReach {
  int layers = 1;
  double distance = 0;  ///< [m]
  /// Whether a part cut with this reach holds what `need` asks for.
  bool covers(const GhostReach& need) const {
    return layers >= need.layers && distance >= need.distance;
  }
};

/// The reach the scene's criterion asks for (one line per criterion, as make_criterion).
GhostReach ghost_reach(const Scene& scene, const BodySizes& body);

/// A decomposed run's view for a criterion (set by Simulation::decompose; the Halo lives in a
/// layer above): this rank's nodes and cells by global id, and a gather over the ranks. The
/// vectors are the Halo's and grow with splits.
struct Decomposition {
  const std::vector<char>* owned = nullptr;             ///< per local node: 1 if owned here
  const std::vector<vtkIdType>* global_node = nullptr;  ///< local node -> global
  const std::vector<vtkIdType>* global_cell = nullptr;  ///< local cell -> global (increasing)
  std::function<vtkIdType(vtkIdType)> local_cell;       ///< global cell -> local (-1: not here)
  /// Every rank's values, rank after rank (collective).
  std::function<std::vector<double>(const std::vector<double>&)> gather_all;
};

/// A fracture criterion: what it examines each step, which splits it asks for, its state for
/// the checkpoint, the threshold the element loop lists cells at. Its calls are per step or per
/// split, never per element (the element loop stays free of virtual calls).
class Criterion {
 public:
  virtual ~Criterion() = default;

  /// The smallest element sigma1 bound that can matter: the element loop lists the cells whose
  /// bound reaches it (ForceAssembler::set_hot_threshold); infinite: none listed.
  virtual double hot_threshold(const Grid& grid, const std::vector<vtkIdType>& root) = 0;

  /// What is over the criterion with the element stresses of the last force computation, in
  /// the order the splits are made.
  virtual std::vector<SplitCandidate> candidates(const Grid& grid, const ForceAssembler& forces,
                                                 const CriterionInputs& in) = 0;

  /// The splits the candidates ask for, in order, each through `split` (which changes the
  /// grid: views of it are to be read again after each call).
  virtual void split(Grid& grid, const ForceAssembler& forces,
                     const std::vector<SplitCandidate>& candidates, const CriterionInputs& in,
                     const SplitCells& split) = 0;

  /// The force a new link with these crack faces starts at, or NaN for the paper's (2.6).
  virtual double link_force(const std::vector<CrackFace>& faces) const {
    (void)faces;
    return std::numeric_limits<double>::quiet_NaN();
  }

  /// The state a step changes, for the checkpoint (docs/checkpoint.md).
  virtual void state(StateWriter& ar) { (void)ar; }
  virtual void state(StateReader& ar) { (void)ar; }
  /// After a re-cut: the state of `src` (the same criterion) with cell e of this grid taken
  /// from cell cell_from[e] of src's (-1: none), node tables on num_points nodes.
  virtual void recut(const Criterion& src, const std::vector<vtkIdType>& cell_from,
                     vtkIdType num_points) {
    (void)src, (void)cell_from, (void)num_points;
  }

  /// Empty, or one line the run prints as a warning at its start (e.g. a length the mesh
  /// does not resolve).
  virtual std::string warning() const { return {}; }

  /// A decomposed run: the rank's view (Simulation::decompose; its part holds the cells
  /// ghost_reach asks for). Criteria whose candidates are nodes ignore it: the owner of a node
  /// decides it (Integrator::step keeps owned candidates).
  virtual void decompose(const Decomposition& d) { (void)d; }
  /// Whether the candidates are nodes decided by their owner (kept by ownership), or agreed
  /// over the ranks by the criterion itself (the facet criterion: every rank gets every face).
  virtual bool decided_by_node_owner() const { return true; }
  /// The order of a step's splits over the ranks (Halo::share_splits): false, decreasing
  /// sigma1 then node id (the node criteria's candidates); true, by node id, each node's splits
  /// in the order they were made (the facet criterion's, which splits the touched nodes in
  /// ascending id).
  virtual bool splits_in_node_order() const { return false; }
};

/// What a criterion is built from besides the scene.
struct CriterionContext {
  const Grid& grid;
  const ElementData& elements;
  /// The whole body's sizes (a decomposed run's part: its whole mesh's).
  const BodySizes& body;
  /// The strength at reference point X: sigma_c, or a Weibull sample (material.weibull_modulus).
  std::function<double(const double X[3])> strength_at;
  /// Whether node p may break: not fixed, inside fracture.region.
  std::function<bool(vtkIdType)> may_break;
};

/// The criterion fracture.criterion names (fracture.mode none: nothing; straight: the paper's
/// (6.7) on its plane). One line per criterion.
std::unique_ptr<Criterion> make_criterion(const Scene& scene, const CriterionContext& context);

/// The split of the paper's rule (SPEC 5): the plane through K normal to the candidate's
/// direction; the cells of K whose current centroid lies on its + side adopt a new node (none
/// if all or none do). K's cells are its node-table entries.
void split_by_plane(const Grid& grid, const ForceAssembler& forces, const SplitCandidate& c,
                    const SplitCells& split);

/// Refuses a criterion's length (`key`, [m]) that no ball in this body can use: longer than
/// the body's largest extent (one line naming the key, the length and the extent).
void check_length_fits(const BodySizes& body, const char* key, double length);

/// Decreasing sigma1 (or G_eps), ties by node id: the order the node criteria split in.
void sort_in_splitting_order(std::vector<SplitCandidate>& c);

}  // namespace brittle
