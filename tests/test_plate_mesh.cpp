// Meshes (SPEC 1): counts against the paper's CM/RM, geometry and conformity invariants of the
// generated plate, locality numbering, and mesh import (.vtu, .msh) with its error messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gmsh.h>
#include <unistd.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "error.hpp"
#include "plate_mesh.hpp"
#include "scene_options.hpp"

namespace {

using brittle::Error;
using brittle::generate_plate_mesh;
using brittle::GeometryParams;
using brittle::MeshParams;
using Grid = vtkSmartPointer<vtkUnstructuredGrid>;

const std::string kData = BRITTLE_TEST_DATA;

std::array<double, 3> point(vtkUnstructuredGrid& g, vtkIdType p) {
  std::array<double, 3> x;
  g.GetPoint(p, x.data());
  return x;
}

std::array<vtkIdType, 4> tet(vtkUnstructuredGrid& g, vtkIdType c) {
  vtkNew<vtkIdList> ids;
  g.GetCellPoints(c, ids);
  return {ids->GetId(0), ids->GetId(1), ids->GetId(2), ids->GetId(3)};
}

double tet_volume(vtkUnstructuredGrid& g, vtkIdType c) {
  const auto t = tet(g, c);
  const auto x0 = point(g, t[0]), x1 = point(g, t[1]), x2 = point(g, t[2]), x3 = point(g, t[3]);
  double a[3], b[3], d[3];
  for (int i = 0; i < 3; ++i) a[i] = x1[i] - x0[i], b[i] = x2[i] - x0[i], d[i] = x3[i] - x0[i];
  return (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
          a[2] * (b[0] * d[1] - b[1] * d[0])) /
         6.0;
}

double total_volume(vtkUnstructuredGrid& g) {
  double v = 0;
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c) v += tet_volume(g, c);
  return v;
}

double min_volume(vtkUnstructuredGrid& g) {
  double v = INFINITY;
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c) v = std::min(v, tet_volume(g, c));
  return v;
}

/// Area of the faces that belong to one tet only; -1 if a face is shared by more than two.
double boundary_area(vtkUnstructuredGrid& g) {
  std::map<std::array<vtkIdType, 3>, int> faces;
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c) {
    const auto t = tet(g, c);
    for (const auto& f : {std::array{0, 1, 2}, std::array{0, 1, 3}, std::array{0, 2, 3},
                          std::array{1, 2, 3}}) {
      std::array<vtkIdType, 3> k = {t[f[0]], t[f[1]], t[f[2]]};
      std::sort(k.begin(), k.end());
      ++faces[k];
    }
  }
  double area = 0;
  for (const auto& [k, n] : faces) {
    if (n > 2) return -1;
    if (n == 2) continue;
    const auto a = point(g, k[0]), b = point(g, k[1]), c = point(g, k[2]);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
    area += 0.5 * std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  }
  return area;
}

bool every_point_used(vtkUnstructuredGrid& g) {
  std::vector<bool> used(g.GetNumberOfPoints(), false);
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c)
    for (vtkIdType p : tet(g, c)) used[p] = true;
  return std::all_of(used.begin(), used.end(), [](bool u) { return u; });
}

bool has_duplicate_points(vtkUnstructuredGrid& g) {
  std::set<std::array<double, 3>> seen;
  for (vtkIdType p = 0; p < g.GetNumberOfPoints(); ++p)
    if (!seen.insert(point(g, p)).second) return true;
  return false;
}

/// Points numbered by first use: walking the cells in order, every point is either seen
/// before or the next new number.
bool numbered_by_first_use(vtkUnstructuredGrid& g) {
  vtkIdType next = 0;
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c)
    for (vtkIdType p : tet(g, c)) {
      if (p == next) ++next;
      else if (p > next) return false;
    }
  return next == g.GetNumberOfPoints();
}

std::vector<double> coordinates(vtkUnstructuredGrid& g) {
  std::vector<double> x;
  for (vtkIdType p = 0; p < g.GetNumberOfPoints(); ++p)
    for (double c : point(g, p)) x.push_back(c);
  return x;
}

std::vector<vtkIdType> connectivity(vtkUnstructuredGrid& g) {
  std::vector<vtkIdType> ids;
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c)
    for (vtkIdType p : tet(g, c)) ids.push_back(p);
  return ids;
}

bool is_tet_mesh(vtkUnstructuredGrid& g) {
  for (vtkIdType c = 0; c < g.GetNumberOfCells(); ++c)
    if (g.GetCellType(c) != VTK_TETRA) return false;
  return g.GetNumberOfCells() > 0;
}

/// Notched-plate outer surface: two faces, four edges less the notch mouth, two notch faces.
double plate_surface(const GeometryParams& g) {
  const double a = g.notch_depth, b = a > 0 ? g.notch_base : 0.0;
  const double notch_face = std::sqrt(a * a + b * b / 4);
  return 2 * (g.L * g.H - a * b / 2) + g.T * (2 * g.L + 2 * g.H - b + (a > 0 ? 2 * notch_face : 0));
}

double plate_volume(const GeometryParams& g) {
  const double b = g.notch_depth > 0 ? g.notch_base : 0.0;
  return (g.L * g.H - g.notch_depth * b / 2) * g.T;
}

/// The [mesh] section of a shipped scene, parsed as the program parses it.
MeshParams scene_mesh(const std::string& name) {
  return brittle::load_scene({std::string(BRITTLE_SOURCE_DIR) + "/scenes/" + name + ".ini"}, {}).mesh;
}
MeshParams cm() { return scene_mesh("cm"); }
MeshParams rm() { return scene_mesh("rm"); }

MeshParams coarse(int layers = 2) {
  MeshParams m;
  m.size = 1.5e-3;
  m.layers = layers;
  return m;
}


class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::path(testing::TempDir()) /
              ("brittle_mesh_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

void write_vtu(vtkUnstructuredGrid& g, const std::string& path) {
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputData(&g);
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1);
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

/// The error message of read_mesh(path), or "" if it did not throw.
std::string read_error(const std::string& path) {
  try {
    brittle::read_mesh(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// ---------------------------------------------------------------------------------------------
// Counts of the paper's meshes (SPEC 1, paper 6.3)

void expect_within_25_percent(double value, double paper, const char* what) {
  EXPECT_GT(value, 0.75 * paper) << what;
  EXPECT_LT(value, 1.25 * paper) << what;
}

TEST(PlateMesh, CoarseMeshCountsMatchThePaper) {
  const Grid g = generate_plate_mesh(GeometryParams{}, cm());
  expect_within_25_percent(g->GetNumberOfCells(), 17084, "CM tets");
  expect_within_25_percent(g->GetNumberOfPoints(), 5326, "CM nodes");
  EXPECT_GT(min_volume(*g), 0.0);
}

TEST(PlateMesh, RefinedMeshCountsMatchThePaperAndTheBandIsFiner) {
  const GeometryParams geo;
  const MeshParams m = rm();
  const Grid g = generate_plate_mesh(geo, m);
  expect_within_25_percent(g->GetNumberOfCells(), 44872, "RM tets");
  expect_within_25_percent(g->GetNumberOfPoints(), 11605, "RM nodes");
  EXPECT_GT(min_volume(*g), 0.0);

  // Edge length inside the band near band_size, outside the transition near size.
  double in_sum = 0, out_sum = 0;
  int in_n = 0, out_n = 0;
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
    const auto t = tet(*g, c);
    double yc = 0;
    for (vtkIdType p : t) yc += point(*g, p)[1] / 4;
    const auto a = point(*g, t[0]), b = point(*g, t[1]);
    if (std::abs(a[2] - b[2]) > 1e-12) continue;  // in-plane edges only
    const double l = std::hypot(a[0] - b[0], a[1] - b[1]);
    if (std::abs(yc) < m.band && point(*g, t[0])[0] > geo.notch_depth) in_sum += l, ++in_n;
    if (std::abs(yc) > 3 * m.band) out_sum += l, ++out_n;
  }
  ASSERT_GT(in_n, 0);
  ASSERT_GT(out_n, 0);
  EXPECT_NEAR(in_sum / in_n, m.band_size, 0.3 * m.band_size);
  EXPECT_NEAR(out_sum / out_n, m.size, 0.3 * m.size);
}


// ---------------------------------------------------------------------------------------------
// Geometry and conformity of the generated plate

TEST(PlateMesh, NotchedPlateIsAConformingTetMeshOfTheOutline) {
  const GeometryParams geo;
  const Grid g = generate_plate_mesh(geo, coarse());
  ASSERT_TRUE(is_tet_mesh(*g));
  EXPECT_GT(min_volume(*g), 0.0);
  EXPECT_NEAR(total_volume(*g), plate_volume(geo), 1e-9 * plate_volume(geo));
  // A face shared by three tets, a gap or a duplicate node would change the free surface.
  EXPECT_NEAR(boundary_area(*g), plate_surface(geo), 1e-9 * plate_surface(geo));
  EXPECT_FALSE(has_duplicate_points(*g));
  EXPECT_TRUE(every_point_used(*g));

  double bounds[6];
  g->GetBounds(bounds);
  EXPECT_DOUBLE_EQ(bounds[0], 0.0);
  EXPECT_DOUBLE_EQ(bounds[1], geo.L);
  EXPECT_DOUBLE_EQ(bounds[2], -geo.H / 2);
  EXPECT_DOUBLE_EQ(bounds[3], geo.H / 2);
  EXPECT_DOUBLE_EQ(bounds[4], 0.0);
  EXPECT_DOUBLE_EQ(bounds[5], geo.T);
}

TEST(PlateMesh, NodesLieOnTheCrackLineAndNotInTheNotch) {
  const GeometryParams geo;
  const MeshParams m = coarse(2);
  const Grid g = generate_plate_mesh(geo, m);
  const double eps = 1e-9 * geo.L;
  std::map<double, std::vector<double>> crack_x_by_z;  // nodes on y = 0, per layer
  int lower_edge = 0, upper_edge = 0, in_notch = 0;
  for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p) {
    const auto x = point(*g, p);
    if (std::abs(x[1]) < eps) crack_x_by_z[std::round(x[2] / eps) * eps].push_back(x[0]);
    if (std::abs(x[1] + geo.H / 2) < eps) ++lower_edge;
    if (std::abs(x[1] - geo.H / 2) < eps) ++upper_edge;
    // strictly inside the wedge: x < a and |y| < (b/2)(1 - x/a)
    if (x[0] < geo.notch_depth - eps &&
        std::abs(x[1]) < geo.notch_base / 2 * (1 - x[0] / geo.notch_depth) - eps)
      ++in_notch;
  }
  EXPECT_EQ(in_notch, 0);
  EXPECT_GE(lower_edge, 2 * (m.layers + 1));
  EXPECT_GE(upper_edge, 2 * (m.layers + 1));
  ASSERT_EQ(crack_x_by_z.size(), static_cast<std::size_t>(m.layers + 1));
  for (auto& [z, xs] : crack_x_by_z) {
    std::sort(xs.begin(), xs.end());
    EXPECT_NEAR(xs.front(), geo.notch_depth, eps) << "z = " << z;
    EXPECT_NEAR(xs.back(), geo.L, eps) << "z = " << z;
    double largest_gap = 0;
    for (std::size_t i = 1; i < xs.size(); ++i) largest_gap = std::max(largest_gap, xs[i] - xs[i - 1]);
    EXPECT_LT(largest_gap, 1.5 * m.size) << "z = " << z;
  }
}

TEST(PlateMesh, UnnotchedPlateHasTheCrackLineAcrossTheWholeLength) {
  GeometryParams geo;
  geo.notch_depth = 0;
  const Grid g = generate_plate_mesh(geo, coarse(1));
  EXPECT_GT(min_volume(*g), 0.0);
  EXPECT_NEAR(total_volume(*g), geo.L * geo.H * geo.T, 1e-9 * geo.L * geo.H * geo.T);
  EXPECT_NEAR(boundary_area(*g), plate_surface(geo), 1e-9 * plate_surface(geo));
  double x_min = INFINITY, x_max = -INFINITY;
  for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p) {
    const auto x = point(*g, p);
    if (std::abs(x[1]) < 1e-12) x_min = std::min(x_min, x[0]), x_max = std::max(x_max, x[0]);
  }
  EXPECT_DOUBLE_EQ(x_min, 0.0);
  EXPECT_DOUBLE_EQ(x_max, geo.L);
}

TEST(PlateMesh, BadParametersThrow) {
  MeshParams m = coarse();
  m.size = 0;
  EXPECT_THROW(generate_plate_mesh(GeometryParams{}, m), Error);
  GeometryParams geo;
  geo.notch_depth = 2 * geo.L;
  EXPECT_THROW(generate_plate_mesh(geo, coarse()), Error);
}

// ---------------------------------------------------------------------------------------------
// Numbering

TEST(Renumbering, IsDeterministicFirstUseAndLocal) {
  const Grid a = generate_plate_mesh(GeometryParams{}, coarse());
  const Grid b = generate_plate_mesh(GeometryParams{}, coarse());
  EXPECT_EQ(coordinates(*a), coordinates(*b));
  EXPECT_EQ(connectivity(*a), connectivity(*b));
  EXPECT_TRUE(numbered_by_first_use(*a));

  // Renumbering a renumbered mesh changes nothing.
  brittle::renumber_for_locality(*b);
  EXPECT_EQ(coordinates(*a), coordinates(*b));
  EXPECT_EQ(connectivity(*a), connectivity(*b));

  // Neighbouring cells are near in the cell order: the nodes of a cell span few numbers.
  double spread = 0;
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c) {
    const auto t = tet(*a, c);
    spread += *std::max_element(t.begin(), t.end()) - *std::min_element(t.begin(), t.end());
  }
  EXPECT_LT(spread / a->GetNumberOfCells(), 0.05 * a->GetNumberOfPoints());
}

TEST(Renumbering, CarriesPointAndCellArraysAlong) {
  const Grid g = generate_plate_mesh(GeometryParams{}, coarse(1));
  // Reverse the cells and attach old ids as arrays, then renumber back.
  const vtkIdType n_cells = g->GetNumberOfCells(), n_points = g->GetNumberOfPoints();
  vtkNew<vtkCellArray> reversed;
  for (vtkIdType c = n_cells - 1; c >= 0; --c) {
    const auto t = tet(*g, c);
    reversed->InsertNextCell(4, t.data());
  }
  const Grid r = vtkSmartPointer<vtkUnstructuredGrid>::New();
  r->SetPoints(g->GetPoints());
  r->SetCells(VTK_TETRA, reversed);
  vtkNew<vtkIdTypeArray> point_id, cell_id;
  point_id->SetName("point_id");
  cell_id->SetName("cell_id");
  for (vtkIdType p = 0; p < n_points; ++p) point_id->InsertNextValue(p);
  for (vtkIdType c = 0; c < n_cells; ++c) cell_id->InsertNextValue(c);
  r->GetPointData()->AddArray(point_id);
  r->GetCellData()->AddArray(cell_id);

  brittle::renumber_for_locality(*r);
  auto* p_ids = vtkIdTypeArray::SafeDownCast(r->GetPointData()->GetArray("point_id"));
  auto* c_ids = vtkIdTypeArray::SafeDownCast(r->GetCellData()->GetArray("cell_id"));
  ASSERT_NE(p_ids, nullptr);
  ASSERT_NE(c_ids, nullptr);
  for (vtkIdType p = 0; p < n_points; ++p)
    ASSERT_EQ(point(*r, p), point(*g, p_ids->GetValue(p))) << p;
  for (vtkIdType c = 0; c < n_cells; ++c) {
    // cell c of r was cell n-1-c_ids of g before reversal (same nodes, in r's numbering)
    const auto t_r = tet(*r, c);
    const auto t_g = tet(*g, n_cells - 1 - c_ids->GetValue(c));
    for (int j = 0; j < 4; ++j) ASSERT_EQ(point(*r, t_r[j]), point(*g, t_g[j]));
  }
}

// ---------------------------------------------------------------------------------------------
// Box (bar) mesh

TEST(BoxMesh, FillsTheBoxWithRegularTets) {
  const double lx = 10e-3, ly = 1e-3, lz = 1e-3, h = 0.5e-3;
  const Grid g = brittle::generate_box_mesh(lx, ly, lz, h);
  ASSERT_TRUE(is_tet_mesh(*g));
  EXPECT_EQ(g->GetNumberOfCells(), 20 * 2 * 2 * 6);  // 20 x 2 x 2 prisms of 2 x 3 tets
  EXPECT_EQ(g->GetNumberOfPoints(), 21 * 3 * 3);
  EXPECT_NEAR(total_volume(*g), lx * ly * lz, 1e-9 * lx * ly * lz);
  EXPECT_NEAR(boundary_area(*g), 2 * (lx * ly + ly * lz + lz * lx), 1e-9 * lx * ly * 2);
  double bounds[6];
  g->GetBounds(bounds);
  EXPECT_DOUBLE_EQ(bounds[2], -ly / 2);
  EXPECT_DOUBLE_EQ(bounds[3], ly / 2);
  // Regular enough for a wave-speed test: every tet keeps a sizeable share of the cube volume.
  EXPECT_GT(min_volume(*g), 0.1 * h * h * h);
}

// ---------------------------------------------------------------------------------------------
// Import

TEST(ReadMesh, VtuRoundTripGivesTheSameMesh) {
  TempDir dir("vtu");
  const Grid g = generate_plate_mesh(GeometryParams{}, coarse());
  write_vtu(*g, dir.file("plate.vtu"));
  const Grid r = brittle::read_mesh(dir.file("plate.vtu"));
  EXPECT_EQ(coordinates(*r), coordinates(*g));
  EXPECT_EQ(connectivity(*r), connectivity(*g));
}

TEST(ReadMesh, MshWrittenByGmshIsRead) {
  TempDir dir("msh");
  // An unstructured (Delaunay) tet mesh of a 2 x 1 x 1 mm box, in both Gmsh file formats.
  std::size_t gmsh_tets = 0;
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::model::add("box");
  namespace geo = gmsh::model::geo;
  const int p1 = geo::addPoint(0, 0, 0, 0.4e-3), p2 = geo::addPoint(2e-3, 0, 0, 0.4e-3);
  const int p3 = geo::addPoint(2e-3, 1e-3, 0, 0.4e-3), p4 = geo::addPoint(0, 1e-3, 0, 0.4e-3);
  const int s = geo::addPlaneSurface({geo::addCurveLoop(
      {geo::addLine(p1, p2), geo::addLine(p2, p3), geo::addLine(p3, p4), geo::addLine(p4, p1)})});
  gmsh::vectorpair out;
  geo::extrude({{2, s}}, 0, 0, 1e-3, out);
  geo::synchronize();
  gmsh::model::mesh::generate(3);
  std::vector<std::size_t> tags, nodes;
  gmsh::model::mesh::getElementsByType(4, tags, nodes);
  gmsh_tets = tags.size();
  gmsh::write(dir.file("box41.msh"));
  gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
  gmsh::write(dir.file("box22.msh"));
  gmsh::finalize();
  ASSERT_GT(gmsh_tets, 10u);

  for (const char* name : {"box41.msh", "box22.msh"}) {
    const Grid r = brittle::read_mesh(dir.file(name));  // triangles, lines, points ignored
    EXPECT_EQ(r->GetNumberOfCells(), static_cast<vtkIdType>(gmsh_tets)) << name;
    EXPECT_TRUE(is_tet_mesh(*r));
    EXPECT_GT(min_volume(*r), 0.0) << name;
    EXPECT_NEAR(total_volume(*r), 2e-9, 1e-9 * 2e-9) << name;
    EXPECT_TRUE(every_point_used(*r));
    EXPECT_TRUE(numbered_by_first_use(*r));
  }
}

TEST(ReadMesh, InvertedTetIsReoriented) {
  const Grid r = brittle::read_mesh(kData + "/inverted_tet.vtu");
  ASSERT_EQ(r->GetNumberOfCells(), 1);
  ASSERT_EQ(r->GetNumberOfPoints(), 4);
  EXPECT_NEAR(tet_volume(*r, 0), 1e-9 / 6, 1e-12 * 1e-9);
}

TEST(ReadMesh, ZeroVolumeTetIsAnErrorNamingFileAndTet) {
  const std::string message = read_error(kData + "/degenerate_tet.vtu");
  EXPECT_NE(message.find("degenerate_tet.vtu"), std::string::npos) << message;
  EXPECT_NE(message.find("tetrahedron 1 "), std::string::npos) << message;
  EXPECT_NE(message.find("zero volume"), std::string::npos) << message;
}

TEST(ReadMesh, OtherCellsAndUnusedPointsAreDropped) {
  TempDir dir("mixed");
  // One tet, one triangle on two extra points, one point used by nothing.
  write_text(dir.file("mixed.vtu"), R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
  <UnstructuredGrid><Piece NumberOfPoints="7" NumberOfCells="2">
    <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">
      5 5 5  0 0 0  2 0 0  0 2 0  0 0 2  9 9 9  8 9 9
    </DataArray></Points>
    <Cells>
      <DataArray type="Int64" Name="connectivity" format="ascii">1 5 6  1 2 3 4</DataArray>
      <DataArray type="Int64" Name="offsets" format="ascii">3 7</DataArray>
      <DataArray type="UInt8" Name="types" format="ascii">5 10</DataArray>
    </Cells>
  </Piece></UnstructuredGrid>
</VTKFile>
)");
  const Grid r = brittle::read_mesh(dir.file("mixed.vtu"));
  ASSERT_EQ(r->GetNumberOfCells(), 1);
  ASSERT_EQ(r->GetNumberOfPoints(), 4);
  EXPECT_NEAR(tet_volume(*r, 0), 8.0 / 6, 1e-12);
}

TEST(ReadMesh, UnreadableFilesAreOneLineErrorsNamingTheFile) {
  TempDir dir("bad");
  write_text(dir.file("garbage.msh"), "this is not a mesh\n\x01\x02\x03 {{{\n");
  write_text(dir.file("garbage.vtu"), "<?xml version=\"1.0\"?>\n<VTKFile type=\"Unstr");
  write_text(dir.file("plate.stl"), "solid x\nendsolid x\n");
  write_text(dir.file("triangle.vtu"), R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
  <UnstructuredGrid><Piece NumberOfPoints="3" NumberOfCells="1">
    <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">
      0 0 0  1 0 0  0 1 0</DataArray></Points>
    <Cells>
      <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2</DataArray>
      <DataArray type="Int64" Name="offsets" format="ascii">3</DataArray>
      <DataArray type="UInt8" Name="types" format="ascii">5</DataArray>
    </Cells>
  </Piece></UnstructuredGrid>
</VTKFile>
)");
  for (const std::string name :
       {"missing.msh", "missing.vtu", "garbage.msh", "garbage.vtu", "plate.stl", "triangle.vtu"}) {
    const std::string path = dir.file(name);
    const std::string message = read_error(path);
    EXPECT_NE(message.find("mesh file '" + path + "'"), std::string::npos) << message;
    EXPECT_NE(message.find("expected a Gmsh .msh or VTK .vtu file"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // After a failed import Gmsh is usable again.
  EXPECT_GT(generate_plate_mesh(GeometryParams{}, coarse(1))->GetNumberOfCells(), 0);
}

TEST(MakeMesh, ReadsTheFileWhenSetAndGeneratesOtherwise) {
  brittle::Scene scene;
  scene.mesh = coarse(1);
  const Grid generated = brittle::make_mesh(scene);
  EXPECT_NEAR(total_volume(*generated), plate_volume(scene.geometry),
              1e-9 * plate_volume(scene.geometry));
  scene.mesh.file = kData + "/inverted_tet.vtu";
  EXPECT_EQ(brittle::make_mesh(scene)->GetNumberOfCells(), 1);
}

// mesh.perturb (docs/mesh.md): nodes off the lateral boundary move in x-y only, by at most the
// fraction of their shortest in-plane edge, nodes above one another together; the same seed
// gives the same mesh, another seed another; too large a fraction is refused.
TEST(PerturbMesh, MovesInteriorNodesInPlaneWithinTheirEdgesAndKeepsTheOutline) {
  const double fraction = 0.25;
  const Grid base = generate_plate_mesh(GeometryParams{}, cm());
  auto copy = [&] {
    Grid g = vtkSmartPointer<vtkUnstructuredGrid>::New();
    g->DeepCopy(base);
    return g;
  };
  Grid a = copy(), b = copy(), c = copy();
  brittle::perturb_mesh(*a, fraction, 1);
  brittle::perturb_mesh(*b, fraction, 1);
  brittle::perturb_mesh(*c, fraction, 2);
  const vtkIdType n = base->GetNumberOfPoints();
  // The shortest in-plane edge of every node, from the unperturbed mesh.
  std::vector<double> shortest(n, 1e30);
  vtkNew<vtkIdList> ids;
  for (vtkIdType e = 0; e < base->GetNumberOfCells(); ++e) {
    base->GetCellPoints(e, ids);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        double p[3], q[3];
        base->GetPoint(ids->GetId(i), p);
        base->GetPoint(ids->GetId(j), q);
        if (std::abs(p[2] - q[2]) > 1e-12) continue;
        const double l = std::hypot(p[0] - q[0], p[1] - q[1]);
        for (vtkIdType k : {ids->GetId(i), ids->GetId(j)}) shortest[k] = std::min(shortest[k], l);
      }
  }
  const GeometryParams geo;
  int moved = 0, on_outline_moved = 0;
  std::map<std::pair<long long, long long>, std::array<double, 2>> column_move;
  bool columns_together = true;
  for (vtkIdType p = 0; p < n; ++p) {
    double x0[3], x1[3], xb[3];
    base->GetPoint(p, x0);
    a->GetPoint(p, x1);
    b->GetPoint(p, xb);
    ASSERT_EQ(x1[2], x0[2]);
    ASSERT_TRUE(x1[0] == xb[0] && x1[1] == xb[1]) << "the same seed, another mesh at " << p;
    const double d = std::hypot(x1[0] - x0[0], x1[1] - x0[1]);
    EXPECT_LE(d, fraction * shortest[p] * (1 + 1e-12)) << p;
    const bool outline = std::abs(std::abs(x0[1]) - 0.5 * geo.H) < 1e-9 || x0[0] < 1e-9 ||
                         std::abs(x0[0] - geo.L) < 1e-9;
    if (d > 0) ++moved, on_outline_moved += outline;
    const auto key = std::make_pair(std::llround(x0[0] * 1e9), std::llround(x0[1] * 1e9));
    const std::array<double, 2> move{x1[0] - x0[0], x1[1] - x0[1]};
    const auto [it, made] = column_move.try_emplace(key, move);
    if (!made && it->second != move) columns_together = false;
  }
  EXPECT_GT(moved, n / 2);
  EXPECT_EQ(on_outline_moved, 0);
  EXPECT_TRUE(columns_together);
  int differ = 0;
  for (vtkIdType p = 0; p < n; ++p) {
    double xa[3], xc[3];
    a->GetPoint(p, xa);
    c->GetPoint(p, xc);
    differ += xa[0] != xc[0];
  }
  EXPECT_GT(differ, n / 2);
  EXPECT_GT(min_volume(*a), 0.0);
  Grid d = copy();
  EXPECT_THROW(brittle::perturb_mesh(*d, 0.31, 1), brittle::Error);
}

}  // namespace
