// Faces that open (Camacho & Ortiz 1996, Pandolfi & Ortiz 2002) and the groups of cells
// that open faces cut a node's cells into.
#include "facet_criterion.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>

namespace brittle {

FacetCriterion::FacetCriterion(double beta, std::function<double(const double X[3])> strength)
    : beta_(beta), strength_of_(std::move(strength)) {}

void FacetCriterion::build(const Grid& grid, const std::vector<vtkIdType>& root) {
  const vtkIdType nc = grid.num_cells();
  const vtkIdType* cells = grid.cells();
  // A face is known by the roots of its three corners (splits rename corners to daughters,
  // whose root is the mesh's node): two cells with the same three roots face each other.
  struct Key {
    std::array<vtkIdType, 3> r;
    vtkIdType face;
  };
  std::vector<Key> keys(4 * nc);
  for (vtkIdType e = 0; e < nc; ++e)
    for (int j = 0; j < 4; ++j) {
      Key& k = keys[4 * e + j];
      int n = 0;
      for (int c = 0; c < 4; ++c)
        if (c != j) k.r[n++] = root[cells[4 * e + c]];
      std::sort(k.r.begin(), k.r.end());
      k.face = 4 * e + j;
    }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return std::tie(a.r, a.face) < std::tie(b.r, b.face);
  });
  across_.assign(4 * nc, -1);
  twin_.assign(4 * nc, -1);
  strength_.assign(4 * nc, std::numeric_limits<double>::infinity());
  weakest_ = std::numeric_limits<double>::infinity();
  const double* X = grid.X();
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    if (keys[i].r != keys[i + 1].r) continue;
    const vtkIdType f = keys[i].face, g = keys[i + 1].face;
    across_[f] = g / 4, across_[g] = f / 4;
    twin_[f] = g, twin_[g] = f;
    double centroid[3];
    for (int a = 0; a < 3; ++a)  // (roots in ascending order: the same bits from either side)
      centroid[a] =
          (X[3 * keys[i].r[0] + a] + X[3 * keys[i].r[1] + a] + X[3 * keys[i].r[2] + a]) / 3.0;
    strength_[f] = strength_[g] = strength_of_(centroid);
    weakest_ = std::min(weakest_, strength_[f]);
    ++i;
  }
}

double FacetCriterion::weakest(const Grid& grid, const std::vector<vtkIdType>& root) {
  if (across_.size() != 4 * static_cast<std::size_t>(grid.num_cells())) build(grid, root);
  return weakest_;
}

std::vector<FacetOpening> FacetCriterion::over(const Grid& grid, const ForceAssembler& forces,
                                               const std::vector<vtkIdType>& root,
                                               const std::vector<std::uint8_t>& open,
                                               const std::function<bool(vtkIdType)>& may_open) {
  if (across_.size() != 4 * static_cast<std::size_t>(grid.num_cells())) build(grid, root);
  const vtkIdType* cells = grid.cells();
  const double *x = grid.x(), *stress = grid.stress();
  // The faces to look at, each once (by the id of its side in the smaller cell): with beta = 0
  // a face over its strength has a cell whose sigma1 bound reached the weakest strength (t_n
  // of the mean is at most the mean's sigma1, at most the larger bound), which the element
  // loop listed; otherwise every interior face.
  faces_.clear();
  const auto add = [&](vtkIdType e) {
    for (int j = 0; j < 4; ++j) {
      const vtkIdType f = 4 * e + j, n = across_[f];
      if (n >= 0 && !open[f]) faces_.push_back(n > e ? f : twin_[f]);
    }
  };
  if (beta_ == 0 && forces.collects_hot_cells()) {
    forces.for_each_hot_cell(add);
    std::sort(faces_.begin(), faces_.end());
    faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());
  } else {
    for (vtkIdType e = 0; e < grid.num_cells(); ++e)
      for (int j = 0; j < 4; ++j)
        if (const vtkIdType f = 4 * e + j; across_[f] > e && !open[f]) faces_.push_back(f);
  }
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
      for (int c = 0; c < 4; ++c)
        if (c != j) p[m++] = cells[4 * e + c];
      const double *s = stress + 6 * e, *t = stress + 6 * n;
      Mat3 T;  // the mean of the two cells' stresses
      T << s[0] + t[0], s[3] + t[3], s[5] + t[5], s[3] + t[3], s[1] + t[1], s[4] + t[4],
          s[5] + t[5], s[4] + t[4], s[2] + t[2];
      T *= 0.5;
      const Vec3 a(x + 3 * p[0]), b(x + 3 * p[1]), c(x + 3 * p[2]);
      Vec3 normal = (b - a).cross(c - a);
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
  std::sort(found.begin(), found.end(), [](const FacetOpening& a, const FacetOpening& b) {
    return std::tie(b.ratio, a.face) < std::tie(a.ratio, b.face);
  });
  return found;
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
      for (int j = 0; j < 4; ++j) {  // the three faces of e that hold K
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
