// The ghost exchange of a decomposed run (issue 14, docs/parallel.md): every rank steps its own
// part of the grid (extract_part: owned cells, and the ghost cells touching its owned nodes) and
// after each update the owners send the positions and velocities of their nodes to the ranks
// that hold them as ghosts. Splits are decided by the owner of the node and replayed on every
// rank that holds the node's cells, in the serial order, with the serial node ids.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "exact_sum.hpp"
#include "fracture.hpp"
#include "grid.hpp"
#include "partition.hpp"

namespace brittle {

/// A split as every rank learns it: global ids and the reference position of the node.
struct GlobalSplit {
  double sigma1 = 0;
  vtkIdType a = -1, b = -1;  ///< global ids: the node that split and the new node
  double X[3] = {0, 0, 0};   ///< reference position of a
  double A_c = 0;
  std::vector<vtkIdType> b_cells;  ///< global cells that adopted b, ascending
};

/// A link that failed (omega reached 1), as every rank learns it.
struct GlobalFailure {
  vtkIdType a = -1, b = -1;  ///< global ids of its nodes
  double X[3] = {0, 0, 0};   ///< reference position of a
  double dissipated = 0, A_c = 0;
};

/// The error of the lowest rank that has one (`mine`: this rank's, empty if none), as
/// "rank R: <error>" (rank 0's as it is); empty if no rank has one. Collective over
/// MPI_COMM_WORLD: a rank that fails alone must not leave the others waiting.
std::string first_error(const std::string& mine);

/// The event catalogue's order of the link failures within a step: by their nodes' ids.
inline bool node_order(const GlobalFailure& p, const GlobalFailure& q) {
  return std::tie(p.a, p.b, p.A_c) < std::tie(q.a, q.b, q.A_c);
}

/// One rank's view of the decomposition and its messages (MPI_COMM_WORLD). Every call is
/// collective: all ranks make the same calls in the same order. It holds nothing sized by the
/// whole grid: its part's nodes and cells, their owners and holders, and the split nodes it
/// holds.
class Halo {
 public:
  /// `part`: this process's part (extract_part, or read from a partitioned mesh).
  explicit Halo(const LocalPart& part);
  /// The same for rank `rank` of `size`, without MPI: to read a checkpoint piece that rank
  /// wrote (Simulation::read_piece). Its collective calls must not be used.
  Halo(const LocalPart& part, int rank, int size);
  ~Halo();

  /// Re-cuts a Halo built at the start of the run for the grid after the splits since
  /// (Simulation::take_part): `whole` is the whole grid now, `root` and `mother` give each of
  /// its nodes' node of the mesh and the node it split from (-1: none), `initial_owner` the
  /// owner of every node of the mesh. Daughters are owned where their mothers are; this rank
  /// holds its cells' nodes and every node it held at the start; the ghost lists follow, in
  /// increasing global id.
  void recut(const Grid& whole, const std::vector<vtkIdType>& root,
             const std::vector<vtkIdType>& mother, const std::vector<int>& initial_owner);

  int rank() const { return rank_; }
  /// What the parts hold past their owned nodes' cells (the partition's).
  const GhostReach& reach() const { return reach_; }
  int size() const { return size_; }
  /// Local node -> global node, and whether this rank owns it (grows with splits).
  const std::vector<vtkIdType>& global_node() const { return global_node_; }
  const std::vector<char>& owned() const { return owned_; }
  const std::vector<vtkIdType>& global_cell() const { return global_cell_; }
  /// Global node -> local node, global cell -> local cell (-1: not here).
  vtkIdType local_node(vtkIdType global) const;
  vtkIdType local_cell(vtkIdType global) const;
  /// Whether this rank owns the local cell (the other local cells are ghosts).
  bool owns_cell(vtkIdType local) const { return owned_cell_[local] != 0; }
  /// Per local cell: 1 if this rank owns it.
  const std::vector<std::uint8_t>& owned_cells() const { return owned_cell_; }
  /// The exact sums of every rank added (in place; the same on every rank).
  void sum(std::vector<ExactSum>& sums) const;
  /// Nodes of the whole grid now (every rank knows every split).
  vtkIdType global_nodes() const { return global_nodes_; }

  /// Ghost nodes get their owners' x and v (non-blocking sends and receives, then a wait).
  void exchange(double* x, double* v);
  /// The same in two halves (issue 27, item 4): begin posts the receives and sends the owned
  /// nodes' x and v (copied out at once), finish waits and writes the ghosts'. Work that
  /// reads no received node may run in between (ForceAssembler::Overlap).
  void begin_exchange(double* x, double* v);
  void finish_exchange(double* x, double* v);
  /// Per local node: 1 for the ghosts the exchange writes; and a number that changes when
  /// they change otherwise than by splits (a daughter is received if her mother is).
  const std::vector<std::uint8_t>& received() const { return received_; }
  std::uint64_t received_version() const { return received_version_; }
  /// Ghost nodes get their owners' velocity and mass (for output: between exchanges a ghost
  /// holds the rate the viscosity saw, and the mass of this rank's cells only).
  void refresh_for_output(double* v, double* mass);
  /// Smallest value over the ranks, with the global id that goes with it (the smaller id on
  /// ties): the stable step and the element that sets it.
  void min_with_id(double& value, vtkIdType& id) const;
  /// Largest value over the ranks.
  int max(int value) const;
  long max(long value) const;
  /// Each of `count` values the largest over the ranks, in one reduction.
  void max(long* values, int count) const;
  /// A decomposed run's agreement before a step, in one reduction: the error of the lowest
  /// rank that has one (`mine`: this rank's, empty if none), as first_error() gives it, and
  /// whether any rank asks to stop.
  bool agree(const std::string& mine, bool stop, std::string& first) const;
  /// Sum over the ranks.
  long sum(long value) const;
  /// The k-th smallest (from 0) of every rank's values, all >= 0 (element volumes), without
  /// gathering them: a bisection on the values' bits, one reduction per bit.
  double select(const std::vector<double>& mine, long k) const;
  /// Nodes of the whole grid before any split, and its cells.
  vtkIdType initial_nodes() const { return initial_nodes_; }
  vtkIdType cells() const { return cells_; }
  /// What this rank has sent and called so far (docs/parallel.md, "Scaling"): ghost bytes and
  /// messages sent point to point, and collective calls (every rank makes the same ones).
  struct Traffic {
    long bytes_sent = 0, messages = 0, collectives = 0;
  };
  Traffic traffic() const;

  /// Every rank's bytes on rank 0, in rank order (MPI_Gatherv); empty on the other ranks.
  std::vector<std::string> gather_to_root(const std::string& mine) const;
  /// Every rank's values, rank after rank (MPI_Allgatherv).
  /// `per_rank`, if given, gets each rank's count.
  std::vector<double> gather_all(const std::vector<double>& mine,
                                 std::vector<int>* per_rank = nullptr) const;

  /// The splits of this step on every rank, in the serial order (decreasing sigma1, then node
  /// id), with the serial ids of the new nodes. `own` are this rank's (local ids, from
  /// Fracture::split); the splits of other ranks are applied to the local copies of their
  /// nodes here (Fracture::apply_remote_split), and the send and receive lists follow.
  /// `removed`: the links this rank removed this step; all ranks' come back in `failures`,
  /// ordered by their nodes' global ids (the event catalogue's order within a step).
  /// `by_node`: the splits are in node id order instead, each node's in the order made
  /// (Criterion::splits_in_node_order: the facet criterion's).
  std::vector<GlobalSplit> share_splits(const std::vector<SplitRecord>& own, Grid& grid,
                                        ForceAssembler& forces, Fracture& fracture,
                                        const std::vector<CohesiveLink>& removed,
                                        std::vector<GlobalFailure>& failures,
                                        bool by_node = false);

  /// What the splits change (node ids and owners, the send and receive lists) to and from a
  /// checkpoint piece (solver/observers/checkpoint.cpp); the static rest comes from the partition.
  template <class Ar>
  void state(Ar& ar);

 private:
  struct Neighbour {
    int rank = -1;
    std::vector<vtkIdType> send, recv;  ///< local ids, in increasing global id
    std::vector<double> send_buffer, recv_buffer;
  };
  Neighbour& neighbour(int rank);
  /// Owned nodes' values of the fields (pointer, values per node) to their ghost copies:
  /// post (receives, packed sends), then finish (wait, unpack).
  void send_ghosts(std::initializer_list<std::pair<double*, int>> fields);
  void post_ghosts(std::initializer_list<std::pair<double*, int>> fields);
  void finish_ghosts(std::initializer_list<std::pair<double*, int>> fields);
  void mark_received();  // received_ from the receive lists, and a new version
  /// (rank, global id, local id) of a ghost node to send or receive.
  using Ghost = std::tuple<int, vtkIdType, vtkIdType>;
  /// The send and receive lists, per neighbour in increasing global id (both sides derive
  /// the same), and received_.
  void set_lists(std::vector<Ghost> send, std::vector<Ghost> recv);
  struct Requests;       // the posted MPI requests (halo.cpp: no MPI in this header)
  std::unique_ptr<Requests> requests_;
  std::vector<std::uint8_t> received_;
  std::uint64_t received_version_ = 0;
  /// Whether `rank` holds the local cell.
  bool holds(vtkIdType local_cell, int rank) const;

  int rank_ = 0, size_ = 1;
  GhostReach reach_;
  long bytes_sent_ = 0, messages_ = 0;
  std::vector<std::int64_t> holder_start_;  ///< per local cell: the ranks holding it (CSR)
  std::vector<int> holders_;
  std::vector<vtkIdType> global_cell_;  ///< local -> global (increasing)
  /// Local -> global: the mesh's nodes (increasing, the first mesh_nodes_), then split nodes.
  std::vector<vtkIdType> global_node_;
  std::size_t mesh_nodes_ = 0;
  std::unordered_map<vtkIdType, vtkIdType> split_local_;  ///< global -> local, split nodes here
  std::vector<char> owned_;
  std::vector<int> owner_;  ///< per local node
  std::vector<std::uint8_t> owned_cell_;
  std::vector<Neighbour> neighbours_;           ///< in increasing rank
  vtkIdType global_nodes_ = 0, initial_nodes_ = 0, cells_ = 0;
};

}  // namespace brittle
