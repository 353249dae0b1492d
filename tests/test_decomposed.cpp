// A decomposed run steps with the serial run's bits (issue 14, docs/parallel.md). Run by ctest
// under mpiexec with 1, 2 and 3 ranks: every rank steps the whole plate serially and its own
// part of it (solver/parallel/halo.hpp) side by side, and checks that its owned nodes and cells hold the
// serial bits after every stretch of steps, and that every rank knows every split, in the
// serial order with the serial node ids, and the energy budget has the serial bits.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "fixtures.hpp"
#include "halo.hpp"
#include "partition.hpp"
#include "plate_mesh.hpp"
#include "simulation.hpp"

namespace brittle {
namespace {

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int ranks() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

/// The paper's plate on CM (500 um) at 0.9 sigma_c.
Scene cm_scene(FractureParams::Mode mode, double end_time) {
  Scene s = testing::plate_scene(0.9, end_time, mode);
  s.mesh.size = 500e-6;
  s.run.threads = 1;
  return s;
}

/// What a decomposed run is checked for.
struct Crossings {
  long splits = 0;       ///< all splits
  long shared = 0;       ///< splits of a node whose cells lie in more than one part
  int owners = 0;        ///< parts whose nodes split
};

/// Steps `scene` serially and decomposed over the ranks with `cell_part` (empty: METIS) for
/// `checks` stretches of `steps` steps; after each, every owned node's x, v and mass, every
/// owned cell's stress and damage, and the split counts equal the serial run's, bit for bit.
Crossings expect_serial_bits(const Scene& scene, int checks, int steps,
                             std::vector<int> cell_part = {}) {
  auto mesh = generate_plate_mesh(scene.geometry, scene.mesh);
  Simulation serial(scene, *mesh);
  const Grid& whole = serial.grid();
  const GhostReach reach = ghost_reach(scene, grid_body_sizes(whole));  // the criterion's
  const Partition partition = cell_part.empty()
                                  ? partition_grid(whole, ranks(), reach)
                                  : partition_from(whole, std::move(cell_part), ranks(), reach);
  const LocalPart part = extract_part(whole, partition, rank());
  Simulation local(scene, *part.mesh);
  Halo halo(part);
  local.decompose(halo);
  EXPECT_EQ(local.dt(), serial.dt());
  Crossings seen;
  std::vector<int> owner_split(ranks(), 0);
  for (int check = 0; check < checks; ++check) {
    for (int s = 0; s < steps; ++s) {
      serial.step();
      local.step();
      for (const GlobalSplit& split : local.last_global_splits()) {
        std::vector<int> parts;
        for (vtkIdType c : split.b_cells) parts.push_back(partition.cell_part[c]);
        // the node's cells: those that took b and those that kept a
        for (vtkIdType c = 0; c < whole.num_cells(); ++c)
          for (int k = 0; k < 4; ++k)
            if (whole.cells()[4 * c + k] == split.a) parts.push_back(partition.cell_part[c]);
        std::sort(parts.begin(), parts.end());
        seen.shared += std::unique(parts.begin(), parts.end()) - parts.begin() > 1;
        if (split.a < static_cast<vtkIdType>(partition.node_owner.size()))
          owner_split[partition.node_owner[split.a]] = 1;
      }
    }
    SCOPED_TRACE(::testing::Message() << "rank " << rank() << " of " << ranks() << ", step "
                                      << serial.steps() << ", t = " << serial.time());
    const Grid& g = local.grid();
    EXPECT_EQ(local.time(), serial.time());
    EXPECT_EQ(local.dt(), serial.dt());
    EXPECT_EQ(local.fracture().splits(), serial.fracture().splits());
    EXPECT_EQ(local.fracture().crack_area(), serial.fracture().crack_area());
    EXPECT_EQ(halo.global_nodes(), whole.num_points());
    // the energy budget, every term (exact sums over each rank's nodes, cells and links)
    const Energies a = local.energies(), b = serial.energies();
    EXPECT_EQ(a.kinetic, b.kinetic);
    EXPECT_EQ(a.elastic, b.elastic);
    EXPECT_EQ(a.viscous_dissipated, b.viscous_dissipated);
    EXPECT_EQ(a.cohesive_stored, b.cohesive_stored);
    EXPECT_EQ(a.cohesive_dissipated, b.cohesive_dissipated);
    EXPECT_EQ(a.damage_dissipated, b.damage_dissipated);
    EXPECT_EQ(a.external_work, b.external_work);
    long mismatched = 0, owned = 0;
    for (vtkIdType i = 0; i < g.num_points(); ++i) {
      if (!halo.owned()[i]) continue;
      ++owned;
      const vtkIdType n = halo.global_node()[i];
      bool same = g.mass()[i] == whole.mass()[n];
      for (int k = 0; k < 3; ++k)
        same = same && g.x()[3 * i + k] == whole.x()[3 * n + k] &&
               g.v()[3 * i + k] == whole.v()[3 * n + k] &&
               g.X()[3 * i + k] == whole.X()[3 * n + k];
      if (!same && mismatched++ == 0)
        ADD_FAILURE() << "owned node " << n << " (local " << i << ") differs from the serial run";
    }
    for (vtkIdType e = 0; e < g.num_cells(); ++e) {
      if (!halo.owns_cell(e)) continue;
      const vtkIdType c = halo.global_cell()[e];
      bool same = g.damage()[e] == whole.damage()[c];
      for (int k = 0; k < 6; ++k) same = same && g.stress()[6 * e + k] == whole.stress()[6 * c + k];
      for (int k = 0; k < 4; ++k)  // the same corners, by global id
        same = same && halo.global_node()[g.cells()[4 * e + k]] == whole.cells()[4 * c + k];
      if (!same && mismatched++ == 0)
        ADD_FAILURE() << "owned cell " << c << " (local " << e << ") differs from the serial run";
    }
    EXPECT_EQ(mismatched, 0);
    // every node of the whole grid is owned by exactly one rank
    long all_owned = owned;
    MPI_Allreduce(MPI_IN_PLACE, &all_owned, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(all_owned, whole.num_points());
  }
  seen.splits = serial.fracture().splits();
  seen.owners = static_cast<int>(std::count(owner_split.begin(), owner_split.end(), 1));
  return seen;
}

/// A hand-made partition of the scene's plate: each cell goes to part(x, y) of its centroid.
template <class Part>
std::vector<int> parts_by_centroid(const Scene& scene, Part part) {
  auto mesh = generate_plate_mesh(scene.geometry, scene.mesh);
  const Grid whole(*mesh);
  std::vector<int> cell_part(whole.num_cells(), 0);
  for (vtkIdType e = 0; e < whole.num_cells(); ++e) {
    double x = 0, y = 0;
    for (int k = 0; k < 4; ++k) {
      x += 0.25 * whole.X()[3 * whole.cells()[4 * e + k]];
      y += 0.25 * whole.X()[3 * whole.cells()[4 * e + k] + 1];
    }
    cell_part[e] = part(x, y);
  }
  return cell_part;
}

/// Stripes `width` wide in x, dealt to the ranks in turn.
std::vector<int> stripes(const Scene& scene, double width) {
  return parts_by_centroid(scene, [width](double x, double) {
    return static_cast<int>(std::floor(x / width)) % ranks();
  });
}

/// Straight crack (6.7) on CM, METIS parts: 12 us, the crack well under way.
TEST(Decomposed, StraightCrackHasTheSerialBits) {
  const Crossings c = expect_serial_bits(cm_scene(FractureParams::Mode::straight, 1e-3), 6, 250);
  EXPECT_GT(c.splits, 20);
}

/// Branching, damage and rate-dependent links on CM: the paper's hardest setting.
Scene branching_scene() {
  Scene s = cm_scene(FractureParams::Mode::branching, 1e-3);
  s.fracture.alpha = testing::kPaperAlpha;
  s.damage = testing::paper_damage();
  return s;
}

/// ... on METIS parts.
TEST(Decomposed, BranchingDamageRateDependentLinksHaveTheSerialBits) {
  const Crossings c = expect_serial_bits(branching_scene(), 4, 350);
  EXPECT_GT(c.splits, 100);
  if (ranks() > 1) {
    EXPECT_GT(c.shared, 0) << "the crack should reach a partition boundary";
  }
}

/// ... on parts cut across the crack's path: stripes 2 mm wide in x, dealt to the ranks in
/// turn, so that the crack crosses a partition boundary every 2 mm and splits nodes on them
/// many times (counted), in every part.
TEST(Decomposed, CrackCrossingPartitionsManyTimesHasTheSerialBits) {
  const Scene s = branching_scene();
  const Crossings c = expect_serial_bits(s, 4, 350, stripes(s, 2e-3));
  EXPECT_GT(c.splits, 100);
  if (ranks() > 1) {
    EXPECT_GT(c.shared, 20) << "the crack should split nodes on partition boundaries many times";
    EXPECT_EQ(c.owners, ranks()) << "nodes of every part should split";
  }
  if (rank() == 0)
    std::cout << "[ crossing ] " << c.splits << " splits, " << c.shared
              << " of nodes whose cells lie in more than one part\n";
}

/// The same mechanisms on a 1 mm plate with 3 mm stripes, short: cheap enough to run under
/// the sanitizers (CI's debug build runs this one only).
TEST(Decomposed, CoarseBranchingRunHasTheSerialBits) {
  Scene s = branching_scene();
  s.mesh.size = 1e-3;
  const Crossings c = expect_serial_bits(s, 2, 150, stripes(s, 3e-3));
  EXPECT_GT(c.splits, 10);
  if (ranks() > 1) {
    EXPECT_GT(c.shared, 0) << "the crack should split nodes on partition boundaries";
  }
}

/// run.step_bound = nodal (a node's bound sums all its cells: an owned node's, in the serial
/// order; the minimum over owned nodes, reduced with its global id) and run.mass_scaling (each
/// cell scaled on its own, the report over owned cells in exact sums): the serial bits, the
/// serial step and the serial report (issue 52, item 3).
TEST(Decomposed, NodalStepBoundAndMassScalingHaveTheSerialBits) {
  Scene s = branching_scene();
  s.mesh.size = 1e-3;
  s.run.step_bound = RunParams::StepBound::nodal;
  s.run.cfl = 0.9;
  {  // a target above the smallest elements' step: some cells scaled
    auto mesh = generate_plate_mesh(s.geometry, s.mesh);
    s.run.mass_scaling = 1.3 * Simulation(s, *mesh).step_distribution().smallest;
  }
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  Simulation serial(s, *mesh);
  const LocalPart part = extract_part(serial.grid(), partition_grid(serial.grid(), ranks()), rank());
  Simulation local(s, *part.mesh);
  Halo halo(part);
  local.decompose(halo);
  const MassScaling &a = local.mass_scaling(), &b = serial.mass_scaling();
  EXPECT_GT(b.elements, 0);
  EXPECT_EQ(a.elements, b.elements);
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.added, b.added);
  EXPECT_EQ(a.largest, b.largest);
  EXPECT_EQ(a.element, b.element);
  EXPECT_EQ(local.dt(), serial.dt());
  const Crossings c = expect_serial_bits(s, 2, 150, stripes(s, 3e-3));
  EXPECT_GT(c.splits, 10);
}

/// The branching scene on a 1 mm mesh with `criterion` (a length of 2.5 mm where it takes one).
Scene criterion_scene(FractureParams::Criterion criterion) {
  Scene s = branching_scene();
  s.mesh.size = 1e-3;
  s.fracture.criterion = criterion;
  s.fracture.length = 2.5e-3;
  return s;
}

/// The facet criterion (issue 52, item 1): each face decided by the owner of its corner with
/// the smallest global id, the opened faces agreed over the ranks in the serial order, a
/// node's groups split by its owner, the splits shared in node order: the serial bits, on
/// stripes that the crack crosses.
TEST(Decomposed, FacetCriterionHasTheSerialBits) {
  const Scene s = criterion_scene(FractureParams::Criterion::facet);
  const Crossings c = expect_serial_bits(s, 2, 150, stripes(s, 3e-3));
  EXPECT_GT(c.splits, 10);
  if (ranks() > 1) {
    EXPECT_GT(c.shared, 0) << "the crack should split nodes on partition boundaries";
  }
}

/// The criteria that read past a node's cells (issue 52, item 2): a ball of 2.5 mm (nonlocal,
/// coupled), of 3 x the median element (energy) or a second ring (recovered) across stripes 3 mm
/// wide, so that the cells a face's owner reads lie on two or three ranks.
TEST(Decomposed, CriteriaThatReadFurtherHaveTheSerialBits) {
  using Name = FractureParams::Criterion;
  for (const Name name : {Name::nonlocal_facet, Name::coupled_facet, Name::recovered_facet,
                          Name::energy}) {
    SCOPED_TRACE(static_cast<int>(name));
    const Scene s = criterion_scene(name);
    const Crossings c = expect_serial_bits(s, 2, 150, stripes(s, 3e-3));
    EXPECT_GT(c.splits, 10);
  }
}

/// A part cut without the reach its criterion asks for is refused at the start, in one line.
TEST(Decomposed, PartWithoutTheCriterionsReachIsRefused) {
  const Scene s = criterion_scene(FractureParams::Criterion::nonlocal_facet);
  auto mesh = generate_plate_mesh(s.geometry, s.mesh);
  const Grid whole(*mesh);
  const LocalPart part = extract_part(whole, partition_grid(whole, ranks()), rank());
  Simulation local(s, *part.mesh);
  Halo halo(part);
  try {
    local.decompose(halo);
    ADD_FAILURE() << "a part of one ghost layer was taken for a ball of 2.5 mm";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1 layer(s) of ghost cells and 0 m"), std::string::npos)
        << e.what();
  }
}

/// Parts cut by hand along the crack plane: cells above y = 0 in part 0, below in the others
/// (split at x = L/2 for 3 ranks). The boundary runs through the notch tip and along the whole
/// straight crack: every split is of a node whose cells lie in two parts.
TEST(Decomposed, PartitionBoundaryThroughTheNotchTip) {
  const Scene s = cm_scene(FractureParams::Mode::straight, 1e-3);
  const double half = 0.5 * s.geometry.L;
  const Crossings c = expect_serial_bits(s, 3, 400, parts_by_centroid(s, [half](double x, double y) {
    return ranks() == 1 || y >= 0 ? 0 : ranks() == 2 || x < half ? 1 : 2;
  }));
  EXPECT_GT(c.splits, 20);
  if (ranks() > 1) {
    EXPECT_EQ(c.shared, c.splits) << "every split should be on the boundary";
  }
}

}  // namespace
}  // namespace brittle

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int failed = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return failed;
}
