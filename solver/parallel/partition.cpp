// METIS partition of the cells and the ghost layers it implies (docs/parallel.md).
#include "partition.hpp"

#include <metis.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkCellType.h>
#include <vtkPoints.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "error.hpp"

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
  start.assign(n + 1, 0);
  for (vtkIdType i = 0; i < 4 * m; ++i) ++start[conn[i] + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  cells.resize(4 * m);
  std::vector<long> fill(start.begin(), start.end() - 1);
  for (vtkIdType e = 0; e < m; ++e)
    for (int c = 0; c < 4; ++c) cells[fill[conn[4 * e + c]]++] = e;
}

}  // namespace

Partition partition_grid(const Grid& grid, int parts) {
  BRITTLE_CHECK(parts >= 1, "partition: ", parts, " parts (expected at least 1)");
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  BRITTLE_CHECK(m < (vtkIdType(1) << 29), "partition: ", m,
                " cells are more than METIS's 32-bit indices take here");
  Partition p;
  p.parts = parts;
  p.cell_part.assign(m, 0);
  if (parts > 1 && m > 0) {
    idx_t ne = static_cast<idx_t>(m), nn = static_cast<idx_t>(n), ncommon = 3,
          nparts = parts, objval = 0;
    std::vector<idx_t> eptr(m + 1), eind(4 * m), epart(m), npart(n);
    for (vtkIdType e = 0; e <= m; ++e) eptr[e] = static_cast<idx_t>(4 * e);
    for (vtkIdType i = 0; i < 4 * m; ++i) eind[i] = static_cast<idx_t>(grid.cells()[i]);
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
  p = partition_from(grid, std::move(p.cell_part), parts);
  p.cut_faces = cut;
  return p;
}

Partition partition_from(const Grid& grid, std::vector<int> cell_part, int parts) {
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  BRITTLE_CHECK(parts >= 1 && static_cast<vtkIdType>(cell_part.size()) == m,
                "partition: ", cell_part.size(), " cell parts for ", m, " cells in ", parts,
                " parts (expected one part per cell)");
  for (int q : cell_part)
    BRITTLE_CHECK(q >= 0 && q < parts, "partition: part ", q, " (expected 0 to ", parts - 1, ")");
  Partition p;
  p.parts = parts;
  p.cell_part = std::move(cell_part);
  std::vector<long> start, cells;
  node_cells(grid, start, cells);
  p.node_owner.assign(n, 0);
  for (vtkIdType k = 0; k < n; ++k)
    if (start[k + 1] > start[k]) p.node_owner[k] = p.cell_part[cells[start[k]]];

  // Per part: the cells touching an owned node, and the nodes of those cells.
  p.stats.assign(parts, {});
  const vtkIdType* conn = grid.cells();
  std::vector<int> cell_mark(m, -1), node_mark(n, -1);
  std::vector<char> neighbour(parts, 0);
  for (vtkIdType k = 0; k < n; ++k) ++p.stats[p.node_owner[k]].owned_nodes;
  for (vtkIdType e = 0; e < m; ++e) ++p.stats[p.cell_part[e]].owned_cells;
  for (int r = 0; r < parts; ++r) {
    PartStats& s = p.stats[r];
    std::fill(neighbour.begin(), neighbour.end(), 0);
    auto hold = [&](long e) {
      if (cell_mark[e] == r) return;
      cell_mark[e] = r;
      if (p.cell_part[e] != r) ++s.ghost_cells;
      for (int c = 0; c < 4; ++c) {
        const vtkIdType q = conn[4 * e + c];
        if (node_mark[q] == r || p.node_owner[q] == r) continue;
        node_mark[q] = r;
        ++s.ghost_nodes;
        neighbour[p.node_owner[q]] = 1;
      }
    };
    for (vtkIdType e = 0; e < m; ++e)
      if (p.cell_part[e] == r) hold(e);
    for (vtkIdType k = 0; k < n; ++k)
      if (p.node_owner[k] == r)
        for (long i = start[k]; i < start[k + 1]; ++i) hold(cells[i]);
    s.neighbours = static_cast<int>(std::count(neighbour.begin(), neighbour.end(), 1));
  }
  return p;
}

LocalPart extract_part(const Grid& grid, const Partition& partition, int rank) {
  BRITTLE_CHECK(rank >= 0 && rank < partition.parts, "partition: rank ", rank,
                " is not a part (expected 0 to ", partition.parts - 1, ")");
  const vtkIdType n = grid.num_points(), m = grid.num_cells();
  const vtkIdType* conn = grid.cells();
  // Owned cells and the cells touching an owned node, then their nodes; both in global order.
  std::vector<char> cell_in(m, 0), node_in(n, 0);
  for (vtkIdType e = 0; e < m; ++e) {
    cell_in[e] = partition.cell_part[e] == rank;
    for (int c = 0; c < 4; ++c)
      if (partition.node_owner[conn[4 * e + c]] == rank) cell_in[e] = 1;
  }
  LocalPart part;
  for (vtkIdType e = 0; e < m; ++e)
    if (cell_in[e]) {
      part.global_cell.push_back(e);
      for (int c = 0; c < 4; ++c) node_in[conn[4 * e + c]] = 1;
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
    const vtkIdType ids[4] = {local[conn[4 * e]], local[conn[4 * e + 1]], local[conn[4 * e + 2]],
                              local[conn[4 * e + 3]]};
    cells->InsertNextCell(4, ids);
  }
  part.mesh = vtkSmartPointer<vtkUnstructuredGrid>::New();
  part.mesh->SetPoints(points);
  part.mesh->SetCells(VTK_TETRA, cells);
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
  // What the Halo needs of the whole partition, for this part only.
  for (vtkIdType k : part.global_node) part.owner.push_back(partition.node_owner[k]);
  part.holder_start.push_back(0);
  for (vtkIdType e : part.global_cell) {
    part.cell_part.push_back(partition.cell_part[e]);
    int r[5] = {partition.cell_part[e], partition.node_owner[conn[4 * e]],
                partition.node_owner[conn[4 * e + 1]], partition.node_owner[conn[4 * e + 2]],
                partition.node_owner[conn[4 * e + 3]]};
    std::sort(r, r + 5);
    part.holders.insert(part.holders.end(), r, std::unique(r, r + 5));
    part.holder_start.push_back(static_cast<std::int64_t>(part.holders.size()));
  }
  part.whole_nodes = n, part.whole_cells = m, part.parts = partition.parts;
  return part;
}

}  // namespace brittle
