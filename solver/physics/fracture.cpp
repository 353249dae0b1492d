// Node splitting (2.10)-(2.12), (6.7) and the nodal cohesive links it creates (2.6), (3.8), (A.1).
#include "fracture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <tuple>

#include "position_hash.hpp"

namespace brittle {

namespace {

/// An edge through the splitting node K of a 2D body, known by its other end's root.
struct CrackEdge {
  vtkIdType p, cell;
  bool plus;
};

/// The crack faces of a 2D split: each edge through K whose two triangles take different
/// daughters, length l x thickness t, counted for both faces and half of each per end: l t
/// (the tets' 2/3 of a face's area).
std::vector<CrackFace> crack_edges(std::vector<CrackEdge> edges, const double* X, const Vec3& XK,
                                   double thickness) {
  std::sort(edges.begin(), edges.end(), [](const CrackEdge& a, const CrackEdge& b) {
    return std::tie(a.p, a.cell) < std::tie(b.p, b.cell);
  });
  std::vector<CrackFace> crack;
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    const CrackEdge &f = edges[i], &g = edges[i + 1];
    if (f.p != g.p || f.plus == g.plus) continue;
    const double area = (Vec3(X + 3 * f.p) - XK).norm() * thickness;
    crack.push_back({f.plus ? g.cell : f.cell, f.plus ? f.cell : g.cell, area});
  }
  return crack;
}

}  // namespace

Fracture::Fracture(const Scene& scene, const Grid& grid, const ElementData& elements,
                   CohesiveLinks& links, const BodySizes& body)
    : region_(scene.fracture.region),
      sigma_c_(scene.material.sigma_c),
      rho0_(scene.material.rho0),
      weibull_m_(scene.material.weibull_modulus),
      weibull_scale_(weibull_m_ > 0 ? sigma_c_ / std::tgamma(1.0 + 1.0 / weibull_m_) : 0.0),
      strength_seed_(static_cast<std::uint64_t>(scene.material.strength_seed)),
      links_(links),
      tip_x_(std::numeric_limits<double>::quiet_NaN()),
      tip_y_(std::numeric_limits<double>::quiet_NaN()) {
  root_.resize(grid.num_points());
  for (vtkIdType p = 0; p < grid.num_points(); ++p) root_[p] = p;
  split_time_.assign(grid.num_points(), std::numeric_limits<double>::quiet_NaN());
  criterion_ = make_criterion(
      scene, CriterionContext{grid, elements, body, [this](const double X[3]) { return strength_at(X); },
                              [this, &grid](vtkIdType p) {
                                return !grid.fixed()[p] && may_break(grid, p);
                              }});
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

double Fracture::hot_threshold(const Grid& grid) {
  return criterion_ ? criterion_->hot_threshold(grid, root_)
                    : std::numeric_limits<double>::infinity();
}

bool Fracture::may_break(const Grid& grid, vtkIdType p) const {
  if (region_.empty()) return true;
  const double x = grid.X()[3 * p], y = grid.X()[3 * p + 1];
  return x >= region_[0] && x <= region_[1] && y >= region_[2] && y <= region_[3];
}

std::vector<SplitCandidate> Fracture::candidates(const Grid& grid, const ForceAssembler& forces) {
  if (!criterion_) return {};
  const std::function<bool(vtkIdType)> may = [&](vtkIdType p) {
    return !grid.fixed()[p] && may_break(grid, p);
  };
  return criterion_->candidates(grid, forces, CriterionInputs{root_, split_time_.data(), time_, may});
}

std::vector<SplitRecord> Fracture::split(Grid& grid, const ElementData& elements,
                                         ForceAssembler& forces,
                                         const std::vector<SplitCandidate>& candidates) {
  std::vector<SplitRecord> records;
  if (!criterion_) return records;
  // grid.fixed() is read afresh: each split grows the grid's arrays, which may move them.
  const std::function<bool(vtkIdType)> may = [&](vtkIdType p) {
    return !grid.fixed()[p] && may_break(grid, p);
  };
  const SplitCells make = [&](vtkIdType K, std::vector<vtkIdType> b_cells, double sigma1) {
    SplitRecord r;
    split_cells(grid, elements, forces, K, std::move(b_cells), sigma1, r);
    if (count_splits_) {
      const double* X = grid.X() + 3 * r.a;
      count_split(r.A_c, X[0], X[1]);
    }
    records.push_back(std::move(r));
  };
  criterion_->split(grid, forces, candidates,
                    CriterionInputs{root_, split_time_.data(), time_, may}, make);
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
  if (elements.corners == 3) {  // a 2D body's triangles: a third each, as lump_masses
    r.m_a = 0;
    for (const Corner& k : around)
      if (!k.plus) r.m_a += rho0_ * elements.V0[k.cell] / 3.0;
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
    if (grid.corners() == 3) break;  // (a 2D body's edges: crack_edges below)
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
  if (grid.corners() == 3) {
    std::vector<CrackEdge> edges;
    for (const Corner& k : around)
      for (int j = 0; j < 3; ++j)
        if (j != k.corner) edges.push_back({root_[cells[3 * k.cell + j]], k.cell, k.plus});
    crack = crack_edges(std::move(edges), X, XK, elements.thickness);
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
  // A criterion may start the link at another force in the direction of (2.6) (the facet
  // criteria: the traction its faces opened at, Akantu's extrinsic insertion); delta_c (3.8)
  // keeps the dissipation A_c gamma.
  if (const double f0 = criterion_->link_force(link.faces); !std::isnan(f0) && link.f0 > 0) {
    set_link_strength(link, f0, links_.law());
    r.f0 = f0 * link.e0;
  }
  r.A_c = link.A_c;
  r.sigma1 = sigma1;
  if (link.f0 > 0) links_.add(std::move(link), grid.num_points());
  r.b_cells = std::move(b_cells);
}

}  // namespace brittle
