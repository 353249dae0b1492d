// Boundary conditions, external loads and the initial state: fixed components, prescribed
// velocities and tractions on regions, the paper's uniaxial pre-stress (B.6)-(B.9) or rest.
#pragma once

#include <vtkUnstructuredGrid.h>

#include <cstdint>
#include <string>
#include <vector>

#include "exact_sum.hpp"
#include "grid.hpp"
#include "material.hpp"
#include "scene.hpp"

namespace brittle {

/// Bits of the grid's `fixed` array (point data "fixed" in the VTU files).
namespace constraint {
inline constexpr std::uint8_t x = 1, y = 2, z = 4;  ///< velocity component prescribed
inline constexpr std::uint8_t no_split = 8;         ///< carries a load or constraint: never splits
}  // namespace constraint

/// Name of the point array that marks the nodes of a physical group of a .msh mesh.
std::string group_array_name(const std::string& group);

/// Nodes of the mesh inside a region (box with a tolerance of 1e-6 of the mesh diagonal, or a
/// physical group), in node order. Throws naming `where` if there is none (unless allowed).
std::vector<vtkIdType> select_nodes(const RegionParams& region, vtkUnstructuredGrid& mesh,
                                    const std::string& where, bool allow_empty = false);

/// A boundary face (triangle of exactly one tet) with its corner nodes and reference area; in
/// a 2D body, a boundary edge (of exactly one triangle): 2 corners, area = length x thickness.
struct BoundaryFace {
  vtkIdType node[3] = {-1, -1, -1};
  int corners = 3;
  double area = 0;
  double normal[3] = {0, 0, 0};  ///< outward unit normal (reference)
};

/// What a region selected on this mesh (faces or nodes) and the error if the whole grid's
/// selection is empty: a decomposed run's part may miss a region that the whole grid has.
struct RegionSelection {
  long count = 0;
  std::string empty_error;
};

/// Boundary faces whose three nodes are all in the region. Throws when the region holds no
/// boundary face (on a rank's part: the whole grid's is checked over the ranks) or holds
/// interior faces (a traction acts on the surface only).
/// A mesh of triangles (a 2D body of `thickness`): its boundary edges.
std::vector<BoundaryFace> select_boundary_faces(const RegionParams& region,
                                                vtkUnstructuredGrid& mesh,
                                                const std::string& where, double thickness = 0);

/// Sets positions and velocities at t = 0 (SPEC 3): the uniaxial stretch (B.6) for the
/// pre-stress `sigma` along y (initial.state = prestress) or the reference configuration
/// (rest), then the initial velocities of [initial.NAME].
void apply_initial_state(const Scene& scene, double sigma, const ElasticConstants& c, Grid& grid,
                         vtkUnstructuredGrid& mesh);

/// The scene's boundary conditions as node lists: constraints (fixed and prescribed-velocity
/// components) and tractions turned into nodal forces, f_i = t A / 3 per face corner: the
/// exact integral of t N_i over a linear triangle of the reference surface. Called by the
/// integrator after each half kick; books the work done on the body by tractions and by the
/// reactions at constrained components.
class Boundary;
/// The boundary's selections and those of the initial velocities' regions
/// ([initial.NAME]), for the check over the ranks (Simulation::decompose).
std::vector<RegionSelection> region_selections(const Scene& scene, vtkUnstructuredGrid& mesh,
                                               const Boundary& boundary);

class Boundary {
 public:
  /// Selects every region and marks the grid's `fixed` bits. Without [boundary.*] sections, a
  /// pre-stressed plate holds y = +-H/2 (the paper's plate, SPEC 3). Throws brittle::Error
  /// naming the section for an empty selection or a traction on interior faces.
  Boundary(const Scene& scene, Grid& grid, vtkUnstructuredGrid& mesh);

  /// After a half kick v += tau F/m of the element forces F (constrained components skipped):
  /// adds tau f_ext(t)/m to the loaded nodes and sets constrained components to their
  /// prescribed velocity at `t_velocity`, booking the work of both as impulse times the mean
  /// of the velocities before and after (exact for the kinetic energy of a kick).
  void after_kick(Grid& grid, const double* force, double tau, double t_force, double t_velocity);

  /// Sets constrained components to their prescribed velocity at t (the initial state).
  void impose_velocities(Grid& grid, double t) const;

  /// Work done on the body so far by tractions and by the reactions at constrained nodes [J].
  /// Work of tractions and reactions on the body so far, exact (solver/physics/exact_sum.hpp).
  ExactSum external_work_sum() const {
    ExactSum w = traction_work_;
    w += reaction_work_;
    return w;
  }
  double external_work() const { return external_work_sum().value(); }
  double traction_work() const { return traction_work_.value(); }
  double reaction_work() const { return reaction_work_.value(); }
  /// A decomposed run: loads and constraints act on the nodes this rank owns only (ghost
  /// nodes get their owners' velocities), so each node's work is counted once.
  void keep_nodes(const std::vector<char>& owned);
  bool empty() const { return constraints_.empty() && loads_.empty(); }

  /// Per region that must select something: how much this mesh's selection holds (faces or
  /// nodes), and the error if the whole grid's holds nothing. A rank's part may miss a region
  /// (its count is 0 there); Simulation::decompose sums the counts over the ranks.
  const std::vector<RegionSelection>& selections() const { return selections_; }

  /// One line per boundary: name, type, nodes (faces), for the run log.
  const std::vector<std::string>& description() const { return description_; }

  /// Reads or writes the state a step changes (checkpoint.cpp, docs/checkpoint.md).
  template <class Archive>
  void state(Archive& ar);
  /// The source's works added if r.sums (recut.cpp).
  void recut(const Boundary& src, const Recut& r);

 private:
  struct Constrained {  // one node of one velocity / fixed boundary
    vtkIdType node;
    std::uint8_t mask;        // constraint::x | y | z
    std::size_t boundary[3];  // per constrained component: its [boundary.*] section
  };
  struct Loaded {  // one node of one traction boundary
    vtkIdType node;
    double f[3];  // nodal force at history factor 1
    std::size_t boundary;
  };
  std::vector<BoundaryParams> params_;
  std::vector<Constrained> constraints_;
  std::vector<Loaded> loads_;
  std::vector<std::string> description_;
  std::vector<RegionSelection> selections_;
  ExactSum traction_work_, reaction_work_;
};

}  // namespace brittle
