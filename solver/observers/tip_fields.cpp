// The fields around the running crack tips (docs/branching.md): hoop stress from the element
// stresses (B.4), energy into crack growth per unit new area against 2 gamma (3.8), tip speed.
#include "tip_fields.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "error.hpp"
#include "material.hpp"
#include "output.hpp"
#include "plane.hpp"

namespace brittle {

StressProbe::StressProbe(std::vector<double> centroids, std::vector<double> volumes, double reach)
    : centroids_(std::move(centroids)), volumes_(std::move(volumes)), reach_(reach) {
  BRITTLE_CHECK(reach_ > 0 && centroids_.size() == 2 * volumes_.size(),
                "StressProbe: reach must be > 0 and centroids two per cell");
  for (std::size_t c = 0; c < volumes_.size(); ++c)
    buckets_[key(static_cast<long long>(std::floor(centroids_[2 * c] / reach_)),
                 static_cast<long long>(std::floor(centroids_[2 * c + 1] / reach_)))]
        .push_back(static_cast<int>(c));
}

bool StressProbe::stress_at(const double* stress, double x, double y, double out[3]) const {
  const long long i0 = static_cast<long long>(std::floor(x / reach_));
  const long long j0 = static_cast<long long>(std::floor(y / reach_));
  double sum[3] = {0, 0, 0}, v = 0;
  for (long long i = i0 - 1; i <= i0 + 1; ++i)
    for (long long j = j0 - 1; j <= j0 + 1; ++j) {
      const auto found = buckets_.find(key(i, j));
      if (found == buckets_.end()) continue;
      for (int c : found->second) {
        const double dx = centroids_[2 * c] - x, dy = centroids_[2 * c + 1] - y;
        if (dx * dx + dy * dy > reach_ * reach_) continue;
        const double* s = stress + 6 * c;
        sum[0] += volumes_[c] * s[0], sum[1] += volumes_[c] * s[1], sum[2] += volumes_[c] * s[3];
        v += volumes_[c];
      }
    }
  if (v <= 0) return false;
  for (int k = 0; k < 3; ++k) out[k] = sum[k] / v;
  return true;
}

HoopProfile hoop_profile(const StressProbe& probe, const double* stress, double x, double y,
                         double direction_deg, double radius, int samples) {
  constexpr double deg = std::numbers::pi / 180.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  HoopProfile p;
  p.theta_max_deg = p.sigma_max = p.sigma_ahead = nan;
  const double dx = std::cos(direction_deg * deg), dy = std::sin(direction_deg * deg);
  for (int k = 0; k < samples; ++k) {
    const double theta = -180.0 + 360.0 * (k + 1) / samples;  // (-180, 180]
    const double c = std::cos(theta * deg), s = std::sin(theta * deg);
    // e_r = c d + s n, e_theta = -s d + c n with n = (-dy, dx)
    const double er[2] = {c * dx - s * dy, c * dy + s * dx};
    const double et[2] = {-s * dx - c * dy, -s * dy + c * dx};
    double t[3];
    double sigma = nan;
    if (probe.stress_at(stress, x + radius * er[0], y + radius * er[1], t))
      sigma = et[0] * et[0] * t[0] + et[1] * et[1] * t[1] + 2 * et[0] * et[1] * t[2];
    p.theta_deg.push_back(theta);
    p.sigma.push_back(sigma);
    if (std::abs(theta) < 1e-9) p.sigma_ahead = sigma;
    // The front half; on a tie the angle nearest the direction (a symmetric field gives 0 or
    // the lobe at negative theta, which comes first).
    if (std::abs(theta) <= 90.0 + 1e-9 && std::isfinite(sigma) &&
        (!std::isfinite(p.sigma_max) || sigma > p.sigma_max ||
         (sigma == p.sigma_max && std::abs(theta) < std::abs(p.theta_max_deg))))
      p.sigma_max = sigma, p.theta_max_deg = theta;
  }
  return p;
}

double tip_direction_deg(const TipTrack& tip, double behind) {
  if (!tip.path.empty()) {
    const TipSample& head = tip.path.back();
    for (std::size_t i = tip.path.size(); i-- > 0;) {
      const double dx = head.x - tip.path[i].x, dy = head.y - tip.path[i].y;
      if (std::hypot(dx, dy) >= behind) return std::atan2(dy, dx) * 180.0 / std::numbers::pi;
    }
    const double dx = head.x - tip.x_start, dy = head.y - tip.y_start;
    if (std::hypot(dx, dy) >= behind) return std::atan2(dy, dx) * 180.0 / std::numbers::pi;
  }
  return std::isfinite(tip.start_angle_deg) ? tip.start_angle_deg : 0.0;
}

namespace {

/// The weight q of the domain integral at cell e's corners (1 inside r_in, 0 past r_out,
/// linear in r between); false when every corner has q = 0.
template <int Corners>
bool corner_weights(const JIntegralFields& f, vtkIdType e, double x, double y, double r_in,
                    double r_out, double q[Corners]) {
  const vtkIdType* n = f.cells + Corners * e;
  const double reach2 = r_out * r_out;
  bool any = false;
  for (int k = 0; k < Corners; ++k) {
    const double* p = f.X + 3 * n[k];
    const double r2 = (p[0] - x) * (p[0] - x) + (p[1] - y) * (p[1] - y);
    q[k] = r2 >= reach2 ? 0.0 : std::clamp((r_out - std::sqrt(r2)) / (r_out - r_in), 0.0, 1.0);
    any = any || q[k] > 0;
  }
  return any;
}

/// dynamic_j_integral over a 2D body's triangles: the same integrand in the plane, the
/// products of linear fields integrated exactly over a triangle, int a b dV = V / 12 (sum_k
/// a_k b_k + (sum_k a_k)(sum_k b_k)); W (B.2) of F = diag(I + H, lambda) with the plane
/// state's lambda (docs/j-integral.md, "Two dimensions").
JIntegral triangle_j_integral(const JIntegralFields& f, double x, double y, double phi,
                              double r_in, double r_out, double thickness) {
  const Eigen::Vector2d d(std::cos(phi), std::sin(phi));
  JIntegral out;
  for (vtkIdType e = 0; e < f.num_cells; ++e) {
    const vtkIdType* n = f.cells + 3 * e;
    double q[3];
    if (!corner_weights<3>(f, e, x, y, r_in, r_out, q)) continue;
    const double* D = f.Dm_inv + 9 * e;
    Eigen::Matrix2d Dm_inv, du, dv;
    Dm_inv << D[0], D[1], D[3], D[4];
    Eigen::RowVector2d dq;
    for (int k = 1; k < 3; ++k) {
      for (int i = 0; i < 2; ++i) {
        du(i, k - 1) =
            (f.x[3 * n[k] + i] - f.X[3 * n[k] + i]) - (f.x[3 * n[0] + i] - f.X[3 * n[0] + i]);
        dv(i, k - 1) = f.v[3 * n[k] + i] - f.v[3 * n[0] + i];
      }
      dq(k - 1) = q[k] - q[0];
    }
    const Eigen::Matrix2d H = du * Dm_inv;
    const Eigen::Vector2d grad_q = (dq * Dm_inv).transpose();
    const Eigen::Vector2d u_1 = H * d, v_1 = (dv * Dm_inv) * d;
    const double* s = f.stress + 6 * e;
    Eigen::Matrix2d sigma;
    sigma << s[0], s[3], s[3], s[1];
    const double V = f.V0[e], omega = f.omega ? f.omega[e] : 0.0;
    Eigen::Vector2d v_sum = Eigen::Vector2d::Zero(), qv_sum = v_sum, a_sum = v_sum, qa_sum = v_sum;
    double vv = 0, q_sum = 0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d vk(f.v[3 * n[k]], f.v[3 * n[k] + 1]);
      v_sum += vk, qv_sum += q[k] * vk, vv += vk.squaredNorm(), q_sum += q[k];
      if (f.a) {
        const Eigen::Vector2d ak(f.a[3 * n[k]], f.a[3 * n[k] + 1]);
        a_sum += ak, qa_sum += q[k] * ak;
      }
    }
    const double kinetic = 0.5 * f.rho0 * (vv + v_sum.squaredNorm()) / 12.0;  // mean of K
    const Eigen::Matrix2d F2 = Eigen::Matrix2d::Identity() + H;
    Mat3 F = Mat3::Zero();
    F.topLeftCorner<2, 2>() = F2;
    F(2, 2) = out_of_plane_stretch(f.plane, F2.determinant(), F2.squaredNorm(), f.K, f.mu);
    const double W = strain_energy_density(F, f.K, f.mu, omega);  // (B.2)
    out.ring += V * ((sigma * grad_q).dot(u_1) - (W + kinetic) * grad_q.dot(d));
    const Eigen::Vector2d int_qa = (V / 12.0) * (qa_sum + q_sum * a_sum);
    const Eigen::Vector2d int_qv = (V / 12.0) * (qv_sum + q_sum * v_sum);
    const double inertia = f.rho0 * (int_qa.dot(u_1) - int_qv.dot(v_1));
    out.inertia += inertia;
    if (q[0] == 1.0 && q[1] == 1.0 && q[2] == 1.0) out.inertia_inside += inertia;
  }
  out.ring /= thickness, out.inertia /= thickness, out.inertia_inside /= thickness;
  out.J = out.ring + out.inertia;
  return out;
}

}  // namespace

JIntegral dynamic_j_integral(const JIntegralFields& f, double x, double y, double direction_deg,
                             double r_in, double r_out, double thickness) {
  BRITTLE_CHECK(r_out > r_in && r_in >= 0 && thickness > 0,
                "dynamic_j_integral: need 0 <= r_in < r_out and thickness > 0, got r_in = ", r_in,
                ", r_out = ", r_out, ", thickness = ", thickness);
  const double phi = direction_deg * std::numbers::pi / 180.0;
  if (f.corners == 3) return triangle_j_integral(f, x, y, phi, r_in, r_out, thickness);
  const Vec3 d(std::cos(phi), std::sin(phi), 0.0);  // the 1-axis of the tip's frame
  JIntegral out;
  for (vtkIdType e = 0; e < f.num_cells; ++e) {
    const vtkIdType* n = f.cells + 4 * e;
    double q[4];
    if (!corner_weights<4>(f, e, x, y, r_in, r_out, q)) continue;
    // Gradients of the linear fields: grad(f)_j = sum_k (f_k - f_0) (Dm^-1)_kj.
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Dm_inv(f.Dm_inv + 9 * e);
    Mat3 du, dv;  // columns: corner k minus corner 0
    Eigen::RowVector3d dq;
    for (int k = 1; k < 4; ++k) {
      for (int i = 0; i < 3; ++i) {
        du(i, k - 1) =
            (f.x[3 * n[k] + i] - f.X[3 * n[k] + i]) - (f.x[3 * n[0] + i] - f.X[3 * n[0] + i]);
        dv(i, k - 1) = f.v[3 * n[k] + i] - f.v[3 * n[0] + i];
      }
      dq(k - 1) = q[k] - q[0];
    }
    const Mat3 H = du * Dm_inv;                       // u_i,j
    const Vec3 grad_q = (dq * Dm_inv).transpose();    // q_,j
    const Vec3 u_1 = H * d, v_1 = (dv * Dm_inv) * d;  // u_i,1 and u_i,t1
    const double* s = f.stress + 6 * e;
    Mat3 sigma;
    sigma << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
    const double V = f.V0[e], omega = f.omega ? f.omega[e] : 0.0;
    // Exact integrals over a tet of products of linear fields a, b with corner values a_k, b_k:
    // int a b dV = V / 20 (sum_k a_k b_k + (sum_k a_k)(sum_k b_k)).
    Vec3 v_sum = Vec3::Zero(), qv_sum = Vec3::Zero(), a_sum = Vec3::Zero(), qa_sum = Vec3::Zero();
    double vv = 0, q_sum = 0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Map<const Vec3> vk(f.v + 3 * n[k]);
      v_sum += vk, qv_sum += q[k] * vk, vv += vk.squaredNorm(), q_sum += q[k];
      if (f.a) {
        const Eigen::Map<const Vec3> ak(f.a + 3 * n[k]);
        a_sum += ak, qa_sum += q[k] * ak;
      }
    }
    const double kinetic = 0.5 * f.rho0 * (vv + v_sum.squaredNorm()) / 20.0;         // mean of K
    const double W = strain_energy_density(Mat3::Identity() + H, f.K, f.mu, omega);  // (B.2)
    // (sigma_ij u_i,1 - (W + K) delta_1j) q_,j
    out.ring += V * ((sigma * grad_q).dot(u_1) - (W + kinetic) * grad_q.dot(d));
    // rho (u_i,tt u_i,1 - u_i,t u_i,t1) q: u_i,1 and u_i,t1 constant in the cell
    const Vec3 int_qa = (V / 20.0) * (qa_sum + q_sum * a_sum);
    const Vec3 int_qv = (V / 20.0) * (qv_sum + q_sum * v_sum);
    const double inertia = f.rho0 * (int_qa.dot(u_1) - int_qv.dot(v_1));
    out.inertia += inertia;
    if (q[0] == 1.0 && q[1] == 1.0 && q[2] == 1.0 && q[3] == 1.0) out.inertia_inside += inertia;
  }
  out.ring /= thickness, out.inertia /= thickness, out.inertia_inside /= thickness;
  out.J = out.ring + out.inertia;
  return out;
}

namespace {

constexpr char kHeader[] =
    "time,tip,x,y,direction_deg,speed,hoop_theta_max_deg,hoop_max_over_sigmac,"
    "hoop_ahead_over_sigmac,G_new_area,G_tip_advance,two_gamma,fracture_energy,crack_area,"
    "crack_length,J,J_over_2gamma,J_inertia_inside,energy_row\n";
constexpr char kHoopHeader[] = "time,tip,theta_deg,sigma_theta_theta_over_sigmac,energy_row\n";

/// The rows of `path` after its header whose last column, the energy row, is below `rows` (a
/// resumed run keeps what was written for the rows before its checkpoint).
std::string rows_before(const std::string& path, long rows) {
  std::ifstream in(path);
  std::string line, kept;
  if (!std::getline(in, line)) return kept;
  while (std::getline(in, line)) {
    const std::size_t comma = line.rfind(',');
    if (comma == std::string::npos || std::strtol(line.c_str() + comma + 1, nullptr, 10) >= rows)
      break;
    kept += line + "\n";
  }
  return kept;
}

/// Path length the tip covered over the last `window` before t, divided by the window: from its
/// last sample at or before t - window (NaN while the tip is younger than the window). Its samples come in bursts
/// of splits, too few for a slope over a short window.
double recent_speed(const TipTrack& tip, double t, double window) {
  if (tip.arc.empty()) return 0;
  double arc_then = 0, t_then = tip.t_start;
  for (std::size_t i = tip.path.size(); i-- > 0;)
    if (tip.path[i].t <= t - window) {
      arc_then = tip.arc[i], t_then = tip.path[i].t;
      break;
    }
  if (!(t_then <= t - window) && !(tip.path.front().t <= t - window))  // younger than the window
    return std::numeric_limits<double>::quiet_NaN();
  return (tip.arc.back() - arc_then) / window;
}

}  // namespace

void TipFieldsWriter::ensure_probe(const Simulation& sim) {
  if (probe_) return;
  const Grid& grid = sim.grid();
  const double* X = grid.X();
  const vtkIdType* cells = grid.cells();
  std::vector<double> centroids(2 * static_cast<std::size_t>(grid.num_cells()));
  double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
  if (grid.corners() == 3) {  // a 2D body: its thickness is the elements' (mesh.thickness)
    for (vtkIdType e = 0; e < grid.num_cells(); ++e)
      for (int k = 0; k < 3; ++k) {
        const double* p = X + 3 * cells[3 * e + k];
        centroids[2 * e] += p[0] / 3.0, centroids[2 * e + 1] += p[1] / 3.0;
      }
    z_min = 0, z_max = sim.elements().thickness;
  } else {
    for (vtkIdType e = 0; e < grid.num_cells(); ++e)
      for (int k = 0; k < 4; ++k) {
        const double* p = X + 3 * cells[4 * e + k];
        centroids[2 * e] += 0.25 * p[0], centroids[2 * e + 1] += 0.25 * p[1];
        z_min = std::min(z_min, p[2]), z_max = std::max(z_max, p[2]);
      }
  }
  h_ = sim.fronts().join() / 4.0;  // the typical element size (Simulation: join = 4 h)
  thickness_ = z_max > z_min ? z_max - z_min : 1.0;
  probe_ = std::make_unique<StressProbe>(std::move(centroids), sim.elements().V0,
                                         kReachElements * h_);
}

void TipFieldsWriter::on_start(const Simulation& sim) { ensure_probe(sim); }

void TipFieldsWriter::on_resume(const Simulation& sim) {
  const long rows = sim.progress().energy_rows;
  rows_ = rows_before(directory_ + "/tip_fields.csv", rows);
  hoop_rows_ = rows_before(directory_ + "/tip_hoop.csv", rows);
  // The energy window goes on from the rows kept: their raw columns (written to round-trip).
  std::istringstream in(rows_);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) v.push_back(std::strtod(c.c_str(), nullptr));
    if ((v.size() == 16 || v.size() == 19) && (history_.empty() || history_.back().t < v[0]))
      history_.push_back({v[0], v[12], v[13], v[14]});
  }
}

void TipFieldsWriter::on_step(const Simulation& sim) {
  // J needs u_tt. The nodal forces miss the links' (they act in sub-steps), so the
  // acceleration is the velocity change over the step before a row: with the velocity-Verlet
  // step, (v_n - v_(n-1)) / dt = (a_(n-1) + a_n) / 2, every force included, off a_n by
  // dt/2 da/dt (dt ~ 0.05 us against the ~0.1 us an element's field takes to change). The
  // copies are made only over the steps just before a row is due (Simulation::run: at
  // t >= next - dt/2), not every step.
  const double t = sim.time(), dt = sim.dt();
  if (t + 2.5 * dt < next_row_) return;
  std::swap(v_now_, v_before_);
  t_before_ = t_now_;
  const Grid& grid = sim.grid();
  v_now_.assign(grid.v(), grid.v() + 3 * grid.num_points());
  t_now_ = t;
}

void TipFieldsWriter::on_energy(const Simulation& sim, const Energies& e) {
  ensure_probe(sim);
  next_row_ = e.time + sim.scene().output.energy_interval;
  const CrackFronts& fronts = sim.fronts();
  const double t = e.time;
  std::vector<int> running;
  for (std::size_t i = 0; i < fronts.tips().size(); ++i) {
    const TipTrack& tip = fronts.tips()[i];
    if (tip.active && !tip.path.empty() && tip.path.back().t >= t - kRunningWindow)
      running.push_back(static_cast<int>(i));
  }
  if (running.empty()) return;  // (the window below spans the rows written: a resume's too)
  // Energy into crack growth: what the links hold and have dissipated (2.7)-(3.3); crack area
  // made (one face: A_c counts both); crack length: every tip's path length.
  double length = 0;
  for (const TipTrack& tip : fronts.tips())
    if (!tip.arc.empty()) length += tip.arc.back();
  history_.push_back({t, e.cohesive_dissipated + e.cohesive_stored,
                      0.5 * sim.fracture().crack_area(), length});
  const Flux& now = history_.back();
  std::size_t back = history_.size() - 1;
  while (back > 0 && history_[back - 1].t >= t - kFluxWindow * (1 + 1e-9)) --back;
  if (back > 0) --back;  // the row at or just before the window's start
  const Flux& then = history_[back];
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double dE = now.fracture_energy - then.fracture_energy;
  const double dA = now.crack_area - then.crack_area;
  const double dL = now.tip_length - then.tip_length;
  const double G_area = dA > 0 ? dE / dA : nan;
  const double G_advance = dL > 0 ? dE / (thickness_ * dL) : nan;
  const double sigma_c = sim.scene().material.sigma_c;
  const double two_gamma = 2.0 * sim.scene().material.gamma;
  const long energy_row = sim.progress().energy_rows;

  // The fields J reads; the acceleration as above, zero at a node split in the last step (no
  // velocity before) and on a row not preceded by two copied steps (the first after a resume).
  const Grid& grid = sim.grid();
  const ElasticConstants& c = sim.constants();
  JIntegralFields fields;
  fields.X = grid.X(), fields.x = grid.x(), fields.v = grid.v();
  fields.cells = grid.cells(), fields.num_cells = grid.num_cells();
  fields.stress = grid.stress(), fields.omega = grid.damage();
  fields.Dm_inv = sim.elements().Dm_inv.data(), fields.V0 = sim.elements().V0.data();
  fields.rho0 = c.rho0, fields.K = c.K, fields.mu = c.mu;
  fields.corners = grid.corners(), fields.plane = sim.scene().material.plane;
  if (t_now_ == t && t_before_ >= 0 && t_before_ < t_now_) {
    acceleration_.resize(v_now_.size());
    const double inv_dt = 1.0 / (t_now_ - t_before_);
    for (std::size_t i = 0; i < v_now_.size(); ++i)
      acceleration_[i] = i < v_before_.size() ? (v_now_[i] - v_before_[i]) * inv_dt : 0.0;
    fields.a = acceleration_.data();
  }

  std::ostringstream row, hoop;
  hoop << std::setprecision(6);
  for (int id : running) {
    const TipTrack& tip = fronts.tips()[static_cast<std::size_t>(id)];
    const TipSample head = fronts.head(id);
    const double direction = tip_direction_deg(tip, sim.fronts().join());
    const double speed = recent_speed(tip, t, kSpeedWindow);
    const HoopProfile p = hoop_profile(*probe_, sim.grid().stress(), head.x, head.y, direction,
                                       kRadiusElements * h_, kSamples);
    const JIntegral J = dynamic_j_integral(fields, head.x, head.y, direction, kJInnerRadius,
                                           kJOuterRadius, thickness_);
    row << std::setprecision(17) << t << std::setprecision(10) << ',' << id << ',' << head.x << ','
        << head.y << ',' << direction << ',' << speed << ',' << p.theta_max_deg << ','
        << p.sigma_max / sigma_c << ',' << p.sigma_ahead / sigma_c << ',' << G_area << ','
        << G_advance << ',' << two_gamma << ',' << std::setprecision(17) << now.fracture_energy
        << ',' << now.crack_area << ',' << now.tip_length << ',' << std::setprecision(10) << J.J
        << ',' << J.J / two_gamma << ',' << J.inertia_inside << ',' << energy_row << '\n';
    for (std::size_t k = 0; k < p.theta_deg.size(); ++k)
      hoop << t << ',' << id << ',' << p.theta_deg[k] << ',' << p.sigma[k] / sigma_c << ','
           << energy_row << '\n';
  }
  rows_ += row.str();
  hoop_rows_ += hoop.str();
}

void TipFieldsWriter::on_finish(const Simulation&, const RunSummary&) {
  write_file_atomically(directory_ + "/tip_fields.csv", kHeader + rows_);
  write_file_atomically(directory_ + "/tip_hoop.csv", kHoopHeader + hoop_rows_);
}

}  // namespace brittle
