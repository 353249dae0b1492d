// Shared test fixtures: the paper's plate as a Scene, the paper's damage and link values, an
// observer that records every energy row, and a helper that runs a scene on a fresh mesh.
#pragma once

#include <sys/mount.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "plate_mesh.hpp"
#include "simulation.hpp"

namespace brittle::testing {

/// A tmpfs of `bytes` on a fresh directory: a full disk on demand. mounted() is false where
/// mounting is not permitted (not root, no CAP_SYS_ADMIN) and reason() says why: skip then.
/// Unmounted and removed when it goes out of scope, whatever the test did.
class SmallTmpfs {
 public:
  explicit SmallTmpfs(std::size_t bytes) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "brittle_tmpfs_XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      reason_ = std::strerror(errno);
      return;
    }
    path_ = pattern;
    const std::string options = "size=" + std::to_string(bytes);
    mounted_ = ::mount("tmpfs", path_.c_str(), "tmpfs", 0, options.c_str()) == 0;
    if (!mounted_) reason_ = std::strerror(errno);
  }
  ~SmallTmpfs() {
    if (mounted_) ::umount2(path_.c_str(), MNT_DETACH);
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  SmallTmpfs(const SmallTmpfs&) = delete;
  SmallTmpfs& operator=(const SmallTmpfs&) = delete;
  bool mounted() const { return mounted_; }
  const std::string& reason() const { return reason_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  bool mounted_ = false;
  std::string reason_;
};

/// The paper's plate on CM (scene defaults = paper values) at sigma / sigma_c = `load`, run
/// to `end_time`, no files written, no frames.
inline Scene plate_scene(double load, double end_time,
                         FractureParams::Mode mode = FractureParams::Mode::none) {
  Scene s;
  s.loading.sigma_over_sigmac = load;
  s.fracture.mode = mode;
  s.run.end_time = end_time;
  s.output.vtu = false;
  s.output.frame_interval = 0;
  return s;
}

/// The paper's damage (6.5)-(6.6): beta1 = 5e6 1/s; beta2, beta3 and Omega_d0 are defaults.
inline DamageParams paper_damage() {
  DamageParams d;
  d.beta1 = 5e6;
  return d;
}

/// The paper's rate parameter of the RD links (6.4) [s].
inline constexpr double kPaperAlpha = 9.35e-8;

/// Collects every energy row of a run.
struct EnergyLog : Observer {
  std::vector<Energies> rows;
  void on_energy(const Simulation&, const Energies& e) override { rows.push_back(e); }
};

struct PlateRun {
  RunSummary summary;
  std::vector<Energies> energies;
};

/// Runs `scene` on its generated plate mesh (no files written); a failed run throws.
inline PlateRun run_plate(const Scene& scene) {
  auto mesh = generate_plate_mesh(scene.geometry, scene.mesh);
  Simulation sim(scene, *mesh);
  EnergyLog log;
  PlateRun r;
  r.summary = sim.run({&log});
  r.energies = std::move(log.rows);
  return r;
}

inline double total_mass(const Grid& g) {
  double m = 0;
  for (vtkIdType i = 0; i < g.num_points(); ++i) m += g.mass()[i];
  return m;
}

inline Vec3 total_momentum(const Grid& g) {
  Vec3 p = Vec3::Zero();
  for (vtkIdType i = 0; i < g.num_points(); ++i) p += g.mass()[i] * Vec3(g.v() + 3 * i);
  return p;
}

/// The paper's plate at 0.9 sigma_c with fracture in `mode`, on a mesh of `mesh_size`.
inline Scene fracture_scene(FractureParams::Mode mode, double end_time, double mesh_size = 500e-6) {
  Scene s = plate_scene(0.9, end_time, mode);
  s.mesh.size = mesh_size;
  return s;
}

/// The node on y = 0 nearest x (reference), or -1.
inline vtkIdType node_on_midplane(const Grid& g, double x) {
  for (vtkIdType p = 0; p < g.num_points(); ++p)
    if (std::abs(g.X()[3 * p + 1]) < 1e-12 && std::abs(g.X()[3 * p] - x) < 0.6e-3) return p;
  return -1;
}

/// What a run on `threads` threads leaves, for the tests that compare thread counts bitwise.
struct ThreadRun {
  long splits = 0;
  std::vector<double> x, v, Omega;  ///< positions, velocities, damage at the end
  double tip_x = 0, tip_y = 0;
};

/// Runs `scene` on `mesh` with `threads` threads (no files written).
inline ThreadRun run_on_threads(Scene scene, vtkUnstructuredGrid& mesh, int threads) {
  scene.run.threads = threads;
  Simulation sim(scene, mesh);
  ThreadRun r;
  r.splits = sim.run({}).splits;
  const Grid& g = sim.grid();
  r.x.assign(g.x(), g.x() + 3 * g.num_points());
  r.v.assign(g.v(), g.v() + 3 * g.num_points());
  r.Omega.assign(g.damage(), g.damage() + g.num_cells());
  r.tip_x = sim.fracture().tip_x(), r.tip_y = sim.fracture().tip_y();
  return r;
}

}  // namespace brittle::testing
