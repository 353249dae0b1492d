// Re-cutting a run's state to another decomposition (docs/checkpoint.md, "Another rank
// count"): a checkpoint written over N MPI ranks (or serially) goes on over M. Every class a
// step changes copies its state from a source of the same run cut differently: the per-node
// and per-cell values by id, the values that hold ids (connectivity, links, roots) renamed,
// and the exact sums of owned contributions added whole (their sum does not depend on how
// they are split).
#pragma once

#include <vtkType.h>

#include <vector>

namespace brittle {

/// How a source's ids map onto a destination's. A decomposed run's part and the whole grid
/// (its serial ids) are the two ends: a part's owned values go into the whole, or the whole's
/// values into a part.
struct Recut {
  std::vector<vtkIdType> node_from;  ///< per destination node: its source node, -1: kept
  std::vector<vtkIdType> cell_from;  ///< per destination cell: its source cell, -1: kept
  std::vector<vtkIdType> node_to;    ///< per source node: its destination node, or -1
  std::vector<vtkIdType> cell_to;    ///< per source cell: its destination cell, or -1
  std::vector<char> link_taken;      ///< per source node: its links (node a) go over
  bool sums = false;                 ///< the source's exact sums are added to the destination's
};

}  // namespace brittle
