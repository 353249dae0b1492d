// The scene: every input of a run, typed and in SI units. Filled and validated by app/
// (INI files + --set), consumed by the solver. Defaults are the paper's values (SPEC 8).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace brittle {

struct MaterialParams {
  double rho0 = 1180.0;     ///< reference density [kg/m^3]
  double E = 3.09e9;        ///< Young's modulus [Pa]
  double nu = 0.35;         ///< Poisson's ratio [-]
  double sigma_c = 75e6;    ///< tensile strength [Pa]
  double gamma = 150.0;     ///< surface energy per unit reference area [N/m]
  double zeta1 = 0.1;       ///< normalized dilatational damping (B.5) [-]
  double zeta2 = 0.1;       ///< normalized distortional damping (B.5) [-]
  /// Statistical strength (docs/branching.md): 0 = every node breaks at sigma_c (the paper);
  /// m > 0 = each node's strength is a Weibull sample of modulus m and mean sigma_c, drawn
  /// from its reference position and strength_seed.
  double weibull_modulus = 0.0;
  int strength_seed = 1;    ///< seed of the per-node strengths [-]
  /// A 2D body's out-of-plane state (mesh.dimension = 2, docs/model.md "Two dimensions"):
  /// strain, F33 = 1; stress, F33 such that T33 = 0, solved per element.
  enum class Plane { strain, stress };
  Plane plane = Plane::strain;
};

/// A notch cut into the generated plate through its thickness ([notch.NAME], docs/scenes.md):
/// from `start` (on the plate's outline) along `direction` for `length`; `opening` wide at
/// the start and closing to a point at the tip (wedge) or `opening` wide all along (slot).
struct NotchParams {
  enum class Shape { wedge, slot };
  std::string name;
  double start[2] = {0, 0};      ///< x, y [m]
  double direction[2] = {1, 0};  ///< unit vector in the plate's plane
  double length = 0;             ///< [m]
  double opening = 0;            ///< [m]
  Shape shape = Shape::wedge;
};

/// The notched plate of SPEC 1: x in [0, L], y in [-H/2, H/2], z in [0, T].
struct GeometryParams {
  double L = 32e-3;            ///< length along x (crack direction) [m]
  double H = 16e-3;            ///< height along y (loading direction) [m]
  double T = 0.5e-3;           ///< thickness along z [m]
  double notch_depth = 4e-3;   ///< a: wedge notch depth, tip at (a, 0) [m]; 0 = no notch
  double notch_base = 0.2e-3;  ///< b: notch opening at x = 0 [m]
  /// [notch.NAME] sections; when any is given they replace the wedge above.
  std::vector<NotchParams> notches;
};

struct MeshParams {
  std::string file;          ///< .msh or .vtu to read instead of generating (empty = generate)
  /// A directory of partitioned-mesh pieces (`brittle partition --out`): each rank of
  /// `mpirun -np N brittle run` reads its own part_R.vtu instead of the whole mesh.
  std::string parts;
  /// 3: tets; 2: triangles in the x-y plane, prisms of `thickness` (issue 53).
  int dimension = 3;
  double thickness = 0.0;    ///< a 2D body's thickness [m] (0 = geometry.T)
  double size = 500e-6;      ///< target element size h away from the band [m]
  double band = 0.0;         ///< half-width of the refined band |y| < band (0 = none) [m]
  double band_size = 0.0;    ///< element size inside the band (0 = size) [m]
  int layers = 1;            ///< element layers through the thickness
  /// Nodal perturbation: nodes off the lateral boundary move in x-y by up to this fraction of
  /// their shortest in-plane edge (0 = none; at most 0.3); perturb_seed draws the moves.
  double perturb = 0.0;
  int perturb_seed = 1;
  /// Gmsh's 2D algorithm for the plate's outline, extruded through the thickness (docs/mesh.md):
  /// Frontal-Delaunay (Gmsh's default, near-equilateral rows), Delaunay, MeshAdapt.
  enum class Algorithm { frontal_delaunay, delaunay, meshadapt };
  Algorithm algorithm = Algorithm::frontal_delaunay;
  /// Refuse a generated mesh whose estimated tet count exceeds this (docs/scenes.md, guards).
  double max_elements = 10e6;
};

/// Cells of the generated plate (tets; triangles in 2D), estimated before meshing: the plate's area in equilateral
/// triangles of the local size (band, linear transition over a further band width, the rest),
/// 3 tets per prism, `layers` prisms per triangle. Within 6 % of Gmsh's counts for CM, RM and a
/// 1.8 M-tet plate.
inline double estimated_tets(const GeometryParams& g, const MeshParams& m) {
  const double per_area = 4.0 / std::sqrt(3.0);  // triangles per h^2 of area
  const double band_size = m.band_size > 0 ? m.band_size : m.size;
  const double band = m.band > 0 ? std::min(m.band, 0.5 * g.H) : 0.0;
  const double transition = std::min(band, std::max(0.5 * g.H - band, 0.0));
  const double mid = 0.5 * (band_size + m.size);
  const double rest = std::max(g.H - 2 * band - 2 * transition, 0.0);
  const double triangles = per_area * g.L *
                           (2 * band / (band_size * band_size) + 2 * transition / (mid * mid) +
                            rest / (m.size * m.size));
  return m.dimension == 2 ? triangles : 3.0 * m.layers * triangles;  // (2D: the triangles)
}

struct LoadingParams {
  /// Exactly one of the two is set (the other NaN).
  double sigma_over_sigmac = std::numeric_limits<double>::quiet_NaN();
  double sigma = std::numeric_limits<double>::quiet_NaN();  ///< [Pa]
  double stress(const MaterialParams& m) const {
    return std::isnan(sigma) ? sigma_over_sigmac * m.sigma_c : sigma;
  }
};

/// Node splitting and nodal cohesive forces (SPEC 5). sigma_c and gamma are material keys.
struct FractureParams {
  enum class Mode { none, straight, branching };
  Mode mode = Mode::none;          ///< none: no node breaks; straight: y = 0, x >= a only (6.7)
  /// How a node fails (docs/fracture-criteria.md): nodal_stress, the paper's (2.10)-(2.12);
  /// energy, the energy of a plane's tractions over a ball of radius epsilon against 2 gamma;
  /// facet, faces open when their traction reaches the strength, nodes split where open faces
  /// cut their cells apart.
  /// nonlocal_facet, the facet criterion on stresses averaged over a ball of radius length;
  /// coupled_facet, a face opens at its strength if the energy over a ball of radius length
  /// reaches 2 gamma too (Leguillon); recovered_facet, the facet criterion on the stress
  /// recovered over each node's patch (Zienkiewicz-Zhu).
  enum class Criterion {
    nodal_stress, energy, facet, nonlocal_facet, coupled_facet, recovered_facet
  };
  Criterion criterion = Criterion::nodal_stress;
  double epsilon = 0.0;  ///< the energy criterion's length [m]; 0 = 3 x the median element size
  /// The nonlocal facet criterion's material length l [m]: stresses are averaged over a ball
  /// of radius l (Bazant's bell); 0 = 0.367 E G_c / sigma_c^2 (nonlocal_facet_criterion.hpp).
  double length = 0.0;
  /// The facet criterion's shear weight: t_eff = sqrt(<t_n>^2 + t_s^2 / beta^2); 0 = t_n alone.
  double beta = 0.0;
  /// The facet criterion's link strength: traction, Akantu's extrinsic insertion (f0 = the
  /// effective traction each crack face reached when it opened, times its share of the face's
  /// area); imbalance, the paper's (2.6) (the force that holds the daughters together).
  enum class FacetLink { traction, imbalance };
  FacetLink facet_link = FacetLink::traction;
  double alpha = 0.0;              ///< rate parameter of (4.4) [s]; 0 = rate-independent (3.5)
  double n = 0.2;                  ///< exponent of (4.4)
  double speed_window_start = 10e-6;  ///< steady crack speed fitted from this time [s]
  double speed_edge_margin = 2e-3;    ///< ... until the tip is this close to x = L [m]
  /// Where nodes may break: x_min, x_max, y_min, y_max of the reference position [m];
  /// empty = anywhere (fixed nodes never break).
  std::vector<double> region;
  /// crack pattern: tracks shorter than this are spurs, not branches [m] (0 = the tracker's
  /// join distance, 4 typical element sizes)
  double min_branch_length = 0;
  /// crack tracker (docs/crack_fronts.md): a split within this in-plane distance of a tip or
  /// path belongs to that crack; two arms are a branching once twice this apart [m] (0 = 4
  /// typical element sizes)
  double track_join = 0;
};

/// Continuum damage (SPEC 6, paper section 5). beta1 = 0 switches it off.
struct DamageParams {
  double beta1 = 0.0;    ///< rate [1/s] (5.2); paper 5e6
  double beta2 = 10.0;   ///< (5.3)
  double beta3 = 0.95;   ///< threshold as a fraction of sigma_c (5.3)
  double Omega_d0 = std::numeric_limits<double>::quiet_NaN();  ///< NaN: from v_inf, v_R (6.6)
  double v_inf = 675.0;  ///< limiting crack speed of the Zhou fit [m/s] (1.1)
  double v_R = 906.0;    ///< Rayleigh speed the paper uses [m/s] (6.2)
  /// Omega_d0, or 1 - (v_inf / v_R)^2 (6.6) when not given.
  double limit() const {
    return std::isnan(Omega_d0) ? 1.0 - (v_inf / v_R) * (v_inf / v_R) : Omega_d0;
  }
  bool enabled() const { return beta1 > 0.0; }
};

/// Which nodes or boundary faces a boundary condition acts on: a box in reference coordinates
/// (bounds may be infinite; a small tolerance is added) or a physical group of a .msh mesh.
struct RegionParams {
  std::vector<double> box;  ///< x_min, x_max, y_min, y_max, z_min, z_max [m], or empty
  std::string group;        ///< physical group name, or empty
};

/// A scalar factor of time multiplying a load: constant (zero before `start`, a step), a linear
/// ramp from 0 at `start` to 1 at start + ramp_time, then held, or a table of (t, value)
/// pairs, linear in between and held beyond its ends.
struct TimeHistory {
  enum class Kind { constant, ramp, table };
  Kind kind = Kind::constant;
  double start = 0;      ///< [s]
  double ramp_time = 0;  ///< [s]
  std::vector<double> table;  ///< t0, f0, t1, f1, ...  (t ascending)
  double at(double t) const;
};

/// One [boundary.NAME] section (docs/scenes.md): fixed components, a prescribed velocity, or a
/// traction (nominal, per unit reference area, fixed direction) on the region's boundary faces.
struct BoundaryParams {
  enum class Type { fixed, velocity, traction };
  std::string name;
  Type type = Type::fixed;
  RegionParams region;
  bool components[3] = {true, true, true};  ///< fixed / velocity: which of x, y, z
  double value[3] = {0, 0, 0};              ///< velocity [m/s] or traction [Pa]
  TimeHistory history;
};

/// One [initial.NAME] section: an initial velocity of the nodes in a region.
struct InitialVelocityParams {
  std::string name;
  RegionParams region;
  double velocity[3] = {0, 0, 0};  ///< [m/s]
};

/// The state at t = 0: the paper's uniaxial pre-stress (B.6)-(B.9) of [loading], or at rest;
/// initial velocities on top. With the pre-stress and no [boundary.*] section, the edges
/// y = +-H/2 are held (the paper's plate).
/// An acoustic-emission sensor (docs/acoustic_emission.md): the node nearest `position`
/// records its velocity along `direction` every step.
struct SensorParams {
  std::string name;
  double position[3] = {0, 0, 0};   ///< [m], reference; put it on the plate's surface
  double direction[3] = {0, 1, 0};  ///< unit vector: the surface normal for a transducer
};

struct InitialParams {
  enum class State { prestress, rest };
  State state = State::prestress;
  std::vector<InitialVelocityParams> velocities;
};

struct RunParams {
  double end_time = 30e-6;  ///< simulated time [s]
  double cfl = 0.5;         ///< fraction of the stable time step
  /// Where the stable step comes from (docs/model.md, "Stable step"): the elements' smallest
  /// altitudes (the default) or the nodal bound of the grid's largest frequency (issue 38).
  enum class StepBound { altitude, nodal };
  StepBound step_bound = StepBound::altitude;
  /// Mass scaling (issue 38; docs/performance.md): elements whose altitude-bound step at cfl
  /// 0.5 is below this get the density that brings it to this [s] (0 = none, the default).
  double mass_scaling = 0;
  int threads = 0;          ///< OpenMP threads (0 = all cores)
  /// Stop once a crack from a notch has reached the plate's outer boundary (CutThrough).
  bool stop_when_cut_through = true;
};

struct OutputParams {
  std::string directory = "out";      ///< where frames, CSV and summary go
  double frame_interval = 1e-6;       ///< VTU frame every this much simulated time [s] (0 = none)
  std::vector<double> frame_times;    ///< explicit frame times [s]; overrides frame_interval
  bool vtu = true;                    ///< write VTU frames + PVD
  double energy_interval = 0.1e-6;    ///< energies.csv row every this much simulated time [s]
  double imbalance_warning = 0.02;    ///< warn once when |E(t) - E(0)| / E(0) exceeds this
  /// checkpoint.bin every this much simulated time, and at the end (0 = only when stopped)
  double checkpoint_interval = 0;
};

/// PNG frames of the live grid, rendered off-screen by render/ (docs/rendering.md).
struct RenderParams {
  /// Which fields to render: sigma1 (sigma1/sigma_c), damage (Omega) and/or crack.
  static constexpr const char* default_fields[] = {"sigma1", "damage"};
  std::vector<double> times;  ///< render during the run at these times [s] (empty = none)
  std::vector<std::string> fields = std::vector<std::string>(default_fields, default_fields + 2);
  int width = 600, height = 400;             ///< PNG size [px]
  double sigma1_min = 0, sigma1_max = 1.2;   ///< fixed colour range of sigma1/sigma_c
  double damage_min = 0, damage_max = 0.45;  ///< fixed colour range of Omega
  double magnification = 1;  ///< displacement magnification (1 = the true deformed shape)
  double zoom = 1;           ///< camera zoom about the plate centre (1 = whole plate)
  /// Colour ramp of sigma1 and Omega: jet (blue -> red, the paper's) or viridis (perceptually
  /// uniform, matplotlib's); docs/rendering.md.
  enum class Colormap { jet, viridis };
  Colormap colormap = Colormap::jet;
  std::string directory;     ///< where PNGs go (empty = <output.directory>/render)
};

struct Scene {
  MaterialParams material;
  GeometryParams geometry;
  MeshParams mesh;
  LoadingParams loading;
  InitialParams initial;
  std::vector<BoundaryParams> boundaries;
  std::vector<SensorParams> sensors;
  FractureParams fracture;
  DamageParams damage;
  RunParams run;
  OutputParams output;
  RenderParams render;
  std::vector<std::string> sources;  ///< the INI files and --set overrides it came from
  /// The named sections ([boundary.NAME], [notch.NAME], ...) as the sources gave them, merged:
  /// kind, name and (key, text) pairs (app/scene_options.cpp, scene_ini).
  struct NamedText {
    std::string kind, name;
    std::vector<std::pair<std::string, std::string>> keys;
  };
  std::vector<NamedText> named_sections;
  /// Every key as "section.key" (or "kind.NAME.key") and its value text, as the run's scene.ini
  /// gives them (set by the application before the run: summary.json "scene").
  std::vector<std::pair<std::string, std::string>> resolved;
};

}  // namespace brittle
