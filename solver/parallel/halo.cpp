// Ghost exchange and shared splits of a decomposed run (docs/parallel.md).
#include "halo.hpp"

#include <mpi.h>
#include <vtkIdList.h>
#include <vtkNew.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

#include "error.hpp"

namespace brittle {
namespace {

int comm_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int comm_size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

long g_collectives = 0;  ///< collective calls of this process (Halo::traffic)

}  // namespace

Halo::Halo(const LocalPart& part) : Halo(part, comm_rank(), comm_size()) {}

Halo::Halo(const LocalPart& part, int rank, int size)
    : rank_(rank),
      size_(size),
      reach_(part.reach),
      holder_start_(part.holder_start),
      holders_(part.holders),
      global_cell_(part.global_cell),
      global_node_(part.global_node),
      mesh_nodes_(part.global_node.size()),
      owned_(part.owned),
      owner_(part.owner),
      global_nodes_(part.whole_nodes),
      initial_nodes_(part.whole_nodes),
      cells_(part.whole_cells) {
  BRITTLE_CHECK(part.parts == size_, "decomposed run: a partition into ", part.parts, " parts for ",
                size_, " ranks (expected one part per rank)");
  const auto cells = static_cast<vtkIdType>(global_cell_.size());
  BRITTLE_CHECK(holder_start_.size() == global_cell_.size() + 1 &&
                    part.cell_part.size() == global_cell_.size() &&
                    owner_.size() == global_node_.size() && owned_.size() == global_node_.size() &&
                    part.mesh && part.mesh->GetNumberOfCells() == cells,
                "decomposed run: the part's tables do not match its mesh");
  for (vtkIdType i = 0; i < cells; ++i) {
    owned_cell_.push_back(part.cell_part[i] == rank_);
    BRITTLE_CHECK(holds(i, rank_), "decomposed run: cell ", global_cell_[i],
                  " is not this rank's part");
  }
  // Send: owned nodes of the local cells to the other holders of those cells. Receive: nodes
  // of the local cells that others own. Both sides derive the same lists, in global order.
  std::vector<Ghost> send, recv;
  vtkNew<vtkIdList> ids;
  for (vtkIdType i = 0; i < cells; ++i) {
    part.mesh->GetCellPoints(i, ids);
    for (vtkIdType c = 0; c < ids->GetNumberOfIds(); ++c) {
      const vtkIdType q = ids->GetId(c);
      if (owner_[q] == rank_) {
        for (std::int64_t h = holder_start_[i]; h < holder_start_[i + 1]; ++h)
          if (holders_[h] != rank_) send.emplace_back(holders_[h], global_node_[q], q);
      } else {
        recv.emplace_back(owner_[q], global_node_[q], q);
      }
    }
  }
  set_lists(std::move(send), std::move(recv));
}

vtkIdType Halo::local_node(vtkIdType global) const {
  if (global < initial_nodes_) {
    const auto end = global_node_.begin() + static_cast<std::ptrdiff_t>(mesh_nodes_);
    const auto it = std::lower_bound(global_node_.begin(), end, global);
    return it != end && *it == global ? it - global_node_.begin() : -1;
  }
  const auto it = split_local_.find(global);
  return it == split_local_.end() ? -1 : it->second;
}

vtkIdType Halo::local_cell(vtkIdType global) const {
  const auto it = std::lower_bound(global_cell_.begin(), global_cell_.end(), global);
  return it != global_cell_.end() && *it == global ? it - global_cell_.begin() : -1;
}

void Halo::recut(const Grid& whole, const std::vector<vtkIdType>& root,
                 const std::vector<vtkIdType>& mother, const std::vector<int>& initial_owner) {
  const vtkIdType n = whole.num_points();
  const vtkIdType* conn = whole.cells();
  BRITTLE_CHECK(whole.num_cells() == cells_ && n >= initial_nodes_ &&
                    static_cast<vtkIdType>(initial_owner.size()) == initial_nodes_,
                "re-cut checkpoint: a grid of ", n, " nodes and ", whole.num_cells(),
                " cells for a decomposition of ", initial_nodes_, " and ", cells_);
  auto root_of = [&](vtkIdType q) {
    return static_cast<std::size_t>(q) < root.size() ? root[q] : q;
  };
  std::vector<int> owner(initial_owner);  // (the whole state is on every rank here anyway)
  for (vtkIdType q = initial_nodes_; q < n; ++q) {  // a mother is older than her daughter
    const vtkIdType m = static_cast<std::size_t>(q) < mother.size() ? mother[q] : -1;
    BRITTLE_CHECK(m >= 0 && m < q, "re-cut checkpoint: node ", q, " has no split event");
    owner.push_back(owner[m]);
  }
  global_nodes_ = n;
  // The nodes held: those held at the start (the mesh's nodes of the local cells) and the
  // daughters at a corner of a local cell now, in increasing global id.
  std::vector<char> held(n, 0);
  for (std::size_t i = 0; i < mesh_nodes_; ++i) held[global_node_[i]] = 1;
  const int corners = whole.corners();
  for (vtkIdType e : global_cell_)
    for (int c = 0; c < corners; ++c) held[conn[corners * e + c]] = 1;
  global_node_.clear(), owned_.clear(), owner_.clear(), split_local_.clear();
  std::vector<vtkIdType> local(n, -1);
  for (vtkIdType q = 0; q < n; ++q)
    if (held[q]) {
      local[q] = static_cast<vtkIdType>(global_node_.size());
      if (q >= initial_nodes_) split_local_[q] = local[q];
      global_node_.push_back(q);
      owned_.push_back(owner[q] == rank_);
      owner_.push_back(owner[q]);
    }
  // Another rank holds an owned node of the mesh if it holds a cell with a corner descended
  // from it, and an owned daughter if it holds a cell with the daughter at a corner; the
  // owner holds every such cell.
  std::vector<Ghost> send, recv;
  for (std::size_t i = 0; i < global_cell_.size(); ++i)
    for (int c = 0; c < corners; ++c) {
      const vtkIdType q = conn[corners * global_cell_[i] + c], r = root_of(q);
      for (vtkIdType p : {q, r}) {
        if (owner[p] != rank_) continue;
        for (std::int64_t h = holder_start_[i]; h < holder_start_[i + 1]; ++h)
          if (holders_[h] != rank_) send.emplace_back(holders_[h], p, local[p]);
      }
    }
  for (vtkIdType q : global_node_)
    if (owner[q] != rank_) recv.emplace_back(owner[q], q, local[q]);
  set_lists(std::move(send), std::move(recv));
}

void Halo::set_lists(std::vector<Ghost> send, std::vector<Ghost> recv) {
  for (auto* list : {&send, &recv}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  neighbours_.clear();
  for (const auto& [r, g, q] : send) neighbour(r).send.push_back(q);
  for (const auto& [r, g, q] : recv) neighbour(r).recv.push_back(q);
  mark_received();
}

bool Halo::holds(vtkIdType i, int rank) const {
  return std::binary_search(holders_.begin() + holder_start_[i],
                            holders_.begin() + holder_start_[i + 1], rank);
}

Halo::Neighbour& Halo::neighbour(int rank) {
  auto it = std::lower_bound(neighbours_.begin(), neighbours_.end(), rank,
                             [](const Neighbour& n, int r) { return n.rank < r; });
  if (it == neighbours_.end() || it->rank != rank) {
    it = neighbours_.insert(it, Neighbour{});
    it->rank = rank;
  }
  return *it;
}

struct Halo::Requests {
  std::vector<MPI_Request> pending;
  int per_node = 0;
};

Halo::~Halo() = default;

void Halo::exchange(double* x, double* v) { send_ghosts({{x, 3}, {v, 3}}); }

void Halo::begin_exchange(double* x, double* v) {
  post_ghosts({{x, 3}, {v, 3}});
}

void Halo::finish_exchange(double* x, double* v) {
  finish_ghosts({{x, 3}, {v, 3}});
}

void Halo::refresh_for_output(double* v, double* mass) { send_ghosts({{v, 3}, {mass, 1}}); }

void Halo::send_ghosts(std::initializer_list<std::pair<double*, int>> fields) {
  post_ghosts(fields);
  finish_ghosts(fields);
}

void Halo::post_ghosts(std::initializer_list<std::pair<double*, int>> fields) {
  if (!requests_) requests_ = std::make_unique<Requests>();
  BRITTLE_ASSERT(requests_->pending.empty());
  int per_node = 0;
  for (const auto& f : fields) per_node += f.second;
  requests_->per_node = per_node;
  std::vector<MPI_Request>& requests = requests_->pending;
  requests.reserve(2 * neighbours_.size());
  for (Neighbour& n : neighbours_) {
    if (n.recv.empty()) continue;
    n.recv_buffer.resize(per_node * n.recv.size());
    requests.emplace_back();
    MPI_Irecv(n.recv_buffer.data(), static_cast<int>(n.recv_buffer.size()), MPI_DOUBLE, n.rank, 0,
              MPI_COMM_WORLD, &requests.back());
  }
  for (Neighbour& n : neighbours_) {
    if (n.send.empty()) continue;
    n.send_buffer.resize(per_node * n.send.size());
    double* b = n.send_buffer.data();
    for (vtkIdType i : n.send)
      for (const auto& [field, width] : fields)
        for (int k = 0; k < width; ++k) *b++ = field[width * i + k];
    requests.emplace_back();
    bytes_sent_ += static_cast<long>(sizeof(double) * n.send_buffer.size());
    ++messages_;
    MPI_Isend(n.send_buffer.data(), static_cast<int>(n.send_buffer.size()), MPI_DOUBLE, n.rank, 0,
              MPI_COMM_WORLD, &requests.back());
  }
}

void Halo::finish_ghosts(std::initializer_list<std::pair<double*, int>> fields) {
  BRITTLE_ASSERT(requests_);
  std::vector<MPI_Request>& requests = requests_->pending;
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  requests.clear();
  for (const Neighbour& n : neighbours_) {
    const double* b = n.recv_buffer.data();
    for (vtkIdType i : n.recv)
      for (const auto& [field, width] : fields)
        for (int k = 0; k < width; ++k) field[width * i + k] = *b++;
  }
}

void Halo::mark_received() {
  received_.assign(global_node_.size(), 0);
  for (const Neighbour& n : neighbours_)
    for (vtkIdType i : n.recv) received_[i] = 1;
  ++received_version_;
}

Halo::Traffic Halo::traffic() const { return {bytes_sent_, messages_, g_collectives}; }

namespace {

/// (value, id) pairs: the smaller value, the smaller id on ties; a NaN value is the smallest
/// (as the stable-step scan takes the first NaN). A total order, so the reduction is
/// commutative and its result does not depend on how MPI groups the ranks.
void least_value_then_id(void* in, void* inout, int* len, MPI_Datatype*) {
  const double* a = static_cast<const double*>(in);
  double* b = static_cast<double*>(inout);
  for (int i = 0; i < *len; ++i, a += 2, b += 2) {
    const bool a_nan = std::isnan(a[0]), b_nan = std::isnan(b[0]);
    const bool first = a_nan != b_nan                  ? a_nan
                       : !a_nan && a[0] != b[0] ? a[0] < b[0]
                                                : a[1] < b[1];  // equal (or both NaN): the id
    if (first) b[0] = a[0], b[1] = a[1];
  }
}

}  // namespace

void Halo::min_with_id(double& value, vtkIdType& id) const {
  ++g_collectives;  // one reduction of (value, id) pairs (ids below 2^53 are exact doubles)
  static const MPI_Datatype pair = [] {
    MPI_Datatype t;
    MPI_Type_contiguous(2, MPI_DOUBLE, &t);
    MPI_Type_commit(&t);
    return t;
  }();
  static const MPI_Op least = [] {
    MPI_Op op;
    MPI_Op_create(&least_value_then_id, /*commute=*/1, &op);
    return op;
  }();
  double both[2] = {value, static_cast<double>(id)};
  MPI_Allreduce(MPI_IN_PLACE, both, 1, pair, least, MPI_COMM_WORLD);
  value = both[0];
  id = static_cast<vtkIdType>(both[1]);
}

int Halo::max(int value) const {
  ++g_collectives;
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

long Halo::max(long value) const {
  ++g_collectives;
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

void Halo::max(long* values, int count) const {
  ++g_collectives;
  MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
}

namespace {

/// The text of rank `from`'s error on every rank ("rank R: ..." but for rank 0), as
/// first_error() names it.
std::string broadcast_error(const std::string& mine, int from) {
  long length = static_cast<long>(mine.size());
  MPI_Bcast(&length, 1, MPI_LONG, from, MPI_COMM_WORLD);
  std::string text = mine;
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, from, MPI_COMM_WORLD);
  return from == 0 ? text : "rank " + std::to_string(from) + ": " + text;
}

}  // namespace

bool Halo::agree(const std::string& mine, bool stop, std::string& first) const {
  ++g_collectives;
  // The lowest rank with an error is the largest of size - rank (0: none).
  int values[2] = {mine.empty() ? 0 : size_ - rank_, stop ? 1 : 0};
  MPI_Allreduce(MPI_IN_PLACE, values, 2, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  first = values[0] == 0 ? std::string() : broadcast_error(mine, size_ - values[0]);
  return values[1] != 0;
}

long Halo::sum(long value) const {
  ++g_collectives;
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return value;
}

double Halo::select(const std::vector<double>& mine, long k) const {
  // Non-negative doubles are ordered as their bit patterns: find the smallest pattern v with
  // more than k values <= v.
  std::vector<std::uint64_t> bits(mine.size());
  for (std::size_t i = 0; i < mine.size(); ++i) {
    BRITTLE_CHECK(mine[i] >= 0, "Halo::select: a negative value ", mine[i]);
    std::memcpy(&bits[i], &mine[i], sizeof(double));
  }
  std::sort(bits.begin(), bits.end());
  BRITTLE_CHECK(k >= 0 && k < sum(static_cast<long>(bits.size())), "Halo::select: no value ", k);
  std::uint64_t lo = 0, hi = 0x7ff0000000000000ull;  // +inf
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    const long at_most =
        static_cast<long>(std::upper_bound(bits.begin(), bits.end(), mid) - bits.begin());
    if (sum(at_most) > k)
      hi = mid;
    else
      lo = mid + 1;
  }
  double v = 0;
  std::memcpy(&v, &lo, sizeof v);
  return v;
}

std::string first_error(const std::string& mine) {
  const int rank = comm_rank(), size = comm_size();
  ++g_collectives;
  int first = mine.empty() ? size : rank;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == size) return {};
  return broadcast_error(mine, first);
}

std::vector<double> Halo::gather_all(const std::vector<double>& mine,
                                     std::vector<int>* per_rank) const {
  g_collectives += 2;
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(size_), offsets(size_ + 1, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int r = 0; r < size_; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<double> all(offsets[size_]);
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);
  if (per_rank) *per_rank = counts;
  return all;
}

std::vector<std::string> Halo::gather_to_root(const std::string& mine) const {
  g_collectives += 3;
  long total = static_cast<long>(mine.size());  // the same verdict on every rank
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  BRITTLE_CHECK(total < (1L << 31) - 1, "decomposed run: ", total,
                " bytes to gather on rank 0 (expected below 2 GiB: a grid this large is "
                "rendered afterwards, brittle render RUN_DIR)");
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(size_), offsets(size_ + 1, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (rank_ == 0) {
    for (int r = 0; r < size_; ++r) offsets[r + 1] = offsets[r] + counts[r];
    all.resize(static_cast<std::size_t>(offsets[size_]));
  }
  MPI_Gatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), offsets.data(), MPI_CHAR,
              0, MPI_COMM_WORLD);
  std::vector<std::string> out;
  if (rank_ == 0)
    for (int r = 0; r < size_; ++r) out.push_back(all.substr(offsets[r], counts[r]));
  return out;
}

void Halo::sum(std::vector<ExactSum>& sums) const {
  std::vector<double> mine;  // the words travel as doubles' bits
  for (const ExactSum& s : sums) {
    const ExactSum::Words w = s.words();
    const std::size_t at = mine.size();
    mine.resize(at + w.size());
    std::memcpy(mine.data() + at, w.data(), sizeof(w));
  }
  const std::vector<double> all = gather_all(mine);
  const std::size_t per_rank = mine.size();
  for (auto& s : sums) s = ExactSum();
  for (int r = 0; r < size_; ++r)
    for (std::size_t i = 0; i < sums.size(); ++i) {
      ExactSum::Words w;
      std::memcpy(w.data(), all.data() + r * per_rank + i * w.size(), sizeof(w));
      sums[i] += ExactSum::from_words(w);
    }
}

std::vector<GlobalSplit> Halo::share_splits(const std::vector<SplitRecord>& own, Grid& grid,
                                            ForceAssembler& forces, Fracture& fracture,
                                            const std::vector<CohesiveLink>& removed,
                                            std::vector<GlobalFailure>& failures,
                                            bool by_node) {
  // This rank's splits made local nodes; they are named below in the global order.
  const vtkIdType before = static_cast<vtkIdType>(global_node_.size());
  global_node_.resize(grid.num_points(), -1);
  owned_.resize(grid.num_points(), 1);
  owner_.resize(grid.num_points(), rank_);
  received_.resize(grid.num_points(), 0);  // own daughters: not received
  // Wire format: failure count, then per failure a, b, X (3), dissipated, A_c; per split:
  // sigma1, a, X (3), A_c, cell count, cells (doubles hold ids < 2^53).
  std::vector<double> wire{double(removed.size())};
  for (const CohesiveLink& l : removed) {
    const double* X = grid.X() + 3 * l.a;
    wire.insert(wire.end(), {double(global_node_[l.a]), double(global_node_[l.b]), X[0], X[1],
                             X[2], l.dissipated, l.A_c});
  }
  for (const SplitRecord& r : own) {
    const double* X = grid.X() + 3 * r.a;
    wire.insert(wire.end(), {r.sigma1, double(global_node_[r.a]), X[0], X[1], X[2], r.A_c,
                             double(r.b_cells.size())});
    for (vtkIdType c : r.b_cells) wire.push_back(double(global_cell_[c]));
  }
  std::vector<int> counts;
  const std::vector<double> all = gather_all(wire, &counts);
  std::vector<GlobalSplit> splits;
  failures.clear();
  std::size_t rank_end = 0;
  for (std::size_t i = 0, r = 0; i < all.size();) {
    if (i == rank_end) {  // a rank's failures first
      rank_end += counts[r++];
      const std::size_t n = static_cast<std::size_t>(all[i++]);
      for (std::size_t k = 0; k < n; ++k, i += 7) {
        GlobalFailure f;
        f.a = static_cast<vtkIdType>(all[i]);
        f.b = static_cast<vtkIdType>(all[i + 1]);
        std::copy(&all[i + 2], &all[i + 5], f.X);
        f.dissipated = all[i + 5];
        f.A_c = all[i + 6];
        failures.push_back(f);
      }
      continue;
    }
    GlobalSplit s;
    s.sigma1 = all[i];
    s.a = static_cast<vtkIdType>(all[i + 1]);
    std::copy(&all[i + 2], &all[i + 5], s.X);
    s.A_c = all[i + 5];
    const std::size_t cells = static_cast<std::size_t>(all[i + 6]);
    for (std::size_t k = 0; k < cells; ++k) s.b_cells.push_back(static_cast<vtkIdType>(all[i + 7 + k]));
    i += 7 + cells;
    splits.push_back(std::move(s));
  }
  std::sort(failures.begin(), failures.end(), node_order);
  // The serial order (Fracture::candidates): decreasing sigma1, then node id; or by node id,
  // a node's splits (all from its owner, in the order made) kept in order.
  if (by_node)
    std::stable_sort(splits.begin(), splits.end(),
                     [](const GlobalSplit& p, const GlobalSplit& q) { return p.a < q.a; });
  else
    std::sort(splits.begin(), splits.end(), [](const GlobalSplit& p, const GlobalSplit& q) {
      return std::tie(q.sigma1, p.a) < std::tie(p.sigma1, q.a);
    });
  std::size_t next_own = 0;
  std::vector<vtkIdType> cells;
  for (GlobalSplit& s : splits) {
    s.b = global_nodes_++;
    // A daughter is owned where her mother is; a rank that does not hold the mother holds
    // none of her cells, nor the daughter.
    const vtkIdType A = local_node(s.a);
    if (A >= 0 && owned_[A]) {
      // Own splits come in the same relative order (local order = global order).
      BRITTLE_CHECK(next_own < own.size() && own[next_own].a == A, "decomposed run: split of node ",
                    s.a, " out of order");
      const vtkIdType B = own[next_own++].b;
      BRITTLE_CHECK(B >= before, "decomposed run: split node ", B, " is not new");
      global_node_[B] = s.b;
      split_local_[s.b] = B;
      for (Neighbour& n : neighbours_)
        if (std::any_of(s.b_cells.begin(), s.b_cells.end(),
                        [&](vtkIdType c) { return holds(local_cell(c), n.rank); }))
          n.send.push_back(B);
    } else if (A >= 0) {
      cells.clear();
      for (vtkIdType c : s.b_cells)
        if (const vtkIdType i = local_cell(c); i >= 0) cells.push_back(i);
      if (!cells.empty()) {
        const vtkIdType B = fracture.apply_remote_split(grid, forces, A, cells);
        global_node_.push_back(s.b);
        owned_.push_back(0);
        owner_.push_back(owner_[A]);
        received_.push_back(1);  // as her mother: the late blocks stay as they were
        split_local_[s.b] = B;
        neighbour(owner_[A]).recv.push_back(B);
      }
    }
    fracture.count_split(s.A_c, s.X[0], s.X[1]);
  }
  BRITTLE_CHECK(next_own == own.size(), "decomposed run: ", own.size() - next_own,
                " splits of this rank were not shared");
  return splits;
}

}  // namespace brittle
