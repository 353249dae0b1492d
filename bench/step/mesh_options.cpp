// bench/step/mesh_options.cpp: the glass plate of bench/peer (100 x 40 x 0.5 mm, the wedge notch
// to x = 50 mm, uniform size h) meshed with Gmsh options that brittle's generator does not
// expose, written as a .msh for `brittle run --dry-run` to measure (issue 38, item 2;
// docs/performance.md, "Better elements"). Built and run by mesh_options.sh.
//
//   mesh_options OUT.msh H ALG2D LAYERS ALG3D SMOOTHING OPTIMIZE NETGEN THRESHOLD
//
// LAYERS > 0: the triangles extruded through the thickness in that many layers (prisms cut into
// tets, as brittle does); 0: the volume meshed freely by ALG3D (1 Delaunay, 4 Frontal, 10 HXT).
#include <gmsh.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 10) {
    std::fprintf(stderr, "usage: %s OUT.msh H ALG2D LAYERS ALG3D SMOOTHING OPTIMIZE NETGEN "
                 "THRESHOLD\n", argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  const double h = std::atof(argv[2]), threshold = std::atof(argv[9]);
  const int alg2d = std::atoi(argv[3]), layers = std::atoi(argv[4]), alg3d = std::atoi(argv[5]);
  const int smoothing = std::atoi(argv[6]), optimize = std::atoi(argv[7]);
  const int netgen = std::atoi(argv[8]);
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
  namespace occ = gmsh::model::occ;
  const double L = 0.1, H = 0.04, T = 0.5e-3, opening = 1e-3;
  const int plate = occ::addRectangle(0, -H / 2, 0, L, H);
  const std::vector<int> corners = {
      occ::addPoint(-opening, opening / 2, 0), occ::addPoint(0, opening / 2, 0),
      occ::addPoint(0.05, 0, 0), occ::addPoint(0, -opening / 2, 0),
      occ::addPoint(-opening, -opening / 2, 0)};
  std::vector<int> lines;
  for (std::size_t i = 0; i < corners.size(); ++i)
    lines.push_back(occ::addLine(corners[i], corners[(i + 1) % corners.size()]));
  const int notch = occ::addPlaneSurface({occ::addCurveLoop(lines)});
  gmsh::vectorpair cut, extruded;
  std::vector<gmsh::vectorpair> map;
  occ::cut({{2, plate}}, {{2, notch}}, cut, map);
  if (layers > 0)
    occ::extrude(cut, 0, 0, T, extruded, {layers}, {}, false);
  else
    occ::extrude(cut, 0, 0, T, extruded);
  occ::synchronize();
  gmsh::option::setNumber("Mesh.Algorithm", alg2d);
  gmsh::option::setNumber("Mesh.Algorithm3D", alg3d);
  gmsh::option::setNumber("Mesh.MeshSizeMin", h);
  gmsh::option::setNumber("Mesh.MeshSizeMax", h);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.Smoothing", smoothing);
  gmsh::option::setNumber("Mesh.Optimize", optimize);
  gmsh::option::setNumber("Mesh.OptimizeNetgen", netgen);
  gmsh::option::setNumber("Mesh.OptimizeThreshold", threshold);
  try {
    gmsh::model::mesh::generate(3);
  } catch (...) {
    std::fprintf(stderr, "mesh_options: Gmsh failed\n");
    return 1;
  }
  gmsh::write(out);
  gmsh::finalize();
  return 0;
}
