// The crack of a split grid, found exactly from its reference positions (docs/rendering.md,
// "crack" frames): a node split copies the reference position, so a cracked face becomes two
// boundary triangles of the grid with the same three reference positions, one per side, while
// the plate's own outer faces (notches included) appear once. The tips come from the solver's
// crack fronts (field data crack_tips), not from the faces: around every split node the split
// surface has a border, and only the tracker knows which borders are tips.
#pragma once

#include <array>
#include <vector>

#include <vtkType.h>

class vtkPoints;
class vtkUnstructuredGrid;

namespace brittle::render {

struct CrackSurface {
  /// Both sides of every cracked face: point ids of the grid, 3 per triangle (a 2D body's
  /// cracked edge a-b: (a, b, b)).
  std::vector<std::array<vtkIdType, 3>> faces;
  /// Cracked faces counted once (the two sides are one face).
  long face_count = 0;
};

/// Finds the crack of `grid` (needs the point array reference_position; throws brittle::Error
/// otherwise). An uncracked grid gives an empty surface.
CrackSurface find_crack_surface(vtkUnstructuredGrid& grid);

/// The crack tips stored on the grid (field data crack_tips, reference x and y) placed where
/// they are shown: at the current position of the crack node whose reference position is
/// nearest (z: the plate's front face). None when the grid has no such array.
std::vector<std::array<double, 3>> shown_tips(vtkUnstructuredGrid& grid, vtkPoints& shown);

}  // namespace brittle::render
