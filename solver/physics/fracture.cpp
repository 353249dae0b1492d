// Node splitting (2.10)-(2.12), (6.7) and the nodal cohesive links it creates (2.6), (3.8), (A.1).
#include "fracture.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include <Eigen/Eigenvalues>

#include "error.hpp"
#include "position_hash.hpp"

namespace brittle {

namespace {

/// Decreasing sigma1 (or G_eps), ties by node id: the order splits are made in.
void sort_in_splitting_order(std::vector<SplitCandidate>& c) {
  std::sort(c.begin(), c.end(), [](const SplitCandidate& a, const SplitCandidate& b) {
    return std::tie(b.sigma1, a.node) < std::tie(a.sigma1, b.node);
  });
}

}  // namespace

Fracture::Fracture(const Scene& scene, const Grid& grid, const ElementData& elements,
                   CohesiveLinks& links)
    : mode_(scene.fracture.mode),
      region_(scene.fracture.region),
      sigma_c_(scene.material.sigma_c),
      rho0_(scene.material.rho0),
      G_c_(2.0 * scene.material.gamma),
      weibull_m_(scene.material.weibull_modulus),
      weibull_scale_(weibull_m_ > 0 ? sigma_c_ / std::tgamma(1.0 + 1.0 / weibull_m_) : 0.0),
      strength_seed_(static_cast<std::uint64_t>(scene.material.strength_seed)),
      links_(links),
      tip_x_(std::numeric_limits<double>::quiet_NaN()),
      tip_y_(std::numeric_limits<double>::quiet_NaN()) {
  root_.resize(grid.num_points());
  for (vtkIdType p = 0; p < grid.num_points(); ++p) root_[p] = p;
  split_time_.assign(grid.num_points(), std::numeric_limits<double>::quiet_NaN());
  if (mode_ == FractureParams::Mode::branching &&
      scene.fracture.criterion == FractureParams::Criterion::energy) {
    double epsilon = scene.fracture.epsilon;
    if (!(epsilon > 0)) {  // 3 x the median element size
      std::vector<double> h = elements.h_e;
      BRITTLE_CHECK(!h.empty(), "fracture.criterion = energy: the mesh has no cells");
      std::nth_element(h.begin(), h.begin() + h.size() / 2, h.end());
      epsilon = 3.0 * h[h.size() / 2];
    }
    energy_ = std::make_unique<EnergyCriterion>(grid, elements, epsilon, scene.material.E, G_c_,
                                                sigma_c_,
                                                plane_stress_rayleigh_speed(scene.material));
  }
  if (mode_ == FractureParams::Mode::branching &&
      scene.fracture.criterion == FractureParams::Criterion::facet) {
    facet_ = std::make_unique<FacetCriterion>(scene.fracture.beta,
                                              [this](const double X[3]) { return strength_at(X); });
    face_open_.assign(4 * static_cast<std::size_t>(grid.num_cells()), 0);
    face_traction_.assign(4 * static_cast<std::size_t>(grid.num_cells()), 0.0);
    traction_link_ = scene.fracture.facet_link == FractureParams::FacetLink::traction;
    facet_->weakest(grid, root_);  // (builds the face tables)
  }
  if (mode_ != FractureParams::Mode::straight) return;
  const double tol = 1e-6 * scene.geometry.H;
  const double* X = grid.X();
  for (vtkIdType p = 0; p < grid.num_points(); ++p)
    if (!grid.fixed()[p] && std::abs(X[3 * p + 1]) < tol &&
        X[3 * p] >= scene.geometry.notch_depth - tol && may_break(grid, p))
      plane_nodes_.push_back(p);
}

/// sigma_c,K = s0 (-ln U)^(1/m), s0 = sigma_c / Gamma(1 + 1/m): Weibull, mean sigma_c; U from a
/// hash of the seed and the bits of the node's reference position (docs/branching.md).
double Fracture::strength(const Grid& grid, vtkIdType p) const {
  return strength_at(grid.X() + 3 * p);
}

double Fracture::strength_at(const double X[3]) const {
  if (weibull_m_ <= 0) return sigma_c_;
  const std::uint64_t h = position_hash(strength_seed_, X, 3);
  const double U = (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;  // in (0, 1)
  return weibull_scale_ * std::pow(-std::log(U), 1.0 / weibull_m_);
}

const double* Fracture::strengths(const Grid& grid) const {
  if (weibull_m_ <= 0) return nullptr;
  const auto n = static_cast<std::size_t>(grid.num_points());
  if (node_strength_.size() > n) node_strength_.clear();  // (a restored, smaller grid)
  for (std::size_t p = node_strength_.size(); p < n; ++p)
    node_strength_.push_back(strength(grid, static_cast<vtkIdType>(p)));
  return node_strength_.data();
}

double Fracture::hot_threshold(const Grid& grid) const {
  if (mode_ != FractureParams::Mode::branching) return std::numeric_limits<double>::infinity();
  if (energy_) return energy_->hot_stress();
  if (facet_)  // (with a shear term the faces are all scanned: no bound from sigma1)
    return facet_->beta() == 0 ? facet_->weakest(grid, root_)
                               : std::numeric_limits<double>::infinity();
  const double* own = strengths(grid);
  if (!own) return sigma_c_;  // (candidates() adds its 1e-9 margin above this)
  return *std::min_element(own, own + grid.num_points());
}

bool Fracture::may_break(const Grid& grid, vtkIdType p) const {
  if (region_.empty()) return true;
  const double x = grid.X()[3 * p], y = grid.X()[3 * p + 1];
  return x >= region_[0] && x <= region_[1] && y >= region_[2] && y <= region_[3];
}

std::vector<SplitCandidate> Fracture::candidates(const Grid& grid,
                                                 const ForceAssembler& forces) const {
  std::vector<SplitCandidate> found;
  if (mode_ == FractureParams::Mode::none) return found;
  if (energy_) return energy_candidates(grid, forces);
  if (facet_) {
    const std::uint8_t* fixed = grid.fixed();
    const std::vector<FacetOpening> open =
        facet_->over(grid, forces, root_, face_open_,
                     [&](vtkIdType p) { return !fixed[p] && may_break(grid, p); });
    for (const FacetOpening& o : open)  // (in their order: largest ratio first)
      found.push_back(
          {grid.cells()[o.face / 4 * 4 + (o.face + 1) % 4], o.ratio, Vec3::UnitY(), o.face});
    return found;
  }
  const bool straight = mode_ == FractureParams::Mode::straight;
  const vtkIdType *start = forces.node_start().data(), *end = forces.node_end().data();
  const std::int32_t* entries = forces.node_entries().data();
  const double *bound = forces.sigma1_bound(), *stress = grid.stress();
  const std::uint8_t* fixed = grid.fixed();
  // "sigma1 reaches sigma_c" up to round-off: a plate loaded to exactly sigma_c holds T_yy =
  // sigma_c to ~1e-15 everywhere, and that uniform state must not break every node at once.
  const double sigma_c = sigma_c_ * (1.0 + 1e-9);
  // Heterogeneous strengths (material.weibull_modulus): each node's own, with the same margin.
  const double* own = strengths(grid);
  const auto strength_of = [&](vtkIdType p) { return own ? own[p] * (1.0 + 1e-9) : sigma_c; };
  // The average's largest principal value (and its normal component) is at most the largest
  // bound of the node's elements: only corners of elements whose bound reaches sigma_c can
  // split. Straight mode has its few plane nodes; elsewhere they are found from the elements.
  if (!straight) {
    const vtkIdType* cells = grid.cells();
    hot_.resize(grid.num_points(), 0);
    for (vtkIdType p : hot_nodes_) hot_[p] = 0;  // last step's marks
    hot_nodes_.clear();
    auto visit = [&](vtkIdType e) {
      const vtkIdType* corner = cells + 4 * e;
      const double weakest =
          own ? std::min(std::min(strength_of(corner[0]), strength_of(corner[1])),
                         std::min(strength_of(corner[2]), strength_of(corner[3])))
              : sigma_c;
      if (bound[e] >= weakest)
        for (int k = 0; k < 4; ++k) hot_[corner[k]] = 1;
    };
    // The element loop listed the cells whose bound reached the weakest strength of the
    // grid (hot_threshold): a superset of those visited here (damage only lowers bounds).
    if (forces.collects_hot_cells())
      forces.for_each_hot_cell(visit);
    else
      for (vtkIdType e = 0; e < grid.num_cells(); ++e) visit(e);
    // Ascending: one pass over the marks (a byte per node) costs less than sorting the list.
    for (vtkIdType p = 0; p < grid.num_points(); ++p)
      if (hot_[p]) hot_nodes_.push_back(p);
  }
  const std::vector<vtkIdType>& nodes = straight ? plane_nodes_ : hot_nodes_;
  const vtkIdType count = static_cast<vtkIdType>(nodes.size());

#pragma omp parallel
  {
    std::vector<SplitCandidate> mine;
#pragma omp for schedule(static) nowait
    for (vtkIdType i = 0; i < count; ++i) {
      const vtkIdType p = nodes[i];
      const double sigma_K = strength_of(p);
      if (fixed[p] || (!straight && !may_break(grid, p))) continue;
      if (straight) {  // (hot nodes passed this filter by construction)
        double most = -std::numeric_limits<double>::infinity();
        for (vtkIdType k = start[p]; k < end[p]; ++k) most = std::max(most, bound[entries[k] / 4]);
        if (most < sigma_K) continue;
      }
      const Mat3 T = nodal_average_stress(forces, stress, p);  // (2.10)
      SplitCandidate c;
      c.node = p;
      if (straight) {
        c.sigma1 = T(1, 1);  // sigma1 = n . T_avg n, n = e_y   (6.7)
      } else {
        if (principal_values_below(T, sigma_K)) continue;  // no eigen-solve needed
        Eigen::SelfAdjointEigenSolver<Mat3> eig;
        eig.computeDirect(T);
        c.sigma1 = eig.eigenvalues()[2];  // sigma1 >= sigma2 >= sigma3   (2.12)
        c.normal = eig.eigenvectors().col(2);
      }
      if (c.sigma1 >= sigma_K) mine.push_back(c);
    }
#pragma omp critical
    found.insert(found.end(), mine.begin(), mine.end());
  }
  sort_in_splitting_order(found);
  return found;
}

std::vector<SplitCandidate> Fracture::energy_candidates(const Grid& grid,
                                                        const ForceAssembler& forces) const {
  const std::uint8_t* fixed = grid.fixed();
  const double G_min = G_c_ * (1.0 + 1e-9);  // (the same round-off margin as sigma_c's)
  const std::vector<EnergySplit> accepted = energy_->splits(
      grid, forces, G_min, [&](vtkIdType p) { return !fixed[p] && may_break(grid, p); },
      split_time_.data(), time_);
  std::vector<SplitCandidate> found;
  for (const EnergySplit& s : accepted) found.push_back({s.node, s.G, s.normal});
  sort_in_splitting_order(found);
  return found;
}

std::vector<SplitRecord> Fracture::split(Grid& grid, const ElementData& elements,
                                         ForceAssembler& forces,
                                         const std::vector<SplitCandidate>& candidates) {
  if (facet_) return split_facets(grid, elements, forces, candidates);
  std::vector<SplitRecord> records;
  for (const SplitCandidate& c : candidates) {
    SplitRecord r;
    if (!split_one(grid, elements, forces, c, r)) continue;
    if (count_splits_) {
      const double* X = grid.X() + 3 * r.a;
      count_split(r.A_c, X[0], X[1]);
    }
    records.push_back(std::move(r));
  }
  return records;
}

void Fracture::note_split(vtkIdType K) {
  root_.push_back(root_[K]);  // the new node's
  split_time_.push_back(time_);
  split_time_[K] = time_;
}

void Fracture::count_split(double A_c, double X, double Y) {
  crack_area_ += A_c;
  ++splits_;
  if (std::isnan(tip_x_) || X > tip_x_) tip_x_ = X, tip_y_ = Y;
}

vtkIdType Fracture::apply_remote_split(Grid& grid, ForceAssembler& forces, vtkIdType K,
                                       const std::vector<vtkIdType>& cells) {
  const vtkIdType B = grid.split_node(K, cells);
  forces.split_node(grid, K, B, cells);
  note_split(K);
  links_.resize_nodes(grid.num_points());
  return B;
}

std::vector<SplitRecord> Fracture::split_nodes(Grid& grid, const ElementData& elements,
                                               ForceAssembler& forces) {
  if (!enabled()) return {};
  const std::vector<SplitCandidate> over = candidates(grid, forces);
  if (over.empty()) return {};
  return split(grid, elements, forces, over);
}

bool Fracture::split_one(Grid& grid, const ElementData& elements, ForceAssembler& forces,
                         const SplitCandidate& c, SplitRecord& r) {
  const vtkIdType K = c.node;
  // Cells of K: the node table is from the start of the step; splits of other nodes in this
  // step only renamed *their* corners, so K's cells are still exactly these (in cell order).
  const vtkIdType *start = forces.node_start().data(), *end = forces.node_end().data();
  const std::int32_t* entries = forces.node_entries().data();
  const double* x = grid.x();
  const vtkIdType* cells = grid.cells();
  const Vec3 xK(x[3 * K], x[3 * K + 1], x[3 * K + 2]);
  std::vector<vtkIdType> b_cells;  // those whose centroid lies on the + side
  for (vtkIdType k = start[K]; k < end[K]; ++k) {
    const vtkIdType e = entries[k] / 4;
    Vec3 centroid = Vec3::Zero();
    for (int j = 0; j < 4; ++j) centroid += Vec3(x + 3 * cells[4 * e + j]);
    if ((0.25 * centroid - xK).dot(c.normal) > 0.0) b_cells.push_back(e);
  }
  if (b_cells.empty() || b_cells.size() == static_cast<std::size_t>(end[K] - start[K]))
    return false;  // nothing to split
  split_cells(grid, elements, forces, K, std::move(b_cells), c.sigma1, r);
  return true;
}

std::vector<SplitRecord> Fracture::split_facets(Grid& grid, const ElementData& elements,
                                                ForceAssembler& forces,
                                                const std::vector<SplitCandidate>& candidates) {
  // Open the faces (both sides), then look at their corners on both sides: a corner may be
  // two daughters already, one in each cell.
  const vtkIdType* cells = grid.cells();
  std::vector<std::pair<vtkIdType, double>> touched;  // (corner, the ratio of its face)
  for (const SplitCandidate& c : candidates) {
    const vtkIdType f = c.face, g = facet_->twin(f);
    face_open_[f] = face_open_[g] = 1;
    face_traction_[f] = face_traction_[g] = c.sigma1 * facet_->strength(f);  // (ratio x strength)
    for (vtkIdType side : {f, g})
      for (int k = 0; k < 4; ++k)
        if (k != side % 4) touched.emplace_back(cells[side / 4 * 4 + k], c.sigma1);
  }
  std::sort(touched.begin(), touched.end(), [](const auto& a, const auto& b) {
    return std::tie(a.first, b.second) < std::tie(b.first, a.second);
  });  // by node, then the largest ratio first
  std::vector<SplitRecord> records;
  std::vector<int> group;
  for (std::size_t i = 0; i < touched.size(); ++i) {
    if (i > 0 && touched[i].first == touched[i - 1].first) continue;
    const vtkIdType K = touched[i].first;
    // grid.fixed() is read afresh: each split grows the grid's arrays, which may move them.
    if (grid.fixed()[K] || !may_break(grid, K)) continue;
    const int n = facet_->groups(forces, face_open_, K, group);
    if (n < 2) continue;
    std::vector<std::vector<vtkIdType>> of_group(n);
    const vtkIdType start = forces.node_start()[K];
    for (std::size_t k = 0; k < group.size(); ++k)
      of_group[group[k]].push_back(forces.node_entries()[start + k] / 4);
    for (int g = 1; g < n; ++g) {  // the first group keeps K (entries are in cell order)
      SplitRecord r;
      split_cells(grid, elements, forces, K, std::move(of_group[g]), touched[i].second, r);
      if (count_splits_) {
        const double* X = grid.X() + 3 * r.a;
        count_split(r.A_c, X[0], X[1]);
      }
      records.push_back(std::move(r));
    }
  }
  return records;
}

void Fracture::split_cells(Grid& grid, const ElementData& elements, ForceAssembler& forces,
                           vtkIdType K, std::vector<vtkIdType> b_cells, double sigma1,
                           SplitRecord& r) {
  const vtkIdType *start = forces.node_start().data(), *end = forces.node_end().data();
  const std::int32_t* entries = forces.node_entries().data();
  const vtkIdType* cells = grid.cells();
  struct Corner {
    vtkIdType cell;
    int corner;
    bool plus;
  };
  std::vector<Corner> around;
  for (vtkIdType k = start[K]; k < end[K]; ++k) {
    const vtkIdType e = entries[k] / 4;
    around.push_back({e, static_cast<int>(entries[k] % 4),
                      std::binary_search(b_cells.begin(), b_cells.end(), e)});
  }

  // Masses and element forces of the two daughters (2.3); m_a + m_b = m_K exactly.
  r.a = K;
  for (const Corner& k : around) {
    const Vec3 f = forces.corner_force(k.cell, k.corner);
    if (k.plus) {
      r.F_b += f;
    } else {
      r.F_a += f;
      if (elements.mass_scale.empty())  // as lump_masses does it
        r.m_a += 0.25 * rho0_ * elements.V0[k.cell];
      else
        r.m_a += 0.25 * rho0_ * elements.V0[k.cell] * elements.mass_scale[k.cell];
    }
  }
  r.m_b = grid.mass()[K] - r.m_a;

  // Faces through K whose two cells now take different daughters: new crack surface,
  // both faces counted, 1/3 of each face per node: 2 area / 3   (SPEC 5). A face is known
  // by the original nodes of its other two corners: one of them may have split already, so
  // that the two cells name different daughters of it.
  struct Face {
    vtkIdType p, q, cell;
    bool plus;
  };
  std::vector<Face> faces;
  for (const Corner& k : around) {
    vtkIdType o[3], n = 0;
    for (int j = 0; j < 4; ++j)
      if (j != k.corner) o[n++] = cells[4 * k.cell + j];
    for (auto [i, j] : {std::pair{0, 1}, {0, 2}, {1, 2}})
      faces.push_back({std::min(root_[o[i]], root_[o[j]]), std::max(root_[o[i]], root_[o[j]]),
                       k.cell, k.plus});
  }
  std::sort(faces.begin(), faces.end(),
            [](const Face& a, const Face& b) { return std::tie(a.p, a.q, a.cell) < std::tie(b.p, b.q, b.cell); });
  std::vector<CrackFace> crack;
  const double* X = grid.X();
  const Vec3 XK(X + 3 * K);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    const Face &f = faces[i], &g = faces[i + 1];
    if (f.p != g.p || f.q != g.q || f.plus == g.plus) continue;
    const double area = 0.5 * (Vec3(X + 3 * f.p) - XK).cross(Vec3(X + 3 * f.q) - XK).norm();
    // (reference positions of daughters equal their original's, so roots give the area)
    crack.push_back({f.plus ? g.cell : f.cell, f.plus ? f.cell : g.cell, 2.0 * area / 3.0});
  }

  r.b = grid.split_node(K, b_cells);  // appends B, rewires b_cells; views refreshed
  forces.split_node(grid, K, r.b, b_cells);  // node table and nodal sums of K and B
  note_split(K);
  grid.mass()[r.a] = r.m_a;
  grid.mass()[r.b] = r.m_b;

  // Granddaughters: every link K holds is cut in two (Appendix A).
  links_.cut_links_of(K, r.b, r.m_a, r.m_b, b_cells, grid.num_points());

  // f0 = (m_A F_B - m_B F_A) / (m_A + m_B)   (2.6)
  r.f0 = (r.m_a * r.F_b - r.m_b * r.F_a) / (r.m_a + r.m_b);
  CohesiveLink link = make_link(r.a, r.b, r.f0, std::move(crack), links_.law());
  if (traction_link_ && link.f0 > 0) {
    // Akantu's extrinsic insertion: the link starts at the traction its faces opened at,
    // f0 = sum of t_open A / 3 over the crack faces (a CrackFace's area is 2 A / 3, both
    // sides), in the direction of (2.6); delta_c (3.8) keeps the dissipation A_c gamma.
    double f0 = 0;
    for (const CrackFace& c : link.faces) {
      const vtkIdType f = facet_->face_between(c.cell_a, c.cell_b);
      f0 += (f >= 0 ? face_traction_[f] : sigma_c_) * 0.5 * c.area;
    }
    set_link_strength(link, f0, links_.law());
    r.f0 = f0 * link.e0;
  }
  r.A_c = link.A_c;
  r.sigma1 = sigma1;
  if (link.f0 > 0) links_.add(std::move(link), grid.num_points());
  r.b_cells = std::move(b_cells);
}

}  // namespace brittle
