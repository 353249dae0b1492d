// Domain decomposition of the tet grid for MPI runs (issue 14, docs/parallel.md): cells split
// into parts by METIS on the dual graph (cells adjacent through a face), nodes owned by a fixed
// rule, and the ghost layer each part needs so that every owned node's force (a sum over its
// cells in global cell order), nodal stress (2.10) and split decision are computed locally;
// deeper for a criterion that reads further (GhostReach, docs/parallel.md "Ghost depth").
#pragma once

#include <cstdint>
#include <vector>

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "criterion.hpp"
#include "grid.hpp"

namespace brittle {

/// What one part (rank) holds.
struct PartStats {
  long owned_cells = 0, owned_nodes = 0;
  long ghost_cells = 0;  ///< cells of other parts held (computed redundantly), extra ones too
  long extra_ghost_cells = 0;  ///< of those, the ones the reach adds beyond the first layer
  long ghost_nodes = 0;  ///< nodes of the part's cells (owned and ghost) owned elsewhere
                         ///< (received every step)
  int neighbours = 0;    ///< parts it receives ghost nodes from (messages per step)
};

struct Partition {
  int parts = 1;
  std::vector<int> cell_part;   ///< per cell, 0..parts-1
  std::vector<int> node_owner;  ///< per node: the part of its lowest-numbered cell
  std::vector<PartStats> stats;
  long cut_faces = 0;           ///< faces between cells of different parts
  GhostReach reach;             ///< what each part holds past its owned nodes' cells
  /// Per cell: the parts that hold it, ascending, in holders[holder_start[e],
  /// holder_start[e + 1]) (its own part, its nodes' owners, and the parts whose reach takes it).
  std::vector<std::int64_t> holder_start;
  std::vector<int> holders;
  BodySizes body;               ///< the whole grid's (a part's mesh carries them, kWholeSizes)

  /// Ghost nodes of all parts over all nodes.
  double ghost_fraction() const;
  /// Ghost cells of all parts over all cells: the redundant element work.
  double redundant_fraction() const;
  /// Largest owned-cell count over the mean: the load imbalance.
  double imbalance() const;
};

/// What one rank holds of the grid: its owned cells and the ghost cells that touch its owned
/// nodes (it may own none of a held cell's nodes), and the cells the partition's reach adds, in
/// global cell order, and the nodes of those cells, in global node order, as a mesh of its own
/// (reference positions). With the first layer an owned node's force is the same sum, in the
/// same order, as in the whole grid (docs/parallel.md); with the reach, a criterion's reading.
struct LocalPart {
  vtkSmartPointer<vtkUnstructuredGrid> mesh;  ///< local cells and nodes, reference positions
  std::vector<vtkIdType> global_cell;         ///< local cell -> global cell (increasing)
  std::vector<vtkIdType> global_node;         ///< local node -> global node (increasing)
  std::vector<char> owned;                    ///< per local node: owned by this rank
  std::vector<int> owner;                     ///< per local node: the rank that owns it
  std::vector<int> cell_part;                 ///< per local cell: the rank that owns it
  /// Per local cell: the ranks that hold it (its part and its nodes' owners), ascending, in
  /// holders[holder_start[i], holder_start[i + 1]).
  std::vector<std::int64_t> holder_start;
  std::vector<int> holders;
  vtkIdType whole_nodes = 0, whole_cells = 0;  ///< the whole grid's
  int parts = 1;
  GhostReach reach;  ///< the partition's
};

/// The part `rank` of `partition` (grid: the whole grid, its reference positions X).
LocalPart extract_part(const Grid& grid, const Partition& partition, int rank);

/// Partitions the grid's cells into `parts` with METIS_PartMeshDual (faces: 3 common nodes;
/// fixed seed, so the same grid always gives the same partition: the reach does not change it)
/// and computes each part's ghost cells for `reach`. parts = 1 gives everything to part 0.
/// Throws brittle::Error if METIS fails.
/// `body`: the grid's BodySizes if the caller has them (else computed here).
Partition partition_grid(const Grid& grid, int parts, const GhostReach& reach = {},
                         const BodySizes* body = nullptr);

/// A given cell partition (cell_part: per cell, 0..parts-1; tests place boundaries by hand) with
/// the node owners and ghost cells it implies. cut_faces is left 0.
Partition partition_from(const Grid& grid, std::vector<int> cell_part, int parts,
                         const GhostReach& reach = {}, const BodySizes* body = nullptr);

/// The whole grid's BodySizes (its element sizes as ElementData's h_e).
BodySizes grid_body_sizes(const Grid& grid);

}  // namespace brittle
