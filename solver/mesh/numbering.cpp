// What every mesh goes through once it is made or read (plate_mesh.hpp): the nodes and cells
// renumbered along a space-filling curve for locality, and the optional random perturbation
// of interior nodes (mesh.perturb).
#include "plate_mesh.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "error.hpp"
#include "position_hash.hpp"

namespace brittle {
namespace {

// ---------------------------------------------------------------------------------------------
// Space-filling curve

/// Spreads the low 10 bits of v so that they occupy every third bit.
std::uint32_t spread_bits(std::uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

/// Morton (Z-order) key of a point, 10 bits per axis in the cube of side `extent` at `lo`
/// (a cube, so that a thin plate is ordered in-plane first, not by its two faces).
std::uint32_t morton_key(const double* x, const double* lo, double extent) {
  std::uint32_t key = 0;
  for (int d = 0; d < 3; ++d) {
    const double u = extent > 0.0 ? (x[d] - lo[d]) / extent : 0.0;
    const auto q = static_cast<std::uint32_t>(std::clamp(u, 0.0, 1.0) * 1023.0 + 0.5);
    key |= spread_bits(q) << d;
  }
  return key;
}

/// out[new] = in[old[new]] for every tuple of every array of `data`.
void permute_arrays(vtkFieldData* data, const std::vector<vtkIdType>& old_of_new) {
  for (int a = 0; a < data->GetNumberOfArrays(); ++a) {
    vtkAbstractArray* in = data->GetAbstractArray(a);
    if (in == nullptr || in->GetNumberOfTuples() != static_cast<vtkIdType>(old_of_new.size()))
      continue;
    vtkSmartPointer<vtkAbstractArray> out;
    out.TakeReference(in->NewInstance());
    out->SetName(in->GetName());
    out->SetNumberOfComponents(in->GetNumberOfComponents());
    out->SetNumberOfTuples(in->GetNumberOfTuples());
    for (std::size_t i = 0; i < old_of_new.size(); ++i)
      out->SetTuple(static_cast<vtkIdType>(i), old_of_new[i], in);
    in->DeepCopy(out);
  }
}

double signed_volume(const std::array<std::array<double, 3>, 4>& p) {
  double a[3], b[3], c[3];
  for (int k = 0; k < 3; ++k)
    a[k] = p[1][k] - p[0][k], b[k] = p[2][k] - p[0][k], c[k] = p[3][k] - p[0][k];
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/// The grid's points and its cells of K corners.
template <std::size_t K>
void read_points_and_cells(vtkUnstructuredGrid& grid, std::vector<std::array<double, 3>>& x,
                           std::vector<std::array<vtkIdType, K>>& cells) {
  x.resize(grid.GetNumberOfPoints());
  for (vtkIdType p = 0; p < grid.GetNumberOfPoints(); ++p) grid.GetPoint(p, x[p].data());
  cells.resize(grid.GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid.GetNumberOfCells(); ++c) {
    grid.GetCellPoints(c, ids);
    for (std::size_t j = 0; j < K; ++j) cells[c][j] = ids->GetId(static_cast<vtkIdType>(j));
  }
}

/// perturb_mesh of a 2D body's triangles: every node off the boundary (the edges of one
/// triangle) moves by up to `fraction` of its shortest edge, as the tets' nodes do.
void perturb_triangles(vtkUnstructuredGrid& grid, double fraction, std::uint64_t seed) {
  const vtkIdType n = grid.GetNumberOfPoints(), cells = grid.GetNumberOfCells();
  std::vector<std::array<double, 3>> x;
  std::vector<std::array<vtkIdType, 3>> tris;
  read_points_and_cells(grid, x, tris);
  std::vector<std::array<vtkIdType, 2>> edges;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> shortest(n, inf);
  for (const auto& t : tris)
    for (int j = 0; j < 3; ++j) {
      const vtkIdType a = t[j], b = t[(j + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
      const double length = std::hypot(x[a][0] - x[b][0], x[a][1] - x[b][1]);
      shortest[a] = std::min(shortest[a], length), shortest[b] = std::min(shortest[b], length);
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint8_t> held(n, 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) held[edges[i][0]] = held[edges[i][1]] = 1;
    i = j;
  }
  vtkPoints* points = grid.GetPoints();
  for (vtkIdType p = 0; p < n; ++p) {
    if (held[p] || !std::isfinite(shortest[p])) continue;
    const std::uint64_t h = position_hash(seed, x[p].data(), 2);
    const double U1 = static_cast<double>(h >> 11) * 0x1.0p-53;
    const double U2 = static_cast<double>(mix64(h) >> 11) * 0x1.0p-53;
    const double r = fraction * shortest[p] * std::sqrt(U2), angle = 2 * M_PI * U1;
    points->SetPoint(p, x[p][0] + r * std::cos(angle), x[p][1] + r * std::sin(angle), x[p][2]);
  }
  points->Modified();
  auto area2 = [](const double* a, const double* b, const double* c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  for (vtkIdType c = 0; c < cells; ++c) {
    double after[3][3];
    for (int j = 0; j < 3; ++j) points->GetPoint(tris[c][j], after[j]);
    const double a0 = area2(x[tris[c][0]].data(), x[tris[c][1]].data(), x[tris[c][2]].data());
    const double a1 = area2(after[0], after[1], after[2]);
    BRITTLE_CHECK(a0 * a1 > 0 && std::abs(a1) > 1e-3 * std::abs(a0), "mesh.perturb = ", fraction,
                  " turns triangle ", c, " over or flat (expected a smaller value)");
  }
}

}  // namespace

void perturb_mesh(vtkUnstructuredGrid& grid, double fraction, std::uint64_t seed) {
  BRITTLE_CHECK(fraction >= 0 && fraction <= 0.3, "mesh.perturb = ", fraction,
                " is out of range (expected 0 <= perturb <= 0.3)");
  const vtkIdType n = grid.GetNumberOfPoints(), cells = grid.GetNumberOfCells();
  if (fraction == 0 || n == 0) return;
  if (cells > 0 && grid.GetCellType(0) == VTK_TRIANGLE)
    return perturb_triangles(grid, fraction, seed);
  std::vector<std::array<double, 3>> x;
  std::vector<std::array<vtkIdType, 4>> tets;
  read_points_and_cells(grid, x, tets);
  double b[6];
  grid.GetBounds(b);
  const double tol = 1e-9 * std::max({b[1] - b[0], b[3] - b[2], b[5] - b[4]});
  // The lateral boundary: faces of one tet only, whose normal is not along z.
  std::vector<std::array<vtkIdType, 3>> faces;
  faces.reserve(4 * cells);
  for (const auto& t : tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<vtkIdType, 3> f;
      for (int j = 0, k = 0; j < 4; ++j)
        if (j != skip) f[k++] = t[j];
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  std::sort(faces.begin(), faces.end());
  std::vector<std::uint8_t> held(n, 0);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1) {
      const auto& f = faces[i];
      double u[3], v[3];
      for (int k = 0; k < 3; ++k) u[k] = x[f[1]][k] - x[f[0]][k], v[k] = x[f[2]][k] - x[f[0]][k];
      const double nx = u[1] * v[2] - u[2] * v[1], ny = u[2] * v[0] - u[0] * v[2],
                   nz = u[0] * v[1] - u[1] * v[0];
      if (std::abs(nz) < 0.9 * std::sqrt(nx * nx + ny * ny + nz * nz))
        for (vtkIdType p : f) held[p] = 1;
    }
    i = j;
  }
  // The shortest in-plane edge of each node (edges of any direction where it has none).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> flat(n, inf), any(n, inf);
  for (const auto& t : tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const auto &p = x[t[i]], &q = x[t[j]];
        const double length = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
        for (vtkIdType k : {t[i], t[j]}) {
          any[k] = std::min(any[k], length);
          if (std::abs(p[2] - q[2]) <= tol) flat[k] = std::min(flat[k], length);
        }
      }
  vtkPoints* points = grid.GetPoints();
  for (vtkIdType p = 0; p < n; ++p) {
    if (held[p]) continue;
    const std::uint64_t h = position_hash(seed, x[p].data(), 2);  // x, y: columns together
    const double U1 = static_cast<double>(h >> 11) * 0x1.0p-53;
    const double U2 = static_cast<double>(mix64(h) >> 11) * 0x1.0p-53;
    const double reach = fraction * (std::isfinite(flat[p]) ? flat[p] : any[p]);
    const double r = reach * std::sqrt(U2), angle = 2 * M_PI * U1;  // uniform in the disc
    points->SetPoint(p, x[p][0] + r * std::cos(angle), x[p][1] + r * std::sin(angle), x[p][2]);
  }
  points->Modified();
  for (vtkIdType c = 0; c < cells; ++c) {
    std::array<std::array<double, 3>, 4> before, after;
    for (int j = 0; j < 4; ++j) {
      before[j] = x[tets[c][j]];
      points->GetPoint(tets[c][j], after[j].data());
    }
    const double v0 = signed_volume(before), v1 = signed_volume(after);
    BRITTLE_CHECK(v0 * v1 > 0 && std::abs(v1) > 1e-3 * std::abs(v0), "mesh.perturb = ", fraction,
                  " turns tet ", c, " over or flat (expected a smaller value)");
  }
}

void renumber_for_locality(vtkUnstructuredGrid& grid) {
  const vtkIdType n_cells = grid.GetNumberOfCells();
  const vtkIdType n_points = grid.GetNumberOfPoints();
  if (n_cells == 0 || n_points == 0) return;

  double bounds[6];
  grid.GetPoints()->GetBounds(bounds);
  const double lo[3] = {bounds[0], bounds[2], bounds[4]};
  const double extent =
      std::max({bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]});

  // Cells ordered by the Morton key of their centroids (ties: old index, so deterministic).
  std::vector<std::uint32_t> key(n_cells);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < n_cells; ++c) {
    grid.GetCellPoints(c, ids);
    double centroid[3] = {0, 0, 0};
    for (vtkIdType j = 0; j < ids->GetNumberOfIds(); ++j) {
      double x[3];
      grid.GetPoint(ids->GetId(j), x);
      for (int d = 0; d < 3; ++d) centroid[d] += x[d] / static_cast<double>(ids->GetNumberOfIds());
    }
    key[c] = morton_key(centroid, lo, extent);
  }
  std::vector<vtkIdType> old_cell(n_cells);
  std::iota(old_cell.begin(), old_cell.end(), 0);
  std::stable_sort(old_cell.begin(), old_cell.end(),
                   [&key](vtkIdType p, vtkIdType q) { return key[p] < key[q]; });

  // Points numbered by first use in the new cell order; unused points keep their order at the end.
  std::vector<vtkIdType> new_point(n_points, -1);
  std::vector<vtkIdType> old_point;
  old_point.reserve(n_points);
  for (vtkIdType c : old_cell) {
    grid.GetCellPoints(c, ids);
    for (vtkIdType j = 0; j < ids->GetNumberOfIds(); ++j) {
      const vtkIdType p = ids->GetId(j);
      if (new_point[p] < 0) {
        new_point[p] = static_cast<vtkIdType>(old_point.size());
        old_point.push_back(p);
      }
    }
  }
  for (vtkIdType p = 0; p < n_points; ++p)
    if (new_point[p] < 0) {
      new_point[p] = static_cast<vtkIdType>(old_point.size());
      old_point.push_back(p);
    }

  vtkNew<vtkPoints> points;
  points->SetDataType(grid.GetPoints()->GetDataType());
  points->SetNumberOfPoints(n_points);
  for (vtkIdType p = 0; p < n_points; ++p) points->SetPoint(p, grid.GetPoint(old_point[p]));

  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfValues(n_cells);
  vtkNew<vtkCellArray> cells;
  cells->AllocateEstimate(n_cells, 4);
  std::vector<vtkIdType> conn;
  for (vtkIdType c = 0; c < n_cells; ++c) {
    grid.GetCellPoints(old_cell[c], ids);
    conn.resize(ids->GetNumberOfIds());
    for (vtkIdType j = 0; j < ids->GetNumberOfIds(); ++j) conn[j] = new_point[ids->GetId(j)];
    cells->InsertNextCell(static_cast<vtkIdType>(conn.size()), conn.data());
    types->SetValue(c, static_cast<unsigned char>(grid.GetCellType(old_cell[c])));
  }

  permute_arrays(grid.GetPointData(), old_point);
  permute_arrays(grid.GetCellData(), old_cell);
  grid.SetPoints(points);
  grid.SetCells(types, cells);
}

}  // namespace brittle
