// Boundary conditions, external loads and the initial state (SPEC 3; docs/model.md,
// "Boundary conditions and loads").
#include "boundary.hpp"

#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "error.hpp"

namespace brittle {

double TimeHistory::at(double t) const {
  switch (kind) {
    case Kind::constant:
      return t >= start ? 1.0 : 0.0;
    case Kind::ramp:
      if (t <= start) return 0.0;
      return ramp_time > 0 && t < start + ramp_time ? (t - start) / ramp_time : 1.0;
    case Kind::table: {
      const std::size_t n = table.size() / 2;
      if (n == 0) return 0.0;
      if (t <= table[0]) return table[1];
      for (std::size_t i = 1; i < n; ++i)
        if (t <= table[2 * i]) {
          const double t0 = table[2 * i - 2], t1 = table[2 * i];
          const double f0 = table[2 * i - 1], f1 = table[2 * i + 1];
          return f0 + (f1 - f0) * (t - t0) / (t1 - t0);
        }
      return table[2 * n - 1];
    }
  }
  return 0.0;
}

std::string group_array_name(const std::string& group) {
  return "group:" + group;
}

namespace {

std::string describe(const RegionParams& r) {
  if (!r.group.empty()) return "physical group '" + r.group + "'";
  std::string s = "box";
  for (std::size_t i = 0; i < r.box.size(); ++i) s += error_message(i ? ", " : " ", r.box[i]);
  return s;
}

/// In-region flag per node of the mesh.
std::vector<std::uint8_t> region_mask(const RegionParams& region, vtkUnstructuredGrid& mesh,
                                      const std::string& where) {
  const vtkIdType np = mesh.GetNumberOfPoints();
  std::vector<std::uint8_t> in(np, 0);
  if (!region.group.empty()) {
    vtkDataArray* a = mesh.GetPointData()->GetArray(group_array_name(region.group).c_str());
    if (a == nullptr) {
      std::string known;
      for (int i = 0; i < mesh.GetPointData()->GetNumberOfArrays(); ++i) {
        const char* name = mesh.GetPointData()->GetArrayName(i);
        if (name && std::string(name).rfind("group:", 0) == 0)
          known += (known.empty() ? "" : ", ") + std::string(name + 6);
      }
      throw Error(error_message(where, ": the mesh has no physical group '", region.group,
                                "' (it has: ", known.empty() ? "none" : known, ")"));
    }
    for (vtkIdType p = 0; p < np; ++p) in[p] = a->GetTuple1(p) != 0 ? 1 : 0;
    return in;
  }
  BRITTLE_CHECK(region.box.size() == 6, where, ": a region needs a box or a group");
  // A rank's part of a decomposed run carries the whole mesh's bounds (extract_part): the same
  // tolerance, so the same nodes, as the serial run.
  double b[6];
  mesh.GetBounds(b);
  if (vtkDataArray* whole = mesh.GetFieldData()->GetArray(kWholeBounds))
    for (int i = 0; i < 6; ++i) b[i] = whole->GetComponent(0, i);
  const double tol =
      1e-6 * std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                       (b[5] - b[4]) * (b[5] - b[4]));
  for (vtkIdType p = 0; p < np; ++p) {
    double X[3];
    mesh.GetPoint(p, X);
    bool inside = true;
    for (int d = 0; d < 3; ++d)
      inside = inside && X[d] >= region.box[2 * d] - tol && X[d] <= region.box[2 * d + 1] + tol;
    in[p] = inside ? 1 : 0;
  }
  return in;
}

using Face = std::array<vtkIdType, 3>;

/// A rank's part of a decomposed run (extract_part marks it with the whole mesh's bounds): a
/// region may miss it, and only the whole grid's selection must not be empty
/// (Boundary::selections, checked over the ranks by Simulation::decompose).
bool is_part(vtkUnstructuredGrid& mesh) {
  return mesh.GetFieldData()->GetArray(kWholeBounds) != nullptr;
}

}  // namespace

std::vector<vtkIdType> select_nodes(const RegionParams& region, vtkUnstructuredGrid& mesh,
                                    const std::string& where, bool allow_empty) {
  const std::vector<std::uint8_t> in = region_mask(region, mesh, where);
  std::vector<vtkIdType> nodes;
  for (vtkIdType p = 0; p < static_cast<vtkIdType>(in.size()); ++p)
    if (in[p]) nodes.push_back(p);
  BRITTLE_CHECK(allow_empty || is_part(mesh) || !nodes.empty(), where, ": the region (",
                describe(region), ") selects no node of the mesh");
  return nodes;
}

namespace {

/// The boundary's selection checked: no interior face (or edge, `kind`), and some unless the
/// mesh is a rank's part (the whole grid's is checked over the ranks).
void check_selection(long interior, bool empty, vtkUnstructuredGrid& mesh, const std::string& where,
                     const RegionParams& region, const char* kind, const char* hint) {
  BRITTLE_CHECK(interior == 0, where, ": the region (", describe(region), ") holds ", interior,
                " interior ", kind, "(s); a traction acts on boundary ", kind, "s only (use ",
                hint, ")");
  BRITTLE_CHECK(!empty || is_part(mesh), where, ": the region (", describe(region),
                ") holds no boundary ", kind, " of the mesh");
}

/// A 2D body's boundary edges in the region: edges of one triangle only, the triangle's third
/// corner giving the outward side.
std::vector<BoundaryFace> boundary_edges(const std::vector<std::uint8_t>& in,
                                         vtkUnstructuredGrid& mesh, double thickness,
                                         long& interior) {
  struct Seen {
    int count = 0;
    vtkIdType a = -1, b = -1, opposite = -1;
  };
  std::map<std::pair<vtkIdType, vtkIdType>, Seen> edges;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < mesh.GetNumberOfCells(); ++c) {
    if (mesh.GetCellType(c) != VTK_TRIANGLE) continue;
    mesh.GetCellPoints(c, ids);
    for (int k = 0; k < 3; ++k) {
      const vtkIdType a = ids->GetId(k), b = ids->GetId((k + 1) % 3);
      if (!in[a] || !in[b]) continue;
      Seen& s = edges[{std::min(a, b), std::max(a, b)}];
      if (s.count++ == 0) s.a = a, s.b = b, s.opposite = ids->GetId((k + 2) % 3);
    }
  }
  std::vector<BoundaryFace> out;
  for (const auto& [key, s] : edges) {
    if (s.count > 1) {
      ++interior;
      continue;
    }
    BoundaryFace bf;
    bf.corners = 2;
    bf.node[0] = s.a, bf.node[1] = s.b;
    double p[3][3];
    mesh.GetPoint(s.a, p[0]), mesh.GetPoint(s.b, p[1]), mesh.GetPoint(s.opposite, p[2]);
    Vec3 n(p[1][1] - p[0][1], p[0][0] - p[1][0], 0.0);
    bf.area = n.norm() * thickness;
    n.normalize();
    if (n.dot(Vec3(p[2]) - Vec3(p[0])) > 0) n = -n;
    for (int d = 0; d < 3; ++d) bf.normal[d] = n[d];
    out.push_back(bf);
  }
  return out;
}

}  // namespace

std::vector<BoundaryFace> select_boundary_faces(const RegionParams& region,
                                                vtkUnstructuredGrid& mesh,
                                                const std::string& where, double thickness) {
  const std::vector<std::uint8_t> in = region_mask(region, mesh, where);
  if (thickness > 0) {
    long interior = 0;
    std::vector<BoundaryFace> out = boundary_edges(in, mesh, thickness, interior);
    check_selection(interior, out.empty(), mesh, where, region, "edge",
                    "a thin box around the edge");
    return out;
  }
  // Faces with all three nodes in the region, counted over the tets that have them: once =
  // on the surface, twice = interior. The fourth node of the tet gives the outward side.
  struct Seen {
    int count = 0;
    Face nodes;  // in the tet's order
    vtkIdType opposite;
  };
  std::map<Face, Seen> faces;
  vtkNew<vtkIdList> ids;
  static constexpr int kFace[4][4] = {{1, 2, 3, 0}, {0, 3, 2, 1}, {0, 1, 3, 2}, {0, 2, 1, 3}};
  for (vtkIdType c = 0; c < mesh.GetNumberOfCells(); ++c) {
    if (mesh.GetCellType(c) != VTK_TETRA) continue;
    mesh.GetCellPoints(c, ids);
    for (const auto& f : kFace) {
      const Face nodes = {ids->GetId(f[0]), ids->GetId(f[1]), ids->GetId(f[2])};
      if (!in[nodes[0]] || !in[nodes[1]] || !in[nodes[2]]) continue;
      Face key = nodes;
      std::sort(key.begin(), key.end());
      Seen& s = faces[key];
      if (s.count++ == 0) s.nodes = nodes, s.opposite = ids->GetId(f[3]);
    }
  }
  std::vector<BoundaryFace> out;
  long interior = 0;
  for (const auto& [key, s] : faces) {
    if (s.count > 1) {
      ++interior;
      continue;
    }
    BoundaryFace bf;
    double p[4][3];
    for (int j = 0; j < 3; ++j) bf.node[j] = s.nodes[j], mesh.GetPoint(s.nodes[j], p[j]);
    mesh.GetPoint(s.opposite, p[3]);
    const Vec3 a = Vec3(p[1]) - Vec3(p[0]), b = Vec3(p[2]) - Vec3(p[0]);
    Vec3 n = a.cross(b);
    bf.area = 0.5 * n.norm();
    n.normalize();
    if (n.dot(Vec3(p[3]) - Vec3(p[0])) > 0) n = -n;
    for (int d = 0; d < 3; ++d) bf.normal[d] = n[d];
    out.push_back(bf);
  }
  check_selection(interior, out.empty(), mesh, where, region, "face",
                  "a thin box around the surface or a surface group");
  return out;
}

void apply_initial_state(const Scene& scene, double sigma, const ElasticConstants& c, Grid& grid,
                         vtkUnstructuredGrid& mesh) {
  double* x = grid.x();
  const double* X = grid.X();
  if (scene.initial.state == InitialParams::State::prestress) {
    // Uniaxial stress sigma along y: x = (b X, lambda Y, b Z)   (B.6)
    const UniaxialStretch s = uniaxial_prestress(sigma, c.K, c.mu);
    for (vtkIdType i = 0; i < grid.num_points(); ++i) {
      x[3 * i] = s.b * X[3 * i];
      x[3 * i + 1] = s.lambda * X[3 * i + 1];
      x[3 * i + 2] = s.b * X[3 * i + 2];
    }
  }
  double* v = grid.v();
  for (const InitialVelocityParams& iv : scene.initial.velocities)
    for (vtkIdType p : select_nodes(iv.region, mesh, "[initial." + iv.name + "]"))
      for (int d = 0; d < 3; ++d) v[3 * p + d] = iv.velocity[d];
}

std::vector<RegionSelection> region_selections(const Scene& scene, vtkUnstructuredGrid& mesh,
                                               const Boundary& boundary) {
  std::vector<RegionSelection> out = boundary.selections();
  for (const InitialVelocityParams& iv : scene.initial.velocities) {
    const std::string where = "[initial." + iv.name + "]";
    out.push_back({static_cast<long>(select_nodes(iv.region, mesh, where).size()),
                   where + ": the region (" + describe(iv.region) + ") selects no node of the mesh"});
  }
  return out;
}

Boundary::Boundary(const Scene& scene, Grid& grid, vtkUnstructuredGrid& mesh)
    : params_(scene.boundaries) {
  // A 2D body's tractions act on its boundary edges, prisms of its thickness.
  const double thickness_2d =
      grid.corners() == 3 ? (scene.mesh.thickness > 0 ? scene.mesh.thickness : scene.geometry.T)
                          : 0.0;
  const bool paper_plate =
      params_.empty() && scene.initial.state == InitialParams::State::prestress;
  if (paper_plate) {
    // The paper's plate: the lateral edges y = +-H/2 held at their pre-stressed positions
    // (an imported mesh without nodes there is left free, as before the boundary sections).
    const double inf = std::numeric_limits<double>::infinity(), h2 = 0.5 * scene.geometry.H;
    for (double y : {h2, -h2}) {
      BoundaryParams b;
      b.name = y > 0 ? "top (paper)" : "bottom (paper)";
      b.region.box = {-inf, inf, y, y, -inf, inf};
      params_.push_back(b);
    }
  }
  const vtkIdType np = grid.num_points();
  // Per node component: the last boundary that constrains it wins.
  std::vector<int> owner(3 * np, -1);
  std::vector<std::vector<std::pair<std::size_t, Vec3>>> load(np);
  std::uint8_t* fixed = grid.fixed();
  for (std::size_t b = 0; b < params_.size(); ++b) {
    const BoundaryParams& p = params_[b];
    const std::string where = "[boundary." + p.name + "]";
    if (p.type == BoundaryParams::Type::traction) {
      const std::vector<BoundaryFace> faces =
          select_boundary_faces(p.region, mesh, where, thickness_2d);
      double area = 0;
      for (const BoundaryFace& f : faces) {
        area += f.area;
        for (int k = 0; k < f.corners; ++k) {
          const vtkIdType n = f.node[k];
          auto& entries = load[n];
          if (entries.empty() || entries.back().first != b) entries.push_back({b, Vec3::Zero()});
          // int t N_i dA = t A / 3 (a triangle), t A / 2 (a 2D body's edge)
          entries.back().second += Vec3(p.value) * (f.area / (f.corners == 3 ? 3.0 : 2.0));
          fixed[n] |= constraint::no_split;
        }
      }
      selections_.push_back({static_cast<long>(faces.size()),
                             error_message(where, ": the region (", describe(p.region),
                                           ") holds no boundary face of the mesh")});
      description_.push_back(error_message(where, " traction ", p.value[0], ", ", p.value[1], ", ",
                                           p.value[2], " Pa on ", faces.size(), " faces, area ",
                                           area, " m^2"));
    } else {
      const std::vector<vtkIdType> nodes = select_nodes(p.region, mesh, where, paper_plate);
      if (!paper_plate)
        selections_.push_back({static_cast<long>(nodes.size()),
                               error_message(where, ": the region (", describe(p.region),
                                             ") selects no node of the mesh")});
      for (vtkIdType n : nodes) {
        for (int d = 0; d < 3; ++d)
          if (p.components[d]) owner[3 * n + d] = static_cast<int>(b);
        fixed[n] |= constraint::no_split;
      }
      description_.push_back(
          error_message(where, p.type == BoundaryParams::Type::fixed ? " fixed " : " velocity ",
                        p.components[0] ? "x" : "", p.components[1] ? "y" : "",
                        p.components[2] ? "z" : "", " on ", nodes.size(), " nodes"));
    }
  }
  for (vtkIdType n = 0; n < np; ++n) {
    Constrained c{n, 0, {}};
    for (int d = 0; d < 3; ++d)
      if (owner[3 * n + d] >= 0) {
        c.mask |= static_cast<std::uint8_t>(1 << d);
        c.boundary[d] = static_cast<std::size_t>(owner[3 * n + d]);
      }
    if (c.mask) constraints_.push_back(c);
    fixed[n] |= c.mask;
    for (const auto& [b, f] : load[n]) loads_.push_back({n, {f[0], f[1], f[2]}, b});
  }
}

void Boundary::keep_nodes(const std::vector<char>& owned) {
  std::erase_if(constraints_, [&](const Constrained& c) { return !owned[c.node]; });
  std::erase_if(loads_, [&](const Loaded& l) { return !owned[l.node]; });
}

void Boundary::impose_velocities(Grid& grid, double t) const {
  double* v = grid.v();
  for (const Constrained& c : constraints_)
    for (int d = 0; d < 3; ++d)
      if (c.mask & (1 << d)) {
        const BoundaryParams& p = params_[c.boundary[d]];
        v[3 * c.node + d] =
            p.type == BoundaryParams::Type::velocity ? p.value[d] * p.history.at(t) : 0.0;
      }
}

void Boundary::after_kick(Grid& grid, const double* force, double tau, double t_force,
                          double t_velocity) {
  double* v = grid.v();
  const double* m = grid.mass();
  const std::uint8_t* fixed = grid.fixed();
  // Tractions: loads_ is in node order, so one node's entries are adjacent.
  for (std::size_t i = 0; i < loads_.size();) {
    const vtkIdType n = loads_[i].node;
    std::size_t end = i;
    Vec3 impulse = Vec3::Zero();
    for (; end < loads_.size() && loads_[end].node == n; ++end)
      impulse += tau * params_[loads_[end].boundary].history.at(t_force) * Vec3(loads_[end].f);
    for (int d = 0; d < 3; ++d) {
      if (fixed[n] & (1 << d)) continue;  // a constrained component takes no traction
      const double after_elements = v[3 * n + d];
      const double before = after_elements - tau * force[3 * n + d] / m[n];
      const double after = after_elements + impulse[d] / m[n];
      v[3 * n + d] = after;
      traction_work_ += impulse[d] * 0.5 * (before + after);
    }
    i = end;
  }
  // Constraints: the reaction is whatever impulse brings the component to its velocity.
  for (const Constrained& c : constraints_)
    for (int d = 0; d < 3; ++d)
      if (c.mask & (1 << d)) {
        const BoundaryParams& p = params_[c.boundary[d]];
        const double target =
            p.type == BoundaryParams::Type::velocity ? p.value[d] * p.history.at(t_velocity) : 0.0;
        double& vd = v[3 * c.node + d];
        const double impulse = m[c.node] * (target - vd) - tau * force[3 * c.node + d];
        reaction_work_ += impulse * 0.5 * (vd + target);
        vd = target;
      }
}

}  // namespace brittle
