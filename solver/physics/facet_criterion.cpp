// Faces that open (Camacho & Ortiz 1996, Pandolfi & Ortiz 2002) and the groups of cells
// that open faces cut a node's cells into.
#include "facet_criterion.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace brittle {

FacetCriterion::FacetCriterion(const Scene& scene, const CriterionContext& context)
    : beta_(scene.fracture.beta),
      strength_of_(context.strength_at),
      sigma_c_(scene.material.sigma_c),
      traction_link_(scene.fracture.facet_link == FractureParams::FacetLink::traction) {
  corners_ = context.grid.corners();  // (a 2D body's faces are its triangles' edges)
  const auto faces = 4 * static_cast<std::size_t>(context.grid.num_cells());
  face_open_.assign(faces, 0);
  face_traction_.assign(faces, 0.0);
  std::vector<vtkIdType> root(context.grid.num_points());
  for (vtkIdType p = 0; p < context.grid.num_points(); ++p) root[p] = p;
  build(context.grid, root);  // (the mesh's own nodes: every root is itself)
}

double FacetCriterion::hot_threshold(const Grid& grid, const std::vector<vtkIdType>& root) {
  // (with a shear term the faces are all scanned: no bound from sigma1)
  return beta_ == 0 ? weakest(grid, root) : std::numeric_limits<double>::infinity();
}

std::vector<SplitCandidate> FacetCriterion::candidates(const Grid& grid,
                                                       const ForceAssembler& forces,
                                                       const CriterionInputs& in) {
  std::vector<SplitCandidate> found;
  std::vector<FacetOpening> opening = over(grid, forces, in.root, face_open_, in.may_break);
  if (decomposition_.owned) opening = agree(grid, opening);
  for (const FacetOpening& o : opening)
    found.push_back(  // (in their order: largest ratio first)
        {grid.cells()[o.face / 4 * corners_ + (o.face % 4 + 1) % corners_], o.ratio,
         Vec3::UnitY(), o.face});
  return found;
}

void FacetCriterion::split(Grid& grid, const ForceAssembler& forces,
                           const std::vector<SplitCandidate>& candidates,
                           const CriterionInputs& in, const SplitCells& split) {
  // Open the faces (both sides), then look at their corners on both sides: a corner may be
  // two daughters already, one in each cell.
  const vtkIdType* cells = grid.cells();
  std::vector<std::pair<vtkIdType, double>> touched;  // (corner, the ratio of its face)
  for (const SplitCandidate& c : candidates) {
    // (a decomposed run's rank may hold one side of a face: its twin is then -1 here)
    const vtkIdType f = c.face, g = twin(f);
    double s = strength(f);
    if (g < 0) {  // the face's strength from its corners' roots, as build() draws it
      double centroid[3];
      face_centroid(grid, in.root, f, centroid);
      s = strength_of_(centroid);
    }
    for (vtkIdType side : {f, g}) {
      if (side < 0) continue;
      face_open_[side] = 1;
      face_traction_[side] = c.sigma1 * s;  // (ratio x strength)
      for (int k = 0; k < corners_; ++k)
        if (k != side % 4) touched.emplace_back(cells[side / 4 * corners_ + k], c.sigma1);
    }
  }
  std::sort(touched.begin(), touched.end(), [](const auto& a, const auto& b) {
    return std::tie(a.first, b.second) < std::tie(b.first, a.second);
  });  // by node, then the largest ratio first
  std::vector<int> group;
  for (std::size_t i = 0; i < touched.size(); ++i) {
    if (i > 0 && touched[i].first == touched[i - 1].first) continue;
    const vtkIdType K = touched[i].first;
    if (!in.may_break(K)) continue;
    if (decomposition_.owned && !(*decomposition_.owned)[K]) continue;  // its owner splits it
    const int n = groups(forces, face_open_, K, group);
    if (n < 2) continue;
    std::vector<std::vector<vtkIdType>> of_group(n);
    const vtkIdType start = forces.node_start()[K];
    for (std::size_t k = 0; k < group.size(); ++k)
      of_group[group[k]].push_back(forces.node_entries()[start + k] / 4);
    for (int g = 1; g < n; ++g)  // the first group keeps K (entries are in cell order)
      split(K, std::move(of_group[g]), touched[i].second);
  }
}

std::vector<FacetOpening> FacetCriterion::agree(const Grid& grid,
                                               const std::vector<FacetOpening>& mine) const {
  const Decomposition& d = decomposition_;
  const std::vector<vtkIdType>&gnode = *d.global_node, &gcell = *d.global_cell;
  const vtkIdType* cells = grid.cells();
  // Mine: the faces whose corner with the smallest global id this rank owns, as (ratio, the
  // global id of the side in the smaller cell, of the other side). Local cell order is the
  // global one, so the smaller local cell is the smaller global cell.
  std::vector<double> wire;
  for (const FacetOpening& o : mine) {
    const vtkIdType f = o.face, e = f / 4;
    vtkIdType lowest = -1;
    for (int k = 0; k < corners_; ++k)
      if (k != f % 4) {
        const vtkIdType p = cells[corners_ * e + k];
        if (lowest < 0 || gnode[p] < gnode[lowest]) lowest = p;
      }
    if (!(*d.owned)[lowest]) continue;
    const vtkIdType g = twin_[f];
    wire.insert(wire.end(), {o.ratio, double(4 * gcell[e] + f % 4),
                             double(4 * gcell[g / 4] + g % 4)});
  }
  const std::vector<double> all = d.gather_all(wire);
  struct Global {
    double ratio;
    vtkIdType low, high;
  };
  std::vector<Global> faces;
  for (std::size_t i = 0; i + 2 < all.size(); i += 3)
    faces.push_back({all[i], static_cast<vtkIdType>(all[i + 1]), static_cast<vtkIdType>(all[i + 2])});
  std::sort(faces.begin(), faces.end(), [](const Global& a, const Global& b) {
    return std::tie(b.ratio, a.low) < std::tie(a.ratio, b.low);
  });  // over()'s order: largest ratio first, ties by face id
  std::vector<FacetOpening> out;
  for (const Global& g : faces) {
    if (const vtkIdType e = d.local_cell(g.low / 4); e >= 0)
      out.push_back({4 * e + g.low % 4, g.ratio});
    else if (const vtkIdType n = d.local_cell(g.high / 4); n >= 0)
      out.push_back({4 * n + g.high % 4, g.ratio});
  }
  return out;
}

double FacetCriterion::link_force(const std::vector<CrackFace>& faces) const {
  if (!traction_link_) return std::numeric_limits<double>::quiet_NaN();
  double f0 = 0;
  for (const CrackFace& c : faces) {
    const vtkIdType f = face_between(c.cell_a, c.cell_b);
    f0 += (f >= 0 ? face_traction_[f] : sigma_c_) * 0.5 * c.area;
  }
  return f0;
}

void FacetCriterion::state(StateWriter& ar) { io_all(ar, face_open_, face_traction_); }
void FacetCriterion::state(StateReader& ar) { io_all(ar, face_open_, face_traction_); }

void FacetCriterion::recut(const Criterion& src, const std::vector<vtkIdType>& cell_from,
                           vtkIdType) {
  const auto& from = static_cast<const FacetCriterion&>(src);  // (the same scene's criterion)
  // Faces by their cell and corner. A cell with no source keeps what it holds: a decomposed
  // checkpoint's pieces are absorbed one after the other, each giving its owned cells.
  face_open_.resize(4 * cell_from.size(), 0);
  face_traction_.resize(4 * cell_from.size(), 0.0);
  for (std::size_t e = 0; e < cell_from.size(); ++e)
    if (const vtkIdType s = cell_from[e]; s >= 0) {
      std::copy_n(from.face_open_.begin() + 4 * s, 4, face_open_.begin() + 4 * e);
      std::copy_n(from.face_traction_.begin() + 4 * s, 4, face_traction_.begin() + 4 * e);
    }
  reset();  // (cells renumbered)
}

void FacetCriterion::build(const Grid& grid, const std::vector<vtkIdType>& root) {
  const vtkIdType nc = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  // A face is known by the roots of its three corners (splits rename corners to daughters,
  // whose root is the mesh's node): two cells with the same three roots face each other.
  struct Key {
    std::array<vtkIdType, 3> r;
    vtkIdType face;
  };
  std::vector<Key> keys;
  keys.reserve(corners_ * nc);
  for (vtkIdType e = 0; e < nc; ++e)
    for (int j = 0; j < corners_; ++j) {  // (a triangle's edge: two roots, the third -1)
      Key k;
      k.r = {-1, -1, -1};
      int n = 3 - (corners_ - 1);
      for (int c = 0; c < corners_; ++c)
        if (c != j) k.r[n++] = root[cells[corners_ * e + c]];
      std::sort(k.r.begin(), k.r.end());
      k.face = 4 * e + j;
      keys.push_back(k);
    }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return std::tie(a.r, a.face) < std::tie(b.r, b.face);
  });
  across_.assign(4 * nc, -1);
  twin_.assign(4 * nc, -1);
  strength_.assign(4 * nc, std::numeric_limits<double>::infinity());
  weakest_ = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    if (keys[i].r != keys[i + 1].r) continue;
    const vtkIdType f = keys[i].face, g = keys[i + 1].face;
    across_[f] = g / 4, across_[g] = f / 4;
    twin_[f] = g, twin_[g] = f;
    double centroid[3];
    face_centroid(grid, root, f, centroid);
    strength_[f] = strength_[g] = strength_of_(centroid);
    weakest_ = std::min(weakest_, strength_[f]);
    ++i;
  }
}

void FacetCriterion::face_centroid(const Grid& grid, const std::vector<vtkIdType>& root,
                                   vtkIdType f, double out[3]) const {
  const vtkIdType* cells = grid.cells();
  std::array<vtkIdType, 3> r = {0, 0, 0};
  int n = 0;
  for (int k = 0; k < corners_ && n < 3; ++k)
    if (k != f % 4) r[n++] = root[cells[f / 4 * corners_ + k]];
  const auto order = [](vtkIdType& a, vtkIdType& b) {
    if (b < a) std::swap(a, b);
  };
  order(r[0], r[1]);  // ascending: two or three
  if (n == 3) order(r[1], r[2]), order(r[0], r[1]);
  const double* X = grid.X();
  for (int a = 0; a < 3; ++a)  // (roots in ascending order: the same bits from either side)
    out[a] = n == 3 ? (X[3 * r[0] + a] + X[3 * r[1] + a] + X[3 * r[2] + a]) / 3.0
                    : (X[3 * r[0] + a] + X[3 * r[1] + a]) / 2.0;
}

double FacetCriterion::weakest(const Grid& grid, const std::vector<vtkIdType>& root) {
  if (across_.size() != 4 * static_cast<std::size_t>(grid.num_cells())) build(grid, root);
  return weakest_;
}

template <int Corners>
std::vector<FacetOpening> FacetCriterion::scan(const Grid& grid, const double* stress,
                                               const std::function<bool(vtkIdType)>& may_open) {
  // Corners: 4, a tet's face (3 corners, the normal of their plane); 3, a triangle's edge (2
  // ends, the in-plane normal across it). The dimension as a parameter: the tets' loop is
  // compiled as it was before 2D bodies (the same bits).
  const vtkIdType* cells = grid.cells();
  const double* x = grid.x();
  const double inv_beta2 = beta_ > 0 ? 1.0 / (beta_ * beta_) : 0.0;
  const auto count = static_cast<std::int64_t>(faces_.size());
  std::vector<FacetOpening> found;
#pragma omp parallel
  {
    std::vector<FacetOpening> mine;
#pragma omp for schedule(static) nowait
    for (std::int64_t i = 0; i < count; ++i) {
      const vtkIdType f = faces_[i], e = f / 4, n = across_[f];
      const int j = static_cast<int>(f % 4);
      vtkIdType p[3];
      int m = 0;
      for (int c = 0; c < Corners; ++c)
        if (c != j) p[m++] = cells[Corners * e + c];
      if constexpr (Corners == 3) p[2] = p[1];  // (an edge: its second end twice)
      const double *s = stress + 6 * e, *t = stress + 6 * n;
      Mat3 T;  // the mean of the two cells' stresses
      T << s[0] + t[0], s[3] + t[3], s[5] + t[5], s[3] + t[3], s[1] + t[1], s[4] + t[4],
          s[5] + t[5], s[4] + t[4], s[2] + t[2];
      T *= 0.5;
      const Vec3 a(x + 3 * p[0]), b(x + 3 * p[1]), c(x + 3 * p[2]);
      Vec3 normal;
      if constexpr (Corners == 4)
        normal = (b - a).cross(c - a);
      else
        normal = Vec3(b.y() - a.y(), a.x() - b.x(), 0.0);  // an edge's: across it
      const double area2 = normal.norm();
      if (!(area2 > 0)) continue;
      normal /= area2;
      const Vec3 traction = T * normal;
      const double t_n = traction.dot(normal);
      const double t_s2 = std::max(0.0, traction.squaredNorm() - t_n * t_n);
      const double t_eff = std::sqrt(std::max(t_n, 0.0) * std::max(t_n, 0.0) + t_s2 * inv_beta2);
      const double ratio = t_eff / strength_[f];
      // "reaches the strength" up to round-off, as the nodal rule's sigma_c (1 + 1e-9)
      if (!(ratio >= 1.0 + 1e-9)) continue;
      if (!may_open(p[0]) || !may_open(p[1]) || !may_open(p[2])) continue;
      mine.push_back({f, ratio});
    }
#pragma omp critical
    found.insert(found.end(), mine.begin(), mine.end());
  }
  return found;
}

std::vector<FacetOpening> FacetCriterion::over(const Grid& grid, const ForceAssembler& forces,
                                               const std::vector<vtkIdType>& root,
                                               const std::vector<std::uint8_t>& open,
                                               const std::function<bool(vtkIdType)>& may_open) {
  if (across_.size() != 4 * static_cast<std::size_t>(grid.num_cells())) build(grid, root);
  const double* stress = gather(grid, forces, open);
  std::vector<FacetOpening> found = corners_ == 4 ? scan<4>(grid, stress, may_open)
                                                  : scan<3>(grid, stress, may_open);
  std::sort(found.begin(), found.end(), [](const FacetOpening& a, const FacetOpening& b) {
    return std::tie(b.ratio, a.face) < std::tie(a.ratio, b.face);
  });
  return found;
}

const double* FacetCriterion::gather(const Grid& grid, const ForceAssembler& forces,
                                     const std::vector<std::uint8_t>& open) {
  // The faces to look at, each once (by the id of its side in the smaller cell): with beta = 0
  // a face over its strength has a cell whose sigma1 bound reached the weakest strength (t_n
  // of the mean is at most the mean's sigma1, at most the larger bound), which the element
  // loop listed; otherwise every interior face.
  faces_.clear();
  if (beta_ == 0 && forces.collects_hot_cells()) {
    forces.for_each_hot_cell([&](vtkIdType e) { add_faces_of(e, open); });
    std::sort(faces_.begin(), faces_.end());
    faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());
  } else {
    for (vtkIdType e = 0; e < grid.num_cells(); ++e)
      for (int j = 0; j < 4; ++j)
        if (const vtkIdType f = 4 * e + j; across_[f] > e && !open[f]) faces_.push_back(f);
  }
  return grid.stress();
}

int FacetCriterion::groups(const ForceAssembler& forces, const std::vector<std::uint8_t>& open,
                           vtkIdType K, std::vector<int>& group) const {
  const vtkIdType first = forces.node_start()[K], last = forces.node_end()[K];
  const std::int32_t* entries = forces.node_entries().data();
  const auto m = static_cast<std::size_t>(last - first);
  group.assign(m, -1);
  // (stars hold tens of cells: a linear search finds a neighbour's entry)
  const auto entry_of = [&](vtkIdType cell) -> std::ptrdiff_t {
    for (std::size_t i = 0; i < m; ++i)
      if (entries[first + i] / 4 == cell) return static_cast<std::ptrdiff_t>(i);
    return -1;
  };
  std::vector<std::size_t> stack;
  int count = 0;
  for (std::size_t seed = 0; seed < m; ++seed) {
    if (group[seed] >= 0) continue;
    group[seed] = count;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      const vtkIdType e = entries[first + i] / 4;
      const int corner = entries[first + i] % 4;
      for (int j = 0; j < corners_; ++j) {  // the faces of e that hold K (3; a triangle's: 2)
        const vtkIdType f = 4 * e + j;
        if (j == corner || open[f] || across_[f] < 0) continue;
        const std::ptrdiff_t k = entry_of(across_[f]);
        if (k >= 0 && group[k] < 0) group[k] = count, stack.push_back(static_cast<std::size_t>(k));
      }
    }
    ++count;
  }
  return count;
}

}  // namespace brittle
