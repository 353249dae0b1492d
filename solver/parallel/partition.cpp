// METIS partition of the cells and the ghost layers it implies (docs/parallel.md).
#include "partition.hpp"

#include <metis.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkCellType.h>
#include <vtkPoints.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <unordered_map>

#include "element_forces.hpp"
#include "error.hpp"
#include "triangle_forces.hpp"

namespace brittle {

double Partition::ghost_fraction() const {
  long ghosts = 0;
  for (const PartStats& s : stats) ghosts += s.ghost_nodes;
  return node_owner.empty() ? 0.0 : double(ghosts) / double(node_owner.size());
}

double Partition::redundant_fraction() const {
  long ghosts = 0;
  for (const PartStats& s : stats) ghosts += s.ghost_cells;
  return cell_part.empty() ? 0.0 : double(ghosts) / double(cell_part.size());
}

double Partition::imbalance() const {
  long most = 0;
  for (const PartStats& s : stats) most = std::max(most, s.owned_cells);
  return cell_part.empty() ? 1.0 : double(most) * parts / double(cell_part.size());
}

namespace {

/// Node -> cells (CSR, cells in increasing order).
void node_cells(const Grid& grid, std::vector<long>& start, std::vector<long>& cells) {
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  const vtkIdType* conn = grid.cells();
  const int k = grid.corners();
  start.assign(n + 1, 0);
  for (vtkIdType i = 0; i < k * m; ++i) ++start[conn[i] + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  cells.resize(k * m);
  std::vector<long> fill(start.begin(), start.end() - 1);
  for (vtkIdType e = 0; e < m; ++e)
    for (int c = 0; c < k; ++c) cells[fill[conn[k * e + c]]++] = e;
}

}  // namespace

Partition partition_grid(const Grid& grid, int parts, const GhostReach& reach,
                         const BodySizes* body) {
  BRITTLE_CHECK(parts >= 1, "partition: ", parts, " parts (expected at least 1)");
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  BRITTLE_CHECK(m < (vtkIdType(1) << 29), "partition: ", m,
                " cells are more than METIS's 32-bit indices take here");
  Partition p;
  p.parts = parts;
  p.cell_part.assign(m, 0);
  if (parts > 1 && m > 0) {
    // Neighbours across a face (a tet's 3 nodes) or an edge (a triangle's 2)
    const int k = grid.corners();
    idx_t ne = static_cast<idx_t>(m), nn = static_cast<idx_t>(n), ncommon = k - 1,
          nparts = parts, objval = 0;
    std::vector<idx_t> eptr(m + 1), eind(k * m), epart(m), npart(n);
    for (vtkIdType e = 0; e <= m; ++e) eptr[e] = static_cast<idx_t>(k * e);
    for (vtkIdType i = 0; i < k * m; ++i) eind[i] = static_cast<idx_t>(grid.cells()[i]);
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;        // the same grid, the same partition
    options[METIS_OPTION_NUMBERING] = 0;
    const int rc = METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr,
                                      &ncommon, &nparts, nullptr, options, &objval, epart.data(),
                                      npart.data());
    BRITTLE_CHECK(rc == METIS_OK, "partition: METIS failed (code ", rc, ") for ", parts,
                  " parts of ", m, " cells");
    for (vtkIdType e = 0; e < m; ++e) p.cell_part[e] = static_cast<int>(epart[e]);
    p.cut_faces = objval;
  }
  const long cut = p.cut_faces;
  p = partition_from(grid, std::move(p.cell_part), parts, reach, body);
  p.cut_faces = cut;
  return p;
}

BodySizes grid_body_sizes(const Grid& grid) {
  // h_e as the run computes it (make_element_data, make_triangle_data: the same bits; the
  // constants and the thickness do not enter)
  if (grid.corners() == 3)
    return body_sizes(grid,
                      make_triangle_data(grid, ElasticConstants{}, MaterialParams{}, 1.0).h_e);
  return body_sizes(grid, make_element_data(grid, ElasticConstants{}, MaterialParams{}).h_e);
}

namespace {

/// The cells within `distance` of a point of a marked cell (cell_mark[e] == mark), by their
/// reference centroids: buckets of side distance + the largest centroid-to-corner radius, so
/// that such a cell lies in a bucket next to its marked cell's.
class Reach {
 public:
  Reach(const Grid& grid, double distance) : distance_(distance) {
    const vtkIdType m = grid.num_cells();
    const vtkIdType* conn = grid.cells();
    const double* X = grid.X();
    centroid_.resize(3 * m);
    radius_.resize(m);
    double largest = 0;
    const int corners = grid.corners();
    for (vtkIdType e = 0; e < m; ++e) {
      double* c = &centroid_[3 * e];
      if (corners == 3) {
        const vtkIdType* t = conn + 3 * e;
        for (int a = 0; a < 3; ++a)
          c[a] = (X[3 * t[0] + a] + X[3 * t[1] + a] + X[3 * t[2] + a]) / 3.0;
      } else {
        for (int a = 0; a < 3; ++a)
          c[a] = 0.25 * (X[3 * conn[4 * e] + a] + X[3 * conn[4 * e + 1] + a] +
                         X[3 * conn[4 * e + 2] + a] + X[3 * conn[4 * e + 3] + a]);
      }
      double r2 = 0;
      for (int k = 0; k < corners; ++k) {
        const double* p = X + 3 * conn[corners * e + k];
        r2 = std::max(r2, (p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                              (p[2] - c[2]) * (p[2] - c[2]));
      }
      radius_[e] = std::sqrt(r2);
      largest = std::max(largest, radius_[e]);
    }
    side_ = (distance + largest) * (1 + 1e-9) + 1e-300;
    for (vtkIdType e = 0; e < m; ++e) buckets_[key(bucket(&centroid_[3 * e]))].push_back(e);
  }

  /// Marks (cell_mark = mark) the unmarked cells within the distance of a marked one: those in
  /// the buckets next to a bucket that holds a marked cell.
  void grow(std::vector<int>& cell_mark, int mark) const {
    std::vector<std::array<long long, 3>> near_marked;
    for (const auto& [k, cells] : buckets_)
      for (vtkIdType e : cells)
        if (cell_mark[e] == mark) {
          near_marked.push_back(bucket(&centroid_[3 * e]));
          break;
        }
    std::vector<long long> look;  // the buckets next to those, each once
    for (const auto& b : near_marked)
      for (long long i = -1; i <= 1; ++i)
        for (long long j = -1; j <= 1; ++j)
          for (long long l = -1; l <= 1; ++l) look.push_back(key({b[0] + i, b[1] + j, b[2] + l}));
    std::sort(look.begin(), look.end());
    look.erase(std::unique(look.begin(), look.end()), look.end());
    std::vector<vtkIdType> found;
    for (long long k : look) {
      const auto here = buckets_.find(k);
      if (here == buckets_.end()) continue;
      for (vtkIdType c : here->second)
        if (cell_mark[c] != mark && near(c, cell_mark, mark)) found.push_back(c);
    }
    for (vtkIdType c : found) cell_mark[c] = mark;
  }

 private:
  /// Whether a marked cell e has cell c's centroid within distance + its radius.
  bool near(vtkIdType c, const std::vector<int>& cell_mark, int mark) const {
    const double* C = &centroid_[3 * c];
    const auto b = bucket(C);
    for (long long i = b[0] - 1; i <= b[0] + 1; ++i)
      for (long long j = b[1] - 1; j <= b[1] + 1; ++j)
        for (long long l = b[2] - 1; l <= b[2] + 1; ++l) {
          const auto it = buckets_.find(key({i, j, l}));
          if (it == buckets_.end()) continue;
          for (vtkIdType e : it->second) {
            if (cell_mark[e] != mark) continue;
            const double* E = &centroid_[3 * e];
            const double d2 = (C[0] - E[0]) * (C[0] - E[0]) + (C[1] - E[1]) * (C[1] - E[1]) +
                              (C[2] - E[2]) * (C[2] - E[2]);
            const double r = distance_ + radius_[e];
            if (d2 <= r * r) return true;
          }
        }
    return false;
  }
  std::array<long long, 3> bucket(const double* c) const {
    return {static_cast<long long>(std::floor(c[0] / side_)),
            static_cast<long long>(std::floor(c[1] / side_)),
            static_cast<long long>(std::floor(c[2] / side_))};
  }
  static long long key(const std::array<long long, 3>& b) {
    return ((b[0] + 1048576) * 2097152LL + (b[1] + 1048576)) * 2097152LL + (b[2] + 1048576);
  }
  double distance_, side_ = 1;
  std::vector<double> centroid_, radius_;
  std::unordered_map<long long, std::vector<vtkIdType>> buckets_;
};

}  // namespace

Partition partition_from(const Grid& grid, std::vector<int> cell_part, int parts,
                         const GhostReach& reach, const BodySizes* body) {
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  BRITTLE_CHECK(parts >= 1 && static_cast<vtkIdType>(cell_part.size()) == m,
                "partition: ", cell_part.size(), " cell parts for ", m, " cells in ", parts,
                " parts (expected one part per cell)");
  for (int q : cell_part)
    BRITTLE_CHECK(q >= 0 && q < parts, "partition: part ", q, " (expected 0 to ", parts - 1, ")");
  BRITTLE_CHECK(reach.layers >= 1 && reach.distance >= 0 && std::isfinite(reach.distance),
                "partition: a ghost reach of ", reach.layers, " layers and ", reach.distance,
                " m (expected at least 1 layer and a finite distance >= 0)");
  Partition p;
  p.parts = parts;
  p.reach = reach;
  p.cell_part = std::move(cell_part);
  p.body = body ? *body : grid_body_sizes(grid);
  std::vector<long> start, cells;
  node_cells(grid, start, cells);
  p.node_owner.assign(n, 0);
  for (vtkIdType k = 0; k < n; ++k)
    if (start[k + 1] > start[k]) p.node_owner[k] = p.cell_part[cells[start[k]]];

  // Per part: the cells it holds (owned, touching an owned node, the reach's), and their nodes.
  p.stats.assign(parts, {});
  const vtkIdType* conn = grid.cells();
  const int corners = grid.corners();
  std::unique_ptr<Reach> far;
  if (parts > 1 && reach.distance > 0) far = std::make_unique<Reach>(grid, reach.distance);
  std::vector<int> cell_mark(m, -1), node_mark(n, -1), ring(n, -1);
  std::vector<std::int64_t> count(m, 0);
  std::vector<char> neighbour(parts, 0);
  std::vector<std::vector<vtkIdType>> held(parts);  // per part: its cells, ascending
  for (vtkIdType k = 0; k < n; ++k) ++p.stats[p.node_owner[k]].owned_nodes;
  for (vtkIdType e = 0; e < m; ++e) ++p.stats[p.cell_part[e]].owned_cells;
  for (int r = 0; r < parts; ++r) {
    PartStats& s = p.stats[r];
    // The first layer: owned cells and the cells of owned nodes; then a ring per layer.
    for (vtkIdType e = 0; e < m; ++e)
      if (p.cell_part[e] == r) cell_mark[e] = r;
    for (vtkIdType k = 0; k < n; ++k)
      if (p.node_owner[k] == r)
        for (long i = start[k]; i < start[k + 1]; ++i) cell_mark[cells[i]] = r;
    long first = 0;
    for (vtkIdType e = 0; e < m; ++e) first += cell_mark[e] == r;
    for (int layer = 2; layer <= reach.layers && parts > 1; ++layer) {
      for (vtkIdType e = 0; e < m; ++e)
        if (cell_mark[e] == r)
          for (int c = 0; c < corners; ++c) ring[conn[corners * e + c]] = r;
      for (vtkIdType k = 0; k < n; ++k)
        if (ring[k] == r)
          for (long i = start[k]; i < start[k + 1]; ++i) cell_mark[cells[i]] = r;
    }
    if (far) far->grow(cell_mark, r);
    std::fill(neighbour.begin(), neighbour.end(), 0);
    for (vtkIdType e = 0; e < m; ++e) {
      if (cell_mark[e] != r) continue;
      held[r].push_back(e);
      ++count[e];
      if (p.cell_part[e] != r) ++s.ghost_cells;
      for (int c = 0; c < corners; ++c) {
        const vtkIdType q = conn[corners * e + c];
        if (node_mark[q] == r || p.node_owner[q] == r) continue;
        node_mark[q] = r;
        ++s.ghost_nodes;
        neighbour[p.node_owner[q]] = 1;
      }
    }
    s.extra_ghost_cells = static_cast<long>(held[r].size()) - first;
    s.neighbours = static_cast<int>(std::count(neighbour.begin(), neighbour.end(), 1));
  }
  // Holders per cell, ascending (parts in increasing order).
  p.holder_start.assign(m + 1, 0);
  for (vtkIdType e = 0; e < m; ++e) p.holder_start[e + 1] = p.holder_start[e] + count[e];
  p.holders.resize(p.holder_start[m]);
  std::vector<std::int64_t> fill(p.holder_start.begin(), p.holder_start.end() - 1);
  for (int r = 0; r < parts; ++r)
    for (vtkIdType e : held[r]) p.holders[fill[e]++] = r;
  return p;
}

LocalPart extract_part(const Grid& grid, const Partition& partition, int rank) {
  BRITTLE_CHECK(rank >= 0 && rank < partition.parts, "partition: rank ", rank,
                " is not a part (expected 0 to ", partition.parts - 1, ")");
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  const vtkIdType* conn = grid.cells();
  const int corners = grid.corners();
  // The cells the part holds (Partition::holders), then their nodes; both in global order.
  std::vector<char> cell_in(m, 0), node_in(n, 0);
  for (vtkIdType e = 0; e < m; ++e)
    cell_in[e] = std::binary_search(partition.holders.begin() + partition.holder_start[e],
                                    partition.holders.begin() + partition.holder_start[e + 1],
                                    rank);
  LocalPart part;
  for (vtkIdType e = 0; e < m; ++e)
    if (cell_in[e]) {
      part.global_cell.push_back(e);
      for (int c = 0; c < corners; ++c) node_in[conn[corners * e + c]] = 1;
    }
  std::vector<vtkIdType> local(n, -1);
  for (vtkIdType k = 0; k < n; ++k)
    if (node_in[k]) {
      local[k] = static_cast<vtkIdType>(part.global_node.size());
      part.global_node.push_back(k);
      part.owned.push_back(partition.node_owner[k] == rank);
    }
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(part.global_node.size()));
  for (std::size_t i = 0; i < part.global_node.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), grid.X() + 3 * part.global_node[i]);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (vtkIdType e : part.global_cell) {
    vtkIdType ids[4];
    for (int c = 0; c < corners; ++c) ids[c] = local[conn[corners * e + c]];
    cells->InsertNextCell(corners, ids);
  }
  part.mesh = vtkSmartPointer<vtkUnstructuredGrid>::New();
  part.mesh->SetPoints(points);
  part.mesh->SetCells(corners == 3 ? VTK_TRIANGLE : VTK_TETRA, cells);
  auto bounds = vtkSmartPointer<vtkDoubleArray>::New();  // region boxes (boundary.cpp)
  bounds->SetName(kWholeBounds);
  bounds->SetNumberOfComponents(6);
  bounds->SetNumberOfTuples(1);
  double* b = bounds->GetPointer(0);  // of the reference positions, as vtkDataSet::GetBounds
  for (int d = 0; d < 3; ++d) b[2 * d] = INFINITY, b[2 * d + 1] = -INFINITY;
  for (vtkIdType k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d)
      b[2 * d] = std::min(b[2 * d], grid.X()[3 * k + d]),
      b[2 * d + 1] = std::max(b[2 * d + 1], grid.X()[3 * k + d]);
  part.mesh->GetFieldData()->AddArray(bounds);
  auto sizes = vtkSmartPointer<vtkDoubleArray>::New();  // the criteria's lengths (criterion.hpp)
  sizes->SetName(kWholeSizes);
  sizes->SetNumberOfComponents(3);
  sizes->InsertNextTuple3(partition.body.extent, partition.body.median_h, partition.body.fine_h);
  part.mesh->GetFieldData()->AddArray(sizes);
  // What the Halo needs of the whole partition, for this part only.
  for (vtkIdType k : part.global_node) part.owner.push_back(partition.node_owner[k]);
  part.holder_start.push_back(0);
  for (vtkIdType e : part.global_cell) {
    part.cell_part.push_back(partition.cell_part[e]);
    part.holders.insert(part.holders.end(), partition.holders.begin() + partition.holder_start[e],
                        partition.holders.begin() + partition.holder_start[e + 1]);
    part.holder_start.push_back(static_cast<std::int64_t>(part.holders.size()));
  }
  part.whole_nodes = n, part.whole_cells = m, part.parts = partition.parts;
  part.reach = partition.reach;
  return part;
}

}  // namespace brittle
