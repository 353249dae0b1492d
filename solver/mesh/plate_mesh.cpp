// Meshes of SPEC 1: the notched plate and a bar generated with Gmsh's C++ API and import of
// .msh / .vtu tetrahedral meshes; the numbering every mesh then gets is in numbering.cpp.
#include "plate_mesh.hpp"

#include <gmsh.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "boundary.hpp"
#include "error.hpp"
#include "isolated_read.hpp"

namespace brittle {
namespace {

using Tet = std::array<vtkIdType, 4>;

constexpr int kGmshTet4 = 4;  // Gmsh element type of the linear tetrahedron

// ---------------------------------------------------------------------------------------------
// Gmsh session

std::mutex gmsh_mutex;

/// Gmsh is one global state per process: one quiet session per call, serialised, and
/// finalised on exit so that the next call starts clean. Errors throw (AbortOnError = 2,
/// the API default) instead of printing or exiting.
class GmshSession {
 public:
  explicit GmshSession(const char* model) : lock_(gmsh_mutex) {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 0);
    gmsh::option::setNumber("General.AbortOnError", 2);
    gmsh::model::add(model);
  }
  ~GmshSession() { gmsh::finalize(); }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
};

/// Gmsh's own message for the last error (call it inside the session).
std::string gmsh_last_error() {
  try {
    std::string e;
    gmsh::logger::getLastError(e);
    return e;
  } catch (...) {
    return {};
  }
}

// ---------------------------------------------------------------------------------------------
// Tetrahedra

double signed_volume(const double* x0, const double* x1, const double* x2, const double* x3) {
  const double a[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]};
  const double b[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]};
  const double c[3] = {x3[0] - x0[0], x3[1] - x0[1], x3[2] - x0[2]};
  return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6.0;
}

double mean_edge_length(const std::array<const double*, 4>& x) {
  double sum = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      sum += std::sqrt((x[i][0] - x[j][0]) * (x[i][0] - x[j][0]) +
                       (x[i][1] - x[j][1]) * (x[i][1] - x[j][1]) +
                       (x[i][2] - x[j][2]) * (x[i][2] - x[j][2]));
  return sum / 6.0;
}

/// Tets as read or generated: points (xyz triples) and 4 point indices per tet, with the
/// index of each tet in its source (for messages).
struct TetSoup {
  std::vector<double> xyz;
  std::vector<Tet> tets;
  std::vector<long long> source_ids;
  /// Named physical groups of a .msh file: name and, per point of xyz, 1 if in the group.
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> groups;
};

/// Swaps two nodes of every inverted tet; throws for a zero-volume one (|V0| <= 1e-12 l^3,
/// l the tet's mean edge length), naming `where` and the tet's index in its source.
void orient_tets(TetSoup& soup, const std::string& where) {
  for (std::size_t e = 0; e < soup.tets.size(); ++e) {
    Tet& t = soup.tets[e];
    const std::array<const double*, 4> x = {&soup.xyz[3 * t[0]], &soup.xyz[3 * t[1]],
                                            &soup.xyz[3 * t[2]], &soup.xyz[3 * t[3]]};
    const double v = signed_volume(x[0], x[1], x[2], x[3]);
    const double l = mean_edge_length(x);
    BRITTLE_CHECK(std::abs(v) > 1e-12 * l * l * l, where, ": tetrahedron ", soup.source_ids[e],
                  " has zero volume");
    if (v < 0.0) std::swap(t[2], t[3]);
  }
}

/// Builds the grid from the used points only (first-use order), then renumbers it.
vtkSmartPointer<vtkUnstructuredGrid> make_grid(const TetSoup& soup) {
  const vtkIdType n_in = static_cast<vtkIdType>(soup.xyz.size() / 3);
  std::vector<vtkIdType> new_id(n_in, -1);
  vtkIdType n_used = 0;
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfValues(4 * static_cast<vtkIdType>(soup.tets.size()));
  vtkIdType k = 0;
  for (const Tet& t : soup.tets)
    for (vtkIdType p : t) {
      if (new_id[p] < 0) new_id[p] = n_used++;
      connectivity->SetValue(k++, new_id[p]);
    }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n_used);
  for (vtkIdType p = 0; p < n_in; ++p)
    if (new_id[p] >= 0) points->SetPoint(new_id[p], &soup.xyz[3 * p]);

  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(soup.tets.size()) + 1);
  std::vector<vtkSmartPointer<vtkUnsignedCharArray>> groups;
  for (const auto& [name, in] : soup.groups) {  // point data, so renumbering carries them along
    auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
    a->SetName(group_array_name(name).c_str());
    a->SetNumberOfTuples(n_used);
    a->Fill(0);
    for (vtkIdType p = 0; p < n_in; ++p)
      if (new_id[p] >= 0 && in[p]) a->SetValue(new_id[p], 1);
    groups.push_back(a);
  }
  for (vtkIdType c = 0; c < offsets->GetNumberOfValues(); ++c) offsets->SetValue(c, 4 * c);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(VTK_TETRA, cells);
  for (const auto& a : groups) grid->GetPointData()->AddArray(a);
  renumber_for_locality(*grid);
  return grid;
}

/// All nodes and linear tets of the current Gmsh model; node tags mapped to indices.
TetSoup gmsh_tets() {
  TetSoup soup;
  std::vector<std::size_t> node_tags;
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(node_tags, soup.xyz, parametric, -1, -1, false, false);
  std::unordered_map<std::size_t, vtkIdType> index;
  index.reserve(node_tags.size());
  for (std::size_t i = 0; i < node_tags.size(); ++i)
    index.emplace(node_tags[i], static_cast<vtkIdType>(i));

  std::vector<std::size_t> element_tags, element_nodes;
  gmsh::model::mesh::getElementsByType(kGmshTet4, element_tags, element_nodes);
  soup.tets.resize(element_tags.size());
  soup.source_ids.assign(element_tags.begin(), element_tags.end());
  for (std::size_t e = 0; e < element_tags.size(); ++e)
    for (int j = 0; j < 4; ++j) {
      const auto it = index.find(element_nodes[4 * e + j]);
      if (it == index.end()) throw Error("Gmsh mesh: tetrahedron refers to an unknown node");
      soup.tets[e][j] = it->second;
    }
  return soup;
}

/// Extrudes the model's surfaces by `thickness` along z in `layers` layers of tets
/// (built-in kernel, prisms split into tets) and meshes it.
void extrude_and_mesh(double thickness, int layers) {
  gmsh::vectorpair surfaces, extruded;
  gmsh::model::geo::synchronize();
  gmsh::model::getEntities(surfaces, 2);
  gmsh::model::geo::extrude(surfaces, 0, 0, thickness, extruded, {layers}, {}, false);
  gmsh::model::geo::synchronize();
  gmsh::model::mesh::generate(3);
}

/// The linear triangles of the current Gmsh model (a 2D body, mesh.dimension = 2), turned
/// counter-clockwise in the x-y plane (z = 0), on the used points in first-use order, renumbered
/// for locality.
vtkSmartPointer<vtkUnstructuredGrid> gmsh_triangles(const char* what) {
  constexpr int kGmshTri3 = 2;  // Gmsh element type of the linear triangle
  std::vector<std::size_t> node_tags;
  std::vector<double> xyz, parametric;
  gmsh::model::mesh::getNodes(node_tags, xyz, parametric, -1, -1, false, false);
  std::unordered_map<std::size_t, vtkIdType> index;
  for (std::size_t i = 0; i < node_tags.size(); ++i)
    index.emplace(node_tags[i], static_cast<vtkIdType>(i));
  std::vector<std::size_t> element_tags, element_nodes;
  gmsh::model::mesh::getElementsByType(kGmshTri3, element_tags, element_nodes);
  BRITTLE_CHECK(!element_tags.empty(), what, ": Gmsh produced no triangles");
  std::vector<vtkIdType> new_id(node_tags.size(), -1);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> cells;
  for (std::size_t e = 0; e < element_tags.size(); ++e) {
    vtkIdType t[3];
    for (int j = 0; j < 3; ++j) {
      const auto it = index.find(element_nodes[3 * e + j]);
      if (it == index.end()) throw Error("Gmsh mesh: triangle refers to an unknown node");
      t[j] = it->second;
    }
    const double* a = &xyz[3 * t[0]];
    const double* b = &xyz[3 * t[1]];
    const double* c = &xyz[3 * t[2]];
    const double area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    const double l2 = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
    BRITTLE_CHECK(std::abs(area2) > 1e-12 * l2, what, ": triangle ", element_tags[e],
                  " has zero area");
    if (area2 < 0) std::swap(t[1], t[2]);
    for (vtkIdType& p : t) {
      if (new_id[p] < 0) {
        new_id[p] = points->GetNumberOfPoints();
        points->InsertNextPoint(xyz[3 * p], xyz[3 * p + 1], 0.0);
      }
      p = new_id[p];
    }
    cells->InsertNextCell(3, t);
  }
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(VTK_TRIANGLE, cells);
  renumber_for_locality(*grid);
  return grid;
}

/// Runs `build` (which meshes in 2D) inside a Gmsh session: the triangles, Gmsh's failures as
/// brittle::Error.
template <class Build>
vtkSmartPointer<vtkUnstructuredGrid> with_gmsh_2d(const char* what, Build build) {
  GmshSession session(what);
  try {
    build();
    return gmsh_triangles(what);
  } catch (const Error&) {
    throw;
  } catch (...) {
    throw Error(error_message(what, ": Gmsh failed (", gmsh_last_error(), ")"));
  }
}

/// Runs `build` inside a Gmsh session and turns any Gmsh failure into brittle::Error.
template <class Build>
vtkSmartPointer<vtkUnstructuredGrid> with_gmsh(const char* what, Build build) {
  TetSoup soup;
  {
    GmshSession session(what);
    try {
      build();
      soup = gmsh_tets();
    } catch (const Error&) {
      throw;
    } catch (...) {  // Gmsh 4.8 throws the message as std::string
      throw Error(error_message(what, ": Gmsh failed (", gmsh_last_error(), ")"));
    }
  }
  BRITTLE_CHECK(!soup.tets.empty(), what, ": Gmsh produced no tetrahedra");
  orient_tets(soup, what);
  return make_grid(soup);
}

// ---------------------------------------------------------------------------------------------
// Import

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

TetSoup read_msh(const std::string& path) {
  GmshSession session("import");
  try {
    gmsh::open(path);
    TetSoup soup = gmsh_tets();
    // Named physical groups (any dimension) as node masks, for [boundary.NAME] group = ...
    std::unordered_map<std::size_t, vtkIdType> index;
    {
      std::vector<std::size_t> tags;
      std::vector<double> xyz, parametric;
      gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, false, false);
      for (std::size_t i = 0; i < tags.size(); ++i)
        index.emplace(tags[i], static_cast<vtkIdType>(i));
    }
    gmsh::vectorpair physical;
    gmsh::model::getPhysicalGroups(physical);
    for (const auto& [dim, tag] : physical) {
      std::string name;
      gmsh::model::getPhysicalName(dim, tag, name);
      if (name.empty()) continue;
      std::vector<std::size_t> tags;
      std::vector<double> coordinates;
      gmsh::model::mesh::getNodesForPhysicalGroup(dim, tag, tags, coordinates);
      auto it = std::find_if(soup.groups.begin(), soup.groups.end(),
                             [&](const auto& g) { return g.first == name; });
      if (it == soup.groups.end())
        it = soup.groups.insert(soup.groups.end(),
                                {name, std::vector<std::uint8_t>(soup.xyz.size() / 3, 0)});
      for (std::size_t t : tags)
        if (auto n = index.find(t); n != index.end()) it->second[n->second] = 1;
    }
    return soup;
  } catch (...) {  // keep Gmsh's reason, on one line
    std::string reason = gmsh_last_error();
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    throw std::runtime_error("Gmsh: " + reason);
  }
}

TetSoup read_vtu(const std::string& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkNew<VtkErrorFlag> catcher;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  reader->AddObserver(vtkCommand::WarningEvent, catcher);
  if (!reader->CanReadFile(path.c_str()))
    throw std::runtime_error("not a VTK XML unstructured grid");
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* in = reader->GetOutput();
  if (catcher->failed || in == nullptr || in->GetPoints() == nullptr)
    throw std::runtime_error("VTK reader failed");

  TetSoup soup;
  const vtkIdType n_points = in->GetNumberOfPoints();
  soup.xyz.resize(3 * n_points);
  for (vtkIdType p = 0; p < n_points; ++p) in->GetPoint(p, &soup.xyz[3 * p]);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < in->GetNumberOfCells(); ++c) {
    if (in->GetCellType(c) != VTK_TETRA) continue;
    in->GetCellPoints(c, ids);
    Tet t;
    for (int j = 0; j < 4; ++j) {
      t[j] = ids->GetId(j);
      if (t[j] < 0 || t[j] >= n_points) throw std::runtime_error("bad point index");
    }
    soup.tets.push_back(t);
    soup.source_ids.push_back(c);
  }
  return soup;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

namespace {

/// The size field of the plate: band_size inside |y| < band, growing to size over a
/// transition of width `band` (Gmsh Box field as background mesh); and mesh.algorithm (set
/// every time: Gmsh keeps options from one mesh of the process to the next).
void set_size_and_algorithm(const GeometryParams& g, const MeshParams& m) {
  using A = MeshParams::Algorithm;
  gmsh::option::setNumber("Mesh.Algorithm", m.algorithm == A::delaunay    ? 5
                                            : m.algorithm == A::meshadapt ? 1
                                                                          : 6);
  const double inner = m.band > 0 && m.band_size > 0 ? m.band_size : m.size;
  const int box = gmsh::model::mesh::field::add("Box");
  gmsh::model::mesh::field::setNumber(box, "VIn", inner);
  gmsh::model::mesh::field::setNumber(box, "VOut", m.size);
  gmsh::model::mesh::field::setNumber(box, "XMin", -g.L);
  gmsh::model::mesh::field::setNumber(box, "XMax", 2 * g.L);
  gmsh::model::mesh::field::setNumber(box, "YMin", -m.band);
  gmsh::model::mesh::field::setNumber(box, "YMax", m.band);
  gmsh::model::mesh::field::setNumber(box, "ZMin", -g.T);
  gmsh::model::mesh::field::setNumber(box, "ZMax", 2 * g.T);
  gmsh::model::mesh::field::setNumber(box, "Thickness", m.band);
  gmsh::model::mesh::field::setAsBackgroundMesh(box);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
}

/// The plate with [notch.NAME] cuts (OpenCASCADE kernel): the rectangle minus one polygon per
/// notch, extruded through the thickness in `layers` layers of tets. A notch whose mouth lies
/// on the outline is extended outwards by its opening so that the cut crosses the edge cleanly.
void build_notched_plate(const GeometryParams& g, const MeshParams& m) {
  namespace occ = gmsh::model::occ;
  const double h2 = g.H / 2, tol = 1e-9 * std::hypot(g.L, g.H);
  const int plate = occ::addRectangle(0, -h2, 0, g.L, g.H);
  gmsh::vectorpair tools;
  for (const NotchParams& n : g.notches) {
    const std::string where = "[notch." + n.name + "]";
    const double dx = n.direction[0], dy = n.direction[1], px = -dy, py = dx;  // px, py: normal
    const double sx = n.start[0], sy = n.start[1];
    const double tx = sx + n.length * dx, ty = sy + n.length * dy;
    const auto inside = [&](double x, double y, double margin) {
      return x > margin && x < g.L - margin && y > -h2 + margin && y < h2 - margin;
    };
    BRITTLE_CHECK(sx >= -tol && sx <= g.L + tol && sy >= -h2 - tol && sy <= h2 + tol, where,
                  ": start (", sx, ", ", sy, ") is outside the plate [0, ", g.L, "] x [", -h2, ", ",
                  h2, "]");
    BRITTLE_CHECK(inside(tx, ty, 0.0), where, ": the tip (", tx, ", ", ty,
                  ") is not inside the plate (expected start + length * direction inside)");
    BRITTLE_CHECK(n.opening < std::min(g.L, g.H), where, ": opening ", n.opening,
                  " is not smaller than the plate");
    const bool on_edge = !inside(sx, sy, tol);
    const double back = on_edge ? n.opening : 0.0;  // outward extension of the mouth
    const double o2 = n.opening / 2;
    std::vector<std::array<double, 2>> polygon = {
        {sx - back * dx + o2 * px, sy - back * dy + o2 * py}, {sx + o2 * px, sy + o2 * py}};
    if (n.shape == NotchParams::Shape::wedge) {
      polygon.push_back({tx, ty});
    } else {
      polygon.push_back({tx + o2 * px, ty + o2 * py});
      polygon.push_back({tx - o2 * px, ty - o2 * py});
    }
    polygon.push_back({sx - o2 * px, sy - o2 * py});
    polygon.push_back({sx - back * dx - o2 * px, sy - back * dy - o2 * py});
    if (!on_edge) polygon.erase(polygon.begin()), polygon.pop_back();  // interior: no extension
    std::vector<int> points, lines;
    for (const auto& p : polygon) points.push_back(occ::addPoint(p[0], p[1], 0));
    for (std::size_t i = 0; i < points.size(); ++i)
      lines.push_back(occ::addLine(points[i], points[(i + 1) % points.size()]));
    tools.push_back({2, occ::addPlaneSurface({occ::addCurveLoop(lines)})});
  }
  gmsh::vectorpair cut, extruded;
  std::vector<gmsh::vectorpair> map;
  occ::cut({{2, plate}}, tools, cut, map);
  BRITTLE_CHECK(cut.size() == 1, "plate with notches: the notches cut the plate into ", cut.size(),
                " pieces (expected one body)");
  if (m.dimension == 2) {  // the cut plate itself, in triangles
    occ::synchronize();
    set_size_and_algorithm(g, m);
    gmsh::model::mesh::generate(2);
    return;
  }
  occ::extrude(cut, 0, 0, g.T, extruded, {m.layers}, {}, false);
  occ::synchronize();
  set_size_and_algorithm(g, m);
  gmsh::model::mesh::generate(3);
}

}  // namespace

vtkSmartPointer<vtkUnstructuredGrid> generate_plate_mesh(const GeometryParams& g,
                                                         const MeshParams& m) {
  BRITTLE_CHECK(g.L > 0 && g.H > 0 && g.T > 0, "plate: L, H, T must be > 0 (got ", g.L, ", ", g.H,
                ", ", g.T, ")");
  BRITTLE_CHECK(g.notch_depth >= 0 && g.notch_depth < g.L, "plate: notch depth ", g.notch_depth,
                " must be in [0, L)");
  BRITTLE_CHECK(g.notch_depth == 0 || (g.notch_base > 0 && g.notch_base < g.H),
                "plate: notch base ", g.notch_base, " must be in (0, H)");
  BRITTLE_CHECK(m.size > 0, "mesh.size ", m.size, " must be > 0");
  BRITTLE_CHECK(m.layers >= 1, "mesh.layers ", m.layers, " must be >= 1");
  BRITTLE_CHECK(m.band >= 0 && m.band_size >= 0, "mesh.band and mesh.band_size must be >= 0");

  if (m.dimension == 2 && !g.notches.empty())
    return with_gmsh_2d("plate mesh", [&] { build_notched_plate(g, m); });
  if (!g.notches.empty()) return with_gmsh("plate mesh", [&] { build_notched_plate(g, m); });
  const auto build = [&] {
    namespace geo = gmsh::model::geo;
    const double L = g.L, h2 = g.H / 2, a = g.notch_depth, b2 = g.notch_base / 2;
    const int p_lower_left = geo::addPoint(0, -h2, 0);
    const int p_lower_right = geo::addPoint(L, -h2, 0);
    const int p_crack_end = geo::addPoint(L, 0, 0);
    const int p_upper_right = geo::addPoint(L, h2, 0);
    const int p_upper_left = geo::addPoint(0, h2, 0);
    std::vector<int> outline = {
        geo::addLine(p_lower_left, p_lower_right), geo::addLine(p_lower_right, p_crack_end),
        geo::addLine(p_crack_end, p_upper_right), geo::addLine(p_upper_right, p_upper_left)};
    int p_crack_start = 0;
    if (a > 0) {  // wedge notch: mouth (0, +-b/2), tip (a, 0)
      const int p_mouth_upper = geo::addPoint(0, b2, 0);
      p_crack_start = geo::addPoint(a, 0, 0);
      const int p_mouth_lower = geo::addPoint(0, -b2, 0);
      outline.push_back(geo::addLine(p_upper_left, p_mouth_upper));
      outline.push_back(geo::addLine(p_mouth_upper, p_crack_start));
      outline.push_back(geo::addLine(p_crack_start, p_mouth_lower));
      outline.push_back(geo::addLine(p_mouth_lower, p_lower_left));
    } else {
      p_crack_start = geo::addPoint(0, 0, 0);
      outline.push_back(geo::addLine(p_upper_left, p_crack_start));
      outline.push_back(geo::addLine(p_crack_start, p_lower_left));
    }
    const int surface = geo::addPlaneSurface({geo::addCurveLoop(outline)});
    const int crack_line = geo::addLine(p_crack_start, p_crack_end);
    geo::synchronize();
    gmsh::model::mesh::embed(1, {crack_line}, 2, surface);

    set_size_and_algorithm(g, m);

    if (m.dimension == 2)
      gmsh::model::mesh::generate(2);
    else
      extrude_and_mesh(g.T, m.layers);
  };
  if (m.dimension == 2) return with_gmsh_2d("plate mesh", build);
  return with_gmsh("plate mesh", build);
}

vtkSmartPointer<vtkUnstructuredGrid> generate_box_mesh(double lx, double ly, double lz, double h) {
  BRITTLE_CHECK(lx > 0 && ly > 0 && lz > 0 && h > 0, "box mesh: lx, ly, lz, h must be > 0 (got ",
                lx, ", ", ly, ", ", lz, ", ", h, ")");
  const auto divisions = [h](double l) {
    return std::max(1, static_cast<int>(std::lround(l / h)));
  };
  return with_gmsh("box mesh", [&] {
    namespace geo = gmsh::model::geo;
    // Structured: nx x ny rectangles, each split into two triangles with alternating
    // diagonals, extruded in nz layers (every prism into three tets).
    const int p0 = geo::addPoint(0, -ly / 2, 0), p1 = geo::addPoint(lx, -ly / 2, 0);
    const int p2 = geo::addPoint(lx, ly / 2, 0), p3 = geo::addPoint(0, ly / 2, 0);
    const int bottom = geo::addLine(p0, p1), right = geo::addLine(p1, p2);
    const int top = geo::addLine(p2, p3), left = geo::addLine(p3, p0);
    const int surface = geo::addPlaneSurface({geo::addCurveLoop({bottom, right, top, left})});
    geo::mesh::setTransfiniteCurve(bottom, divisions(lx) + 1);
    geo::mesh::setTransfiniteCurve(top, divisions(lx) + 1);
    geo::mesh::setTransfiniteCurve(right, divisions(ly) + 1);
    geo::mesh::setTransfiniteCurve(left, divisions(ly) + 1);
    geo::mesh::setTransfiniteSurface(surface, "Alternate");
    extrude_and_mesh(lz, divisions(lz));
  });
}

vtkSmartPointer<vtkUnstructuredGrid> read_mesh(const std::string& path) {
  const std::string where = "mesh file '" + path + "'";
  const std::string expected = " (expected a Gmsh .msh or VTK .vtu file holding tetrahedra)";
  const std::string ext = lower_extension(path);
  BRITTLE_CHECK(ext == ".msh" || ext == ".vtu", where, ": unknown extension '", ext, "'", expected);
  std::error_code ec;
  BRITTLE_CHECK(std::filesystem::exists(path, ec), where, ": no such file", expected);
  BRITTLE_CHECK(std::filesystem::is_regular_file(path, ec), where, ": not a regular file",
                expected);

  // What can be checked before a third-party reader sees the file.
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  BRITTLE_CHECK(!ec && size > 0, where, ": is empty", expected);
  {
    std::ifstream in(path, std::ios::binary);
    std::string head(256, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const std::size_t start = head.find_first_not_of(" \t\r\n");
    const std::string first = start == std::string::npos ? std::string() : head.substr(start);
    if (ext == ".msh")
      BRITTLE_CHECK(first.starts_with("$MeshFormat"), where,
                    ": does not start with $MeshFormat", expected);
    else
      BRITTLE_CHECK(first.starts_with("<?xml") || first.starts_with("<VTKFile"), where,
                    ": does not start with an XML header", expected);
  }
  // The reader runs in a child process: a crash of Gmsh or VTK on a malformed file is an
  // error message here (isolated_read.hpp).
  const bool msh = ext == ".msh";
  const std::string bytes = read_isolated(
      where, msh ? "Gmsh reader" : "VTK reader", expected.substr(11, expected.size() - 12), size,
      [&](StateWriter& w) {
        TetSoup s = msh ? read_msh(path) : read_vtu(path);
        std::vector<std::string> names;
        std::vector<std::vector<std::uint8_t>> masks;
        for (auto& [name, mask] : s.groups) names.push_back(name), masks.push_back(mask);
        io_all(w, s.xyz, s.tets, s.source_ids, names, masks);
      });
  TetSoup soup;
  {
    StateReader r(bytes.data(), bytes.data() + bytes.size(), where);
    std::vector<std::string> names;
    std::vector<std::vector<std::uint8_t>> masks;
    io_all(r, soup.xyz, soup.tets, soup.source_ids, names, masks);
    BRITTLE_CHECK(soup.xyz.size() % 3 == 0 && soup.source_ids.size() == soup.tets.size() &&
                      names.size() == masks.size(),
                  where, ": the reader's result is inconsistent");
    const vtkIdType n_points = static_cast<vtkIdType>(soup.xyz.size() / 3);
    for (const Tet& t : soup.tets)
      for (vtkIdType p : t)
        BRITTLE_CHECK(p >= 0 && p < n_points, where, ": a tetrahedron refers to point ", p,
                      " of ", n_points);
    for (std::size_t i = 0; i < names.size(); ++i) {
      BRITTLE_CHECK(masks[i].size() == soup.xyz.size() / 3, where, ": group '",
                    escape_control(names[i]), "' does not match the points");
      soup.groups.emplace_back(names[i], std::move(masks[i]));
    }
  }
  BRITTLE_CHECK(!soup.tets.empty(), where, ": holds no tetrahedra", expected);
  for (double c : soup.xyz)
    BRITTLE_CHECK(std::isfinite(c), where, ": has a non-finite point coordinate");
  orient_tets(soup, where);
  return make_grid(soup);
}

vtkSmartPointer<vtkUnstructuredGrid> make_mesh(const Scene& scene) {
  vtkSmartPointer<vtkUnstructuredGrid> mesh = scene.mesh.file.empty()
                                                  ? generate_plate_mesh(scene.geometry, scene.mesh)
                                                  : read_mesh(scene.mesh.file);
  if (scene.mesh.perturb > 0)
    perturb_mesh(*mesh, scene.mesh.perturb, static_cast<std::uint64_t>(scene.mesh.perturb_seed));
  return mesh;
}

}  // namespace brittle
