// MPI groundwork (issue 14, docs/parallel.md): the METIS partition and its ghost layers checked
// against a brute-force count, and whole runs spread over ranks by mpirun giving the same
// files as the serial command.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gmsh.h>
#include <nlohmann/json.hpp>
#include <vtkCellData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "cli_helpers.hpp"
#include "fixtures.hpp"
#include "mpi_helpers.hpp"
#include "element_forces.hpp"
#include "exact_sum.hpp"
#include "grid.hpp"
#include "output.hpp"
#include "partition.hpp"
#include "plate_mesh.hpp"

namespace fs = std::filesystem;
using brittle_test::contains;
using brittle_test::quote;
using brittle_test::read_text;
using brittle_test::TempDir;

namespace brittle {
namespace {

using namespace mpi_test;

/// The CM plate on a 1 mm mesh (about 3,800 tets).
Grid small_grid(vtkSmartPointer<vtkUnstructuredGrid>& mesh) {
  Scene scene = testing::plate_scene(0.9, 1e-6);
  scene.mesh.size = 1e-3;
  mesh = make_mesh(scene);
  return Grid(*mesh);
}

TEST(Partition, OnePartHasNoGhosts) {
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
  const Grid grid = small_grid(mesh);
  const Partition p = partition_grid(grid, 1);
  ASSERT_EQ(p.stats.size(), 1u);
  EXPECT_EQ(p.stats[0].owned_cells, grid.num_cells());
  EXPECT_EQ(p.stats[0].owned_nodes, grid.num_points());
  EXPECT_EQ(p.stats[0].ghost_nodes, 0);
  EXPECT_EQ(p.stats[0].ghost_cells, 0);
  EXPECT_EQ(p.cut_faces, 0);
}

/// Every part's ghost layer, counted the slow way: the owned cells and the cells touching an
/// owned node, the nodes
/// of those cells; ghosts are the ones another part owns. Also: the owner rule, balance and
/// determinism.
TEST(Partition, GhostLayersAreWhatOwnedNodesNeed) {
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
  const Grid grid = small_grid(mesh);
  const vtkIdType* conn = grid.cells();
  for (int parts : {2, 3, 5}) {
    SCOPED_TRACE(parts);
    const Partition p = partition_grid(grid, parts);
    ASSERT_EQ(p.cell_part.size(), static_cast<std::size_t>(grid.num_cells()));
    EXPECT_EQ(p.cell_part, partition_grid(grid, parts).cell_part);  // same grid, same partition
    EXPECT_LT(p.imbalance(), 1.05);
    EXPECT_GT(p.cut_faces, 0);
    // Owner: the part of the node's lowest-numbered cell.
    std::vector<vtkIdType> first_cell(grid.num_points(), -1);
    for (vtkIdType e = grid.num_cells() - 1; e >= 0; --e)
      for (int c = 0; c < 4; ++c) first_cell[conn[4 * e + c]] = e;
    for (vtkIdType k = 0; k < grid.num_points(); ++k)
      ASSERT_EQ(p.node_owner[k], p.cell_part[first_cell[k]]) << k;
    long total_ghosts = 0;
    for (int r = 0; r < parts; ++r) {
      std::set<vtkIdType> cells, nodes;
      for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
        if (p.cell_part[e] == r) cells.insert(e);  // its own cells, with or without owned nodes
        for (int c = 0; c < 4; ++c)
          if (p.node_owner[conn[4 * e + c]] == r) cells.insert(e);
      }
      std::set<int> neighbours;
      long ghost_cells = 0;
      for (vtkIdType e : cells) {
        if (p.cell_part[e] != r) ++ghost_cells;
        for (int c = 0; c < 4; ++c)
          if (p.node_owner[conn[4 * e + c]] != r) {
            nodes.insert(conn[4 * e + c]);
            neighbours.insert(p.node_owner[conn[4 * e + c]]);
          }
      }
      EXPECT_EQ(p.stats[r].ghost_cells, ghost_cells) << r;
      EXPECT_EQ(p.stats[r].ghost_nodes, static_cast<long>(nodes.size())) << r;
      EXPECT_EQ(p.stats[r].neighbours, static_cast<int>(neighbours.size())) << r;
      EXPECT_GT(p.stats[r].ghost_nodes, 0) << r;
      total_ghosts += p.stats[r].ghost_nodes;
    }
    EXPECT_DOUBLE_EQ(p.ghost_fraction(), double(total_ghosts) / grid.num_points());
  }
}

/// A criterion's ghost reach (issue 52, item 2), counted the slow way: with 2 layers a part
/// holds every cell touching a node of a first-layer cell; with a distance, every cell whose
/// centroid lies within it of a point of a held cell (checked at the corners and centroids).
/// The extracted parts and the holders agree, and the reach adds cells only.
TEST(Partition, GhostReachHoldsWhatACriterionReads) {
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
  const Grid grid = small_grid(mesh);
  const vtkIdType* conn = grid.cells();
  const double* X = grid.X();
  auto centroid = [&](vtkIdType e, int a) {
    return 0.25 * (X[3 * conn[4 * e] + a] + X[3 * conn[4 * e + 1] + a] +
                   X[3 * conn[4 * e + 2] + a] + X[3 * conn[4 * e + 3] + a]);
  };
  const int parts = 3;
  const Partition one = partition_grid(grid, parts);
  for (const GhostReach reach : {GhostReach{2, 0.0}, GhostReach{1, 2.5e-3}}) {
    SCOPED_TRACE(::testing::Message() << reach.layers << " layers, " << reach.distance << " m");
    const Partition p = partition_grid(grid, parts, reach);
    EXPECT_EQ(p.cell_part, one.cell_part);  // the reach does not move the cut
    for (int r = 0; r < parts; ++r) {
      std::vector<char> first(grid.num_cells(), 0), need(grid.num_cells(), 0);
      for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
        first[e] = p.cell_part[e] == r;
        for (int c = 0; c < 4; ++c) first[e] |= p.node_owner[conn[4 * e + c]] == r;
      }
      need = first;
      if (reach.layers == 2) {
        std::set<vtkIdType> nodes;
        for (vtkIdType e = 0; e < grid.num_cells(); ++e)
          if (first[e])
            for (int c = 0; c < 4; ++c) nodes.insert(conn[4 * e + c]);
        for (vtkIdType e = 0; e < grid.num_cells(); ++e)
          for (int c = 0; c < 4; ++c) need[e] |= nodes.count(conn[4 * e + c]) > 0;
      } else {  // within the distance of a corner or the centroid of a first-layer cell
        std::vector<std::array<double, 3>> points;
        for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
          if (!first[e]) continue;
          points.push_back({centroid(e, 0), centroid(e, 1), centroid(e, 2)});
          for (int c = 0; c < 4; ++c)
            points.push_back({X[3 * conn[4 * e + c]], X[3 * conn[4 * e + c] + 1],
                              X[3 * conn[4 * e + c] + 2]});
        }
        for (vtkIdType e = 0; e < grid.num_cells(); ++e)
          for (const auto& q : points) {
            const double d = std::hypot(centroid(e, 0) - q[0], centroid(e, 1) - q[1],
                                        centroid(e, 2) - q[2]);
            if (d <= reach.distance) {
              need[e] = 1;
              break;
            }
          }
      }
      const LocalPart part = extract_part(grid, p, r);
      std::set<vtkIdType> held(part.global_cell.begin(), part.global_cell.end());
      long missing = 0, extra = 0;
      for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
        missing += need[e] && !held.count(e);
        extra += held.count(e) && !first[e];
        const bool holder = std::binary_search(p.holders.begin() + p.holder_start[e],
                                               p.holders.begin() + p.holder_start[e + 1], r);
        ASSERT_EQ(holder, held.count(e) > 0) << "cell " << e;
      }
      EXPECT_EQ(missing, 0) << "part " << r;
      EXPECT_GT(extra, 0) << "part " << r;
      EXPECT_EQ(p.stats[r].extra_ghost_cells, extra) << "part " << r;
      EXPECT_EQ(part.reach.layers, reach.layers);
      EXPECT_EQ(part.reach.distance, reach.distance);
    }
  }
  // No reach: a cell's holders are its part and its corners' owners.
  for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
    std::set<int> h{one.cell_part[e]};
    for (int c = 0; c < 4; ++c) h.insert(one.node_owner[conn[4 * e + c]]);
    ASSERT_EQ(std::vector<int>(h.begin(), h.end()),
              std::vector<int>(one.holders.begin() + one.holder_start[e],
                               one.holders.begin() + one.holder_start[e + 1]));
  }
}

/// The claim the decomposed run rests on (docs/parallel.md): a rank that holds its owned cells
/// plus the ghost cells touching its owned nodes, in global order, computes every owned node's
/// force and mass with the same bits as the whole grid, and every cell's stress too.
TEST(Partition, OwnedNodeForcesOfEveryPartAreTheSerialBits) {
  vtkSmartPointer<vtkUnstructuredGrid> mesh;
  Grid whole = small_grid(mesh);
  const Scene scene = testing::plate_scene(0.9, 1e-6);
  const ElasticConstants c = ElasticConstants::from(scene.material);
  const ElementData elements = make_element_data(whole, c, scene.material);
  lump_masses(whole, elements, scene.material.rho0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), omega(0.0, 0.9);
  for (vtkIdType i = 0; i < 3 * whole.num_points(); ++i) {
    whole.x()[i] = whole.X()[i] + 0.05e-3 * unit(rng);
    whole.v()[i] = 20.0 * unit(rng);
  }
  for (vtkIdType e = 0; e < whole.num_cells(); ++e) whole.damage()[e] = omega(rng);
  ForceAssembler serial(whole, elements, c);
  ASSERT_LT(serial.compute(whole), 0);
  for (int parts : {2, 3, 5}) {
    const Partition p = partition_grid(whole, parts);
    for (int r = 0; r < parts; ++r) {
      SCOPED_TRACE(::testing::Message() << parts << " parts, part " << r);
      const LocalPart part = extract_part(whole, p, r);
      Grid local(*part.mesh);
      const ElementData local_elements = make_element_data(local, c, scene.material);
      lump_masses(local, local_elements, scene.material.rho0);
      for (std::size_t i = 0; i < part.global_node.size(); ++i)
        for (int k = 0; k < 3; ++k) {
          local.x()[3 * i + k] = whole.x()[3 * part.global_node[i] + k];
          local.v()[3 * i + k] = whole.v()[3 * part.global_node[i] + k];
        }
      for (std::size_t e = 0; e < part.global_cell.size(); ++e)
        local.damage()[e] = whole.damage()[part.global_cell[e]];
      ForceAssembler assembler(local, local_elements, c);
      ASSERT_LT(assembler.compute(local), 0);
      long owned = 0;
      for (std::size_t i = 0; i < part.global_node.size(); ++i) {
        if (!part.owned[i]) continue;
        ++owned;
        const vtkIdType g = part.global_node[i];
        ASSERT_EQ(local.mass()[i], whole.mass()[g]) << "node " << g;
        for (int k = 0; k < 3; ++k)
          ASSERT_EQ(assembler.nodal_forces()[3 * i + k], serial.nodal_forces()[3 * g + k])
              << "node " << g << " component " << k;  // bitwise, not near
      }
      EXPECT_EQ(owned, p.stats[r].owned_nodes);
      for (std::size_t e = 0; e < part.global_cell.size(); ++e)
        for (int k = 0; k < 6; ++k)
          ASSERT_EQ(local.stress()[6 * e + k], whole.stress()[6 * part.global_cell[e] + k]);
    }
  }
}

/// The exact sum (solver/physics/exact_sum.hpp) does not depend on the order of the additions, keeps
/// what a floating-point sum loses, and rounds to within an ulp.
TEST(ExactSum, OrderDoesNotMatterAndNothingIsLost) {
  ExactSum cancel;
  for (double x : {1e16, 1.0, -1e16, 1e-300, -1e-300, 5e-324}) cancel += x;
  EXPECT_EQ(cancel.value(), 1.0);  // a float sum gives 0; the exact 1 + 5e-324 rounds to 1
  ExactSum tiny;
  tiny += 5e-324;
  tiny += 5e-324;
  EXPECT_EQ(tiny.value(), 1e-323);  // subnormals add exactly
  ExactSum big;
  big += 1.7e308;
  big += 1.7e308;
  big += -1.7e308;
  EXPECT_EQ(big.value(), 1.7e308);  // past the double range and back
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40);
  std::vector<double> values(20000);
  for (double& x : values) x = std::ldexp(mantissa(rng), exponent(rng));
  ExactSum forward, halves;
  for (double x : values) forward += x;
  std::shuffle(values.begin(), values.end(), rng);
  ExactSum a, b;
  for (std::size_t i = 0; i < values.size(); ++i) (i % 2 ? a : b) += values[i];
  halves += a;
  halves += b;
  EXPECT_EQ(forward.value(), halves.value());
  EXPECT_EQ(ExactSum::from_words(forward.words()).value(), forward.value());
  long double reference = 0;  // 64-bit mantissa, sorted by magnitude: close to exact
  std::sort(values.begin(), values.end(), [](double p, double q) { return std::abs(p) < std::abs(q); });
  for (double x : values) reference += x;
  EXPECT_NEAR(forward.value(), static_cast<double>(reference),
              4 * std::numeric_limits<double>::epsilon() * std::abs(forward.value()));
  ExactSum negative;
  negative += -2.5;
  negative += 0.25;
  EXPECT_EQ(negative.value(), -2.25);
  ExactSum nan;
  nan += std::numeric_limits<double>::infinity();
  EXPECT_EQ(nan.value(), std::numeric_limits<double>::infinity());
  nan += -std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isnan(nan.value()));
}

/// `mpirun -np 1, 2, 3 brittle study` runs the same runs as the serial command: every run's
/// energies, events and summary (timings aside) are bitwise those of the serial study.
TEST(Mpi, StudyOverRanksEqualsTheSerialStudy) {
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::string args = " study mesh " + quote(scenes + "cm.ini") +
                           " --sizes 2e-3,1e-3 --case straight --case damage=" +
                           quote(scenes + "damage.ini") + " --set run.end_time=8e-6 --jobs 1";
  ASSERT_EQ(shell(quote(BRITTLE_EXE) + args + " --out " + quote((dir / "serial").string()),
                  dir / "serial.log"),
            0)
      << read_text(dir / "serial.log");
  for (int ranks : {1, 2, 3}) {
    SCOPED_TRACE(ranks);
    const fs::path out = dir / ("np" + std::to_string(ranks));
    const fs::path log = dir / ("np" + std::to_string(ranks) + ".log");
    ASSERT_EQ(shell(mpiexec(ranks) + args + " --out " + quote(out.string()), log), 0)
        << read_text(log);
    // One table, from rank 0.
    const std::string text = read_text(log);
    EXPECT_TRUE(contains(text, "wrote")) << text;
    EXPECT_EQ(text.find("wrote"), text.rfind("wrote")) << text;
    for (const char* run : {"straight/h_2000um", "straight/h_1000um", "damage/h_2000um",
                            "damage/h_1000um"}) {
      SCOPED_TRACE(run);
      for (const char* file : {"energies.csv", "events.csv", "crack_tip.csv", "sensors.csv"})
        EXPECT_EQ(read_text(out / run / file), read_text(dir / "serial" / run / file)) << file;
      std::ifstream a(out / run / "summary.json"), b(dir / "serial" / run / "summary.json");
      EXPECT_EQ(without_timings(nlohmann::json::parse(a)),
                without_timings(nlohmann::json::parse(b)));
    }
  }
}

/// `mpirun -np 2, 3 brittle run` writes what the serial run writes, bit for bit: every CSV,
/// events, pattern, summary (timings aside) and the last frame's points, cells and arrays (put
/// together from the pieces by serial id), for a straight crack and for branching with damage
/// and rate-dependent links on CM; `brittle render` of the .pvd gives the serial PNGs.
TEST(Mpi, DecomposedRunWritesTheSerialFiles) {
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"straight", quote(scenes + "cm.ini") + " --set run.end_time=20e-6"},
      {"branching", quote(scenes + "cm.ini") + " " + quote(scenes + "branching.ini") + " " +
                        quote(scenes + "damage.ini") + " " + quote(scenes + "rate-dependent.ini") +
                        " --set run.end_time=15e-6"},
      // the nodal step bound and mass scaling (issue 52, item 3) on the glass plate, whose
      // traction regions miss the middle rank's part on 3 ranks
      {"nodal-bound-mass-scaling",
       quote(scenes + "glass-branching.ini") + " " + quote(scenes + "glass-nodal.ini") +
           " --set run.step_bound=nodal --set run.cfl=0.9 --set run.mass_scaling=5e-8"
           " --set run.end_time=40e-6"},
      // the facet criterion (issue 52, item 1): the glass plate as shipped on the 1 mm band,
      // past the fork (x = 74 mm, 50 us)
      {"facet", quote(scenes + "glass-branching.ini") +
                    " --set mesh.band_size=1e-3 --set run.end_time=60e-6"}};
  const std::string threads = " --set run.threads=1";
  for (const auto& [name, args] : cases) {
    SCOPED_TRACE(name);
    const fs::path serial = dir / (name + "_serial");
    ASSERT_EQ(shell(quote(BRITTLE_EXE) + " run " + args + threads + " --out " + quote(serial.string()),
                    dir / "serial.log"),
              0)
        << read_text(dir / "serial.log");
    const Frame expected = last_frame(serial, 0);
    std::ifstream summary(serial / "summary.json");
    const nlohmann::json serial_summary = without_timings(nlohmann::json::parse(summary));
    EXPECT_GT(serial_summary["splits"].get<long>(), 20);
    for (int ranks : {2, 3}) {  // (one part: Decomposed.Ranks1, in one process)
      SCOPED_TRACE(ranks);
      const fs::path out = dir / (name + "_np" + std::to_string(ranks));
      const fs::path log = dir / (name + "_np" + std::to_string(ranks) + ".log");
      ASSERT_EQ(shell(mpiexec(ranks) + " run " + args + threads + " --out " + quote(out.string()), log), 0)
          << read_text(log);
      EXPECT_EQ(read_text(log).find("wrote"), read_text(log).rfind("wrote")) << "rank 0 only";
      for (const char* file :
           {"energies.csv", "crack_tip.csv", "events.csv", "branches.csv", "pattern.json"})
        EXPECT_EQ(read_text(out / file), read_text(serial / file)) << file;
      std::ifstream s(out / "summary.json");
      nlohmann::json j = without_timings(nlohmann::json::parse(s)), e = serial_summary;
      j.erase("threads"), e.erase("threads");
      if (name == "nodal-bound-mass-scaling") {
        // Mass scaling brings every scaled cell's step to the target: which cell is "the
        // smallest" is then a tie in the last bits, which the two loops (serial and over the
        // ranks) may round differently (docs/parallel.md, "Limits"); the step itself is equal.
        EXPECT_EQ(j["step_distribution"]["smallest"], e["step_distribution"]["smallest"]);
        j.erase("step_distribution"), e.erase("step_distribution");
      }
      EXPECT_EQ(j, e);
      const Frame got = last_frame(out, ranks);
      EXPECT_EQ(got.points, expected.points);
      EXPECT_EQ(got.cells, expected.cells);
      EXPECT_EQ(got.point.size(), expected.point.size());
      for (const auto& [array, values] : expected.point) EXPECT_EQ(got.point.at(array), values) << array;
      EXPECT_EQ(got.cell.size(), expected.cell.size());
      for (const auto& [array, values] : expected.cell) EXPECT_EQ(got.cell.at(array), values) << array;
      // brittle render joins the pieces into the serial grid: the same PNGs, crack frames too
      // (a piece boundary is not a crack)
      for (const fs::path& run : {serial, out})
        ASSERT_EQ(shell(quote(BRITTLE_EXE) + " render " + quote((run / "run.pvd").string()) +
                            " --fields crack,sigma1 --times 10e-6 --out " +
                            quote((run / "png").string()),
                        dir / "render.log"),
                  0)
            << read_text(dir / "render.log");
      int pngs = 0;
      for (const auto& png : fs::directory_iterator(serial / "png")) {
        ++pngs;
        EXPECT_EQ(read_text(png.path()), read_text(out / "png" / png.path().filename()))
            << png.path().filename();
      }
      EXPECT_EQ(pngs, 2);
      fs::remove_all(serial / "png");
    }
  }
}

/// A box of 8 x 4 x 0.5 mm meshed by Gmsh (0.5 mm elements) with the physical groups
/// "bottom" (y = 0), "top" (y = 4 mm) and "body", written as `path`.
void write_box_with_groups(const std::string& path) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::model::add("box");
  namespace geo = gmsh::model::geo;
  const double h = 0.5e-3;
  const int p1 = geo::addPoint(0, 0, 0, h), p2 = geo::addPoint(8e-3, 0, 0, h);
  const int p3 = geo::addPoint(8e-3, 4e-3, 0, h), p4 = geo::addPoint(0, 4e-3, 0, h);
  const int s = geo::addPlaneSurface({geo::addCurveLoop(
      {geo::addLine(p1, p2), geo::addLine(p2, p3), geo::addLine(p3, p4), geo::addLine(p4, p1)})});
  gmsh::vectorpair out;  // the top face, the volume, then the sides of the four lines
  geo::extrude({{2, s}}, 0, 0, 0.5e-3, out);
  geo::synchronize();
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {out[2].second}), "bottom");
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {out[4].second}), "top");
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {out[1].second}), "body");
  gmsh::model::mesh::generate(3);
  gmsh::write(path);
  gmsh::finalize();
}

/// Issue 27, item 3: what a serial run does with sensors, render.times and regions given by
/// physical group, a run over 2 and 3 ranks does with the same bits: energies, sensors.csv,
/// spectra.csv, sensors.json and the PNGs drawn while running (rank 0 joins the pieces).
TEST(Mpi, SensorsRenderTimesAndGroupRegionsMatchTheSerialRun) {
  TempDir dir;
  const std::string mesh = (dir / "box.msh").string();
  write_box_with_groups(mesh);
  {
    std::ofstream ini(dir / "box.ini");
    ini << "[material]\nrho0 = 1180\nE = 3.09e9\nnu = 0.35\nsigma_c = 75e6\ngamma = 150\n"
           "zeta1 = 0.1\nzeta2 = 0.1\n[mesh]\nfile = " << mesh << "\n"
           "[initial]\nstate = rest\n[boundary.bottom]\ntype = fixed\ngroup = bottom\n"
           "[boundary.top]\ntype = traction\ngroup = top\ntraction = 0, 20e6, 0\n"
           "history = ramp\nramp_time = 1e-6\n[fracture]\nmode = none\n"
           "[sensor.corner]\nposition = 8e-3, 4e-3, 0.5e-3\ndirection = 0, 1, 0\n"
           "[sensor.side]\nposition = 8e-3, 2e-3, 0.25e-3\ndirection = 1, 0, 0\n"
           "[run]\nend_time = 4e-6\nthreads = 1\n[output]\nframe_interval = 2e-6\n"
           "[render]\ntimes = 2e-6, 4e-6\nfields = sigma1\nwidth = 320\nheight = 160\n";
  }
  const std::string scene = quote((dir / "box.ini").string());
  const fs::path serial = dir / "serial";
  ASSERT_EQ(shell(quote(BRITTLE_EXE) + " run " + scene + " --out " + quote(serial.string()),
                  dir / "serial.log"),
            0)
      << read_text(dir / "serial.log");
  const nlohmann::json s = nlohmann::json::parse(read_text(serial / "summary.json"));
  EXPECT_GT(s.at("external_work").get<double>(), 0.0) << "the traction on 'top' acted";
  EXPECT_GT(s.at("tets").get<long>(), 500);
  const std::string sensors = read_text(serial / "sensors.csv");
  EXPECT_GT(std::count(sensors.begin(), sensors.end(), '\n'), 50) << "a row per step";
  const nlohmann::json where = nlohmann::json::parse(read_text(serial / "sensors.json"));
  EXPECT_NE(where.at(0).at("node"), where.at(1).at("node"));
  EXPECT_GT(std::abs(where.at(0).at("dominant_frequency").get<double>()), 0.0);
  std::vector<fs::path> pngs;
  for (const auto& png : fs::recursive_directory_iterator(serial / "render"))
    if (png.path().extension() == ".png") pngs.push_back(fs::relative(png.path(), serial));
  ASSERT_EQ(pngs.size(), 2u);
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(ranks);
    const fs::path out = dir / ("np" + std::to_string(ranks));
    const fs::path log = dir / ("np" + std::to_string(ranks) + ".log");
    ASSERT_EQ(shell(mpiexec(ranks) + " run " + scene + " --out " + quote(out.string()), log), 0)
        << read_text(log);
    for (const char* file : {"energies.csv", "sensors.csv", "spectra.csv", "sensors.json"})
      EXPECT_TRUE(read_text(out / file) == read_text(serial / file)) << file;
    for (const fs::path& png : pngs)
      EXPECT_TRUE(read_text(out / png) == read_text(serial / png)) << png;
  }
}

/// `mpirun -np 3 brittle run --dry-run`: rank 0 prints the serial estimates and every rank's
/// part (cells, nodes, neighbours, memory); nothing is written.
TEST(Mpi, DryRunReportsEveryRanksPart) {
  TempDir dir;
  const std::string scene = quote(std::string(BRITTLE_SOURCE_DIR) + "/scenes/cm.ini");
  const fs::path out = dir / "out";
  ASSERT_EQ(shell(mpiexec(3) + " run " + scene + " --dry-run --out " + quote(out.string()),
                  dir / "log"),
            0)
      << read_text(dir / "log");
  const std::string text = read_text(dir / "log");
  EXPECT_TRUE(contains(text, "14676 tets")) << text;
  EXPECT_TRUE(contains(text, "over 3 ranks")) << text;
  std::istringstream lines(text);
  long own = 0;
  int rows = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream row(line);
    int rank = -1;
    long cells = 0;
    if (line.ends_with(" GB") && (row >> rank >> cells) && rank == rows) ++rows, own += cells;
  }
  EXPECT_EQ(rows, 3) << text;
  EXPECT_EQ(own, 14676) << "every tet owned once";
  EXPECT_FALSE(fs::exists(out));
}

/// Per rank: the sizes of the allocations it made (tests/support/alloc_log.cpp's files).
std::map<int, std::vector<std::size_t>> allocations(const fs::path& dir) {
  std::map<int, std::vector<std::size_t>> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::istringstream in(read_text(entry.path()));
    int rank = -1;
    in >> rank;
    for (std::size_t n; in >> n;) out[rank].push_back(n);
  }
  return out;
}

/// How many of `sizes` are an array of the whole grid: a whole number of 1 to 72 bytes (a
/// char to 9 doubles) per node or per cell of it, or per one more (CSR starts).
long whole_grid_arrays(const std::vector<std::size_t>& sizes, long nodes, long cells) {
  long n = 0;
  for (std::size_t size : sizes)
    for (long count : {nodes, cells, nodes + 1, cells + 1})
      if (size % count == 0 && size / count >= 1 && size / count <= 72) {
        ++n;
        break;
      }
  return n;
}

/// Issue 27, item 2: `brittle partition --out` cuts the mesh into parts, and `mpirun -np N
/// brittle run --set mesh.parts=DIR/parts_N` reads one per rank: the serial bits, and no rank
/// allocates an array of the whole grid's size. The same run given the whole mesh is the
/// control that the check sees such arrays (every rank holds the whole mesh there). Pieces of
/// another rank count, and a serial run, are refused with one line.
TEST(Mpi, PartitionedMeshRunHoldsNoWholeGridArray) {
  if (brittle_test::kSanitized) GTEST_SKIP() << "AddressSanitizer has its own allocator";
  TempDir dir;
  const std::string scenes = std::string(BRITTLE_SOURCE_DIR) + "/scenes/";
  const std::string scene = quote(scenes + "cm.ini") + " " + quote(scenes + "branching.ini") +
                            " --set run.end_time=10e-6 --set run.threads=1 "
                            "--set output.frame_interval=5e-6";
  const fs::path pieces = dir / "pieces";
  ASSERT_EQ(shell(quote(BRITTLE_EXE) + " partition " + quote(scenes + "cm.ini") +
                      " --ranks 2 --out " + quote(pieces.string()),
                  dir / "partition.log"),
            0)
      << read_text(dir / "partition.log");
  ASSERT_TRUE(fs::exists(pieces / "parts_2/part_1.vtu"));
  const std::string parts = " --set mesh.parts=" + quote((pieces / "parts_2").string());
  for (const char* run : {"parts", "whole"}) {
    fs::create_directories(dir / (std::string(run) + "_alloc"));
    const std::string log =
        "BRITTLE_ALLOC_LOG=" + quote((dir / (std::string(run) + "_alloc")).string()) +
        " LD_PRELOAD=" + quote(BRITTLE_ALLOC_LOG_LIB) + " ";
    ASSERT_EQ(
        shell(log + mpiexec(2) + " run " + scene + (run == std::string("parts") ? parts : "") +
                  " --out " + quote((dir / run).string()),
              dir / (std::string(run) + ".log")),
        0)
        << read_text(dir / (std::string(run) + ".log"));
  }
  for (const char* file :
       {"energies.csv", "events.csv", "frames/frame_0002_r1.vtu", "frames/links_0002_r0.vtp"})
    EXPECT_TRUE(read_text(dir / "parts" / file) == read_text(dir / "whole" / file)) << file;
  const nlohmann::json s = nlohmann::json::parse(read_text(dir / "parts/summary.json"));
  const long nodes = s.at("nodes").get<long>(), cells = s.at("tets").get<long>();
  EXPECT_EQ(cells, 14676);
  const auto with_parts = allocations(dir / "parts_alloc");
  const auto with_whole = allocations(dir / "whole_alloc");
  ASSERT_EQ(with_parts.size(), 2u);
  ASSERT_EQ(with_whole.size(), 2u);
  for (const auto& [rank, sizes] : with_parts) {
    EXPECT_EQ(whole_grid_arrays(sizes, nodes, cells), 0) << "rank " << rank;
    EXPECT_GT(sizes.size(), 100u) << "rank " << rank << ": the log saw the allocations";
  }
  for (const auto& [rank, sizes] : with_whole)
    EXPECT_GT(whole_grid_arrays(sizes, nodes, cells), 3) << "rank " << rank << " (the control)";

  // Another rank count's pieces, and a serial run: refused with one line naming the key.
  ASSERT_NE(
      shell(mpiexec(3) + " run " + scene + parts + " --out " + quote((dir / "three").string()),
            dir / "three.log"),
      0);
  EXPECT_TRUE(contains(read_text(dir / "three.log"), "mpirun -np 3: parts_3"))
      << read_text(dir / "three.log");
  ASSERT_EQ(shell(quote(BRITTLE_EXE) + " run " + scene + parts + " --out " +
                      quote((dir / "serial").string()),
                  dir / "serial.log"),
            2);
  EXPECT_TRUE(contains(read_text(dir / "serial.log"), "mesh.parts = "))
      << read_text(dir / "serial.log");
}

}  // namespace
}  // namespace brittle
