// The live grid: a vtkUnstructuredGrid of linear tets that *is* the simulation state
// (points = current positions, point data = nodal fields, cell data = element fields).
#pragma once

#include <vtkCellArray.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <cstdint>
#include <vector>

namespace brittle {

struct Recut;  // run/recut.hpp: how a run is cut differently (recut() below)

/// Names of the arrays kept on the live grid (written as they are to VTU).
namespace field {
inline constexpr const char* reference_position = "reference_position";  // X, point, 3
inline constexpr const char* velocity = "velocity";                      // point, 3
inline constexpr const char* displacement = "displacement";              // x - X, point, 3
inline constexpr const char* mass = "mass";                              // lumped, point, 1
inline constexpr const char* fixed = "fixed";                            // BC flag, point, 1
inline constexpr const char* crack = "crack";  // 1 on nodes made or kept by a split, point, 1
inline constexpr const char* damage = "damage";                          // Omega, cell, 1
inline constexpr const char* sigma1_over_sigmac = "sigma1_over_sigmac";  // cell, 1
inline constexpr const char* stress = "stress";  // T_el, cell, 6 (xx yy zz xy yz xz)
inline constexpr const char* time = "TimeValue";  // field data, ParaView's name
/// Field data, once a node has split: the reference (x, y) of every crack tip that has not
/// branched (CrackFronts), 2 components per tip, for crack frames [m].
inline constexpr const char* crack_tips = "crack_tips";
}  // namespace field

/// Field data of a part's mesh: the whole mesh's bounds (6), which region boxes are measured
/// against (physics/boundary.cpp; written by parallel/partition.cpp's extract_part).
inline constexpr const char* kWholeBounds = "whole_mesh_bounds";
/// Field data of a rank's part: the whole mesh's BodySizes (extent, median h_e, finest 5 % h_e).
inline constexpr const char* kWholeSizes = "whole_mesh_sizes";

/// Owns the vtkUnstructuredGrid and hands out raw contiguous views of its arrays for the
/// step loop. Views are invalidated when points are appended; call refresh() afterwards.
class Grid {
 public:
  /// Copies the reference mesh (tets only) into a new live grid with 64-bit cell storage and
  /// adds the nodal and element arrays above, zero-initialised; positions = reference.
  explicit Grid(vtkUnstructuredGrid& reference_mesh);

  vtkUnstructuredGrid* vtk() const { return grid_; }
  vtkIdType num_points() const { return num_points_; }
  vtkIdType num_cells() const { return num_cells_; }
  /// Corners per cell: 4 (tets, 3D) or 3 (triangles, a 2D body; issue 53), and the dimension.
  int corners() const { return corners_; }
  int dimension() const { return corners_ - 1; }

  // Raw views (struct of arrays); 3 doubles per point for vector fields.
  double* x() const { return x_; }                 ///< current positions
  double* X() const { return X_; }                 ///< reference positions
  double* v() const { return v_; }                 ///< velocities
  double* u() const { return u_; }                 ///< displacements (filled by update_displacement)
  double* mass() const { return mass_; }
  std::uint8_t* fixed() const { return fixed_; }
  std::uint8_t* crack() const { return crack_; }
  vtkIdType* cells() const { return conn_; }       ///< corners() point ids per cell, contiguous
  double* damage() const { return damage_; }
  double* sigma1_over_sigmac() const { return sigma1_; }
  double* stress() const { return stress_; }      ///< 6 per cell

  /// Appends a copy of point k (position and every point-data tuple) and hands corner k of
  /// the given cells over to it; both are flagged as crack nodes. Returns the new point's id.
  /// The only topology change a step makes (a restore or a re-cut replaces the grid whole);
  /// views are refreshed.
  vtkIdType split_node(vtkIdType k, const std::vector<vtkIdType>& cells);

  /// displacement = x - X, before output.
  void update_displacement();
  /// Re-reads array pointers and sizes after the VTK arrays changed size.
  void refresh();
  /// Marks the grid modified for VTK pipelines (writers, renderers) after a step.
  void mark_modified();

  /// Reads or writes the state a step changes (checkpoint.cpp, docs/checkpoint.md).
  template <class Archive>
  void state(Archive& ar);
  /// Takes positions, nodal and element values and connectivity from a grid of the same run
  /// cut differently (recut.cpp); the destination gets r.node_from.size() nodes.
  void recut(const Grid& src, const Recut& r);

 private:
  vtkSmartPointer<vtkUnstructuredGrid> grid_;
  vtkIdType num_points_ = 0, num_cells_ = 0;
  int corners_ = 4;
  double *x_ = nullptr, *X_ = nullptr, *v_ = nullptr, *u_ = nullptr, *mass_ = nullptr;
  std::uint8_t *fixed_ = nullptr, *crack_ = nullptr;
  vtkIdType* conn_ = nullptr;
  double *damage_ = nullptr, *sigma1_ = nullptr, *stress_ = nullptr;
};

}  // namespace brittle
