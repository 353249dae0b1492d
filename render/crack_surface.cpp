// Crack faces and crack front from reference positions (crack_surface.hpp).
#include "crack_surface.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkIdList.h>
#include <vtkDataArray.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include "error.hpp"
#include "grid.hpp"

namespace brittle::render {
namespace {

using Point = std::array<double, 3>;
using FaceKey = std::array<Point, 3>;  ///< sorted reference positions of a triangle

/// A 2D body's crack (issue 53): a cracked edge is two boundary edges of the triangles with the
/// same two reference positions; each side as the "face" (a, b, b), which draws as the edge.
CrackSurface find_crack_edges(vtkUnstructuredGrid& grid, vtkDataArray& X) {
  std::map<std::pair<vtkIdType, vtkIdType>, int> uses;  // edges by grid point ids
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < grid.GetNumberOfCells(); ++c) {
    grid.GetCellPoints(c, cell);
    if (cell->GetNumberOfIds() != 3) continue;
    for (int i = 0; i < 3; ++i) {
      const vtkIdType a = cell->GetId(i), b = cell->GetId((i + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  struct Seen {
    int count = 0;
    std::array<vtkIdType, 2> first{}, second{};
  };
  std::map<std::array<Point, 2>, Seen> by_key;
  for (const auto& [edge, count] : uses) {
    if (count != 1) continue;  // interior
    std::array<Point, 2> key;
    X.GetTuple(edge.first, key[0].data());
    X.GetTuple(edge.second, key[1].data());
    std::sort(key.begin(), key.end());
    Seen& seen = by_key[key];
    (seen.count == 0 ? seen.first : seen.second) = {edge.first, edge.second};
    ++seen.count;
  }
  CrackSurface crack;
  for (const auto& [key, seen] : by_key)
    if (seen.count == 2) {
      crack.faces.push_back({seen.first[0], seen.first[1], seen.first[1]});
      crack.faces.push_back({seen.second[0], seen.second[1], seen.second[1]});
      ++crack.face_count;
    }
  return crack;
}

}  // namespace

CrackSurface find_crack_surface(vtkUnstructuredGrid& grid) {
  vtkDataArray* X = grid.GetPointData()->GetArray(field::reference_position);
  BRITTLE_CHECK(X && X->GetNumberOfComponents() == 3, "render: crack frames need the point data '",
                field::reference_position, "'");
  if (grid.GetNumberOfCells() > 0 && grid.GetCellType(0) == VTK_TRIANGLE)
    return find_crack_edges(grid, *X);
  CrackSurface crack;
  // Boundary triangles of the (split) grid, with the grid's point ids.
  vtkNew<vtkDataSetSurfaceFilter> surface;
  surface->SetInputData(&grid);
  surface->PassThroughPointIdsOn();
  surface->Update();
  vtkPolyData* faces = surface->GetOutput();
  auto* ids = vtkIdTypeArray::SafeDownCast(
      faces->GetPointData()->GetArray(surface->GetOriginalPointIdsName()));
  BRITTLE_CHECK(ids, "render: the surface filter gave no original point ids");
  auto reference = [&](vtkIdType surface_point) {
    Point p;
    X->GetTuple(ids->GetValue(surface_point), p.data());
    return p;
  };

  // Key every boundary triangle by its reference positions: twice = a cracked face.
  struct Seen {
    int count = 0;
    std::array<vtkIdType, 3> first{}, second{};
  };
  std::map<FaceKey, Seen> by_key;
  vtkCellArray* polys = faces->GetPolys();
  vtkNew<vtkIdList> cell;
  for (polys->InitTraversal(); polys->GetNextCell(cell);) {
    if (cell->GetNumberOfIds() != 3) continue;
    std::array<vtkIdType, 3> points;
    FaceKey key;
    for (int i = 0; i < 3; ++i) {
      points[i] = ids->GetValue(cell->GetId(i));
      key[i] = reference(cell->GetId(i));
    }
    std::sort(key.begin(), key.end());
    Seen& seen = by_key[key];
    (seen.count == 0 ? seen.first : seen.second) = points;
    ++seen.count;
  }

  for (const auto& [key, seen] : by_key)
    if (seen.count == 2) {
      crack.faces.push_back(seen.first);
      crack.faces.push_back(seen.second);
      ++crack.face_count;
    }
  return crack;
}

std::vector<std::array<double, 3>> shown_tips(vtkUnstructuredGrid& grid, vtkPoints& shown) {
  std::vector<std::array<double, 3>> tips;
  vtkDataArray* stored = grid.GetFieldData()->GetArray(field::crack_tips);
  vtkDataArray* X = grid.GetPointData()->GetArray(field::reference_position);
  vtkDataArray* crack = grid.GetPointData()->GetArray(field::crack);
  if (!stored || stored->GetNumberOfComponents() != 2 || !X || !crack) return tips;
  double bounds[6];
  shown.GetBounds(bounds);
  for (vtkIdType t = 0; t < stored->GetNumberOfTuples(); ++t) {
    const double x = stored->GetComponent(t, 0), y = stored->GetComponent(t, 1);
    vtkIdType best = -1;
    double best_d2 = 0;
    for (vtkIdType k = 0; k < grid.GetNumberOfPoints(); ++k) {
      if (crack->GetComponent(k, 0) == 0) continue;
      const double dx = X->GetComponent(k, 0) - x, dy = X->GetComponent(k, 1) - y;
      const double d2 = dx * dx + dy * dy;
      if (best < 0 || d2 < best_d2) best = k, best_d2 = d2;
    }
    if (best < 0) continue;
    double p[3];
    shown.GetPoint(best, p);
    tips.push_back({p[0], p[1], bounds[5]});
  }
  return tips;
}

}  // namespace brittle::render
