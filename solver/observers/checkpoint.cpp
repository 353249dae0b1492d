// Checkpoint file and the state() of every class a step changes (docs/checkpoint.md).
//
// Layout: magic, format, brittle version, scene sources, the scene by section (to say which
// one differs), the mesh fingerprint, time and step, the state, and an FNV-1a checksum of all
// that precedes it. The state is each class's state(ar), in one order; a class that gains a
// member a step changes must add it there (the resume tests compare every output bitwise).
#include "checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <utility>

#include "simulation.hpp"

namespace fs = std::filesystem;

namespace brittle {

// ------------------------------------------------------------------------------------------
// state() of the classes a step changes
// ------------------------------------------------------------------------------------------

template <class Ar>
void RunProgress::state(Ar& ar) {
  io_all(ar, next_frame, next_energy, next_checkpoint, frames_written, energy_rows,
         imbalance_warned, max_relative_imbalance, warnings, wall_seconds);
}

namespace {
/// Every array of a vtkFieldData (point or cell data) as bytes, `tuples` tuples each.
template <class Ar>
void data_arrays(Ar& ar, vtkFieldData* data, vtkIdType tuples, const char* kind) {
  std::uint64_t count = data->GetNumberOfArrays();
  io(ar, count);
  BRITTLE_CHECK(count == static_cast<std::uint64_t>(data->GetNumberOfArrays()), ar.what(),
                ": the grid has other ", kind, " arrays than the checkpoint's");
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    vtkDataArray* a = vtkDataArray::SafeDownCast(data->GetAbstractArray(i));
    BRITTLE_ASSERT(a);
    std::string name = a->GetName() ? a->GetName() : "";
    std::uint64_t bytes_per_tuple = a->GetNumberOfComponents() * a->GetDataTypeSize();
    const std::string expected = name;
    const std::uint64_t expected_size = bytes_per_tuple;
    io_all(ar, name, bytes_per_tuple);
    BRITTLE_CHECK(name == expected && bytes_per_tuple == expected_size, ar.what(), ": ", kind,
                  " array '", name, "' does not match the grid's '", expected, "'");
    if constexpr (Ar::loading) {
      ar.check(tuples, bytes_per_tuple);
      a->SetNumberOfTuples(tuples);
    }
    ar.raw(static_cast<char*>(a->GetVoidPointer(0)), tuples * bytes_per_tuple);
    if constexpr (Ar::loading) a->Modified();
  }
}
}  // namespace

template <class Ar>
void Grid::state(Ar& ar) {
  std::uint64_t np = num_points_, nc = num_cells_;
  io_all(ar, np, nc);
  if constexpr (Ar::loading) {
    BRITTLE_CHECK(nc == static_cast<std::uint64_t>(num_cells_), ar.what(),
                  ": the checkpoint has ", nc, " cells, the mesh ", num_cells_);
    ar.check(np, 3 * sizeof(double));
    grid_->GetPoints()->SetNumberOfPoints(static_cast<vtkIdType>(np));
  }
  ar.raw(static_cast<double*>(grid_->GetPoints()->GetData()->GetVoidPointer(0)), 3 * np);
  data_arrays(ar, grid_->GetPointData(), static_cast<vtkIdType>(np), "point");
  data_arrays(ar, grid_->GetCellData(), static_cast<vtkIdType>(nc), "cell");
  ar.raw(grid_->GetCells()->GetConnectivityArray64()->GetPointer(0), corners_ * nc);
  if constexpr (Ar::loading) {
    refresh();
    for (vtkIdType i = 0; i < corners_ * num_cells_; ++i)
      BRITTLE_CHECK(conn_[i] >= 0 && conn_[i] < num_points_, ar.what(),
                    ": a cell refers to node ", conn_[i], " of ", num_points_);
    grid_->GetPoints()->Modified();
    grid_->GetCells()->Modified();
    mark_modified();
  }
}

template <class Ar>
void ForceAssembler::state(Ar& ar) {
  io_all(ar, blocks_, force_, viscous_work_, volume_, sigma1_bound_, alpha1_,
         node_start_, node_end_, node_entries_);
  if constexpr (Ar::loading) {  // the element buffer is filled on demand (recompute_block)
    ranges_ = 0;
    std::fill(stored_.begin(), stored_.end(), 0);
  }
}

template <class Ar>
void CohesiveLink::state(Ar& ar) {
  io_all(ar, a, b, f0, e0, A_c, delta_c, delta, delta_max, omega, f, dissipated, opening_rate,
         faces);
}

template <class Ar>
void CohesiveLinks::state(Ar& ar) {
  io_all(ar, links_, linked_, linked_nodes_, delta_start_, impulse_, removed_dissipated_);
  forget_groups();  // derived from the links (update_groups)
}

template <class Ar>
void Fracture::state(Ar& ar) {
  io_all(ar, root_, split_time_, splits_, crack_area_, tip_x_, tip_y_);
  if (criterion_) criterion_->state(ar);  // (its own: open faces, scratch marks)
}

template <class Ar>
void Damage::state(Ar& ar) {
  io_all(ar, step_index_, undamaged_energy_, evaluated_at_, block_cells_,
         touched_nodes_, touched_);
}

template <class Ar>
void Boundary::state(Ar& ar) {
  io_all(ar, traction_work_, reaction_work_);
}

template <class Ar>
void Halo::state(Ar& ar) {
  int rank = rank_, size = size_;
  io_all(ar, rank, size);
  BRITTLE_CHECK(rank == rank_ && size == size_, ar.what(), ": a piece of rank ", rank, " of ",
                size, ", read by rank ", rank_, " of ", size_);
  io_all(ar, owner_, global_nodes_, global_node_, owned_);
  if constexpr (Ar::loading) {
    BRITTLE_CHECK(owner_.size() == global_node_.size() && owned_.size() == global_node_.size() &&
                      global_node_.size() >= mesh_nodes_,
                  ar.what(), ": damaged (node tables)");
    split_local_.clear();
    for (std::size_t i = mesh_nodes_; i < global_node_.size(); ++i)
      split_local_[global_node_[i]] = static_cast<vtkIdType>(i);
  }
  std::uint64_t n = neighbours_.size();
  io(ar, n);
  if constexpr (Ar::loading) ar.check(n, 1), neighbours_.assign(n, Neighbour{});
  for (Neighbour& b : neighbours_) io_all(ar, b.rank, b.send, b.recv);
  if constexpr (Ar::loading) mark_received();
}

template <class Ar>
void Simulation::fields(Ar& ar, Halo* halo) {
  io_all(ar, time_, dt_, initial_dt_, steps_, dt_reductions_, substep_cap_steps_,
         damage_dissipated_, initial_energy_, energy_reference_, tip_samples_,
         events_, progress_);
  io_all(ar, grid_, assembler_, links_, fracture_, damage_, boundary_);
  if (halo) io(ar, *halo);  // a decomposed run's piece: this rank's ids and lists
}

template <class Ar>
void Simulation::state(Ar& ar) {
  fields(ar, halo_);
  if constexpr (Ar::loading) rebuild_fronts();
}

void Simulation::read_piece(StateReader& ar, Halo& halo) {
  BRITTLE_CHECK(!halo_ && steps_ == 0, ar.what(), ": read into a run that has started");
  fields(ar, &halo);
  BRITTLE_CHECK(ar.done(), ar.what(), ": damaged (bytes left after the state)");
}

// ------------------------------------------------------------------------------------------
// The scene, section by section (a resumed run must be the same run)
// ------------------------------------------------------------------------------------------

template <class Ar>
void io(Ar& ar, RegionParams& r) {
  io_all(ar, r.box, r.group);
}
template <class Ar>
void io(Ar& ar, NotchParams& n) {
  io_all(ar, n.name, n.start[0], n.start[1], n.direction[0], n.direction[1], n.length, n.opening,
         n.shape);
}
template <class Ar>
void io(Ar& ar, BoundaryParams& b) {
  io_all(ar, b.name, b.type, b.region, b.components[0], b.components[1], b.components[2],
         b.value[0], b.value[1], b.value[2], b.history.kind, b.history.start, b.history.ramp_time,
         b.history.table);
}
template <class Ar>
void io(Ar& ar, SensorParams& p) {
  io_all(ar, p.name, p.position[0], p.position[1], p.position[2], p.direction[0], p.direction[1],
         p.direction[2]);
}
template <class Ar>
void io(Ar& ar, InitialVelocityParams& v) {
  io_all(ar, v.name, v.region, v.velocity[0], v.velocity[1], v.velocity[2]);
}

namespace {

/// (section, bytes) of everything that shapes the run's results. run.end_time, run.threads
/// (results are bitwise the same for any count), output.directory and
/// output.checkpoint_interval may change on resume; the sources are the files' names only.
std::vector<std::pair<std::string, std::string>> scene_sections(Scene s) {
  std::vector<std::pair<std::string, std::string>> out;
  auto section = [&](const char* name, auto&&... fields) {
    StateWriter w;
    io_all(w, fields...);
    out.emplace_back(name, std::move(w.bytes()));
  };
  MaterialParams& m = s.material;
  section("material", m.rho0, m.E, m.nu, m.sigma_c, m.gamma, m.zeta1, m.zeta2, m.weibull_modulus,
          m.strength_seed);
  GeometryParams& g = s.geometry;
  section("geometry", g.L, g.H, g.T, g.notch_depth, g.notch_base, g.notches);
  MeshParams& me = s.mesh;
  section("mesh", me.file, me.size, me.band, me.band_size, me.layers, me.perturb,
          me.perturb_seed, me.algorithm);
  section("loading", s.loading.sigma_over_sigmac, s.loading.sigma);
  section("initial", s.initial.state, s.initial.velocities);
  section("boundary", s.boundaries);
  section("sensor", s.sensors);
  FractureParams& f = s.fracture;
  section("fracture", f.mode, f.alpha, f.n, f.speed_window_start, f.speed_edge_margin, f.region,
          f.min_branch_length, f.criterion, f.epsilon, f.beta, f.track_join, f.facet_link,
          f.length);
  DamageParams& d = s.damage;
  section("damage", d.beta1, d.beta2, d.beta3, d.Omega_d0, d.v_inf, d.v_R);
  section("run", s.run.cfl, s.run.stop_when_cut_through, s.run.step_bound, s.run.mass_scaling);
  OutputParams& o = s.output;
  section("output", o.frame_interval, o.frame_times, o.vtu, o.energy_interval,
          o.imbalance_warning);
  RenderParams& r = s.render;
  section("render", r.times, r.fields, r.width, r.height, r.sigma1_min, r.sigma1_max, r.damage_min,
          r.damage_max, r.magnification, r.zoom, r.colormap, r.directory);
  return out;
}

constexpr char kMagic[] = "brittle checkpoint\n";
constexpr std::uint32_t kFormat = 14;  // 2: exact energy sums; 3: cut-through and colormap keys;
                                       // 4: Weibull strength keys; 5: no element forces (the
                                       // next step recomputes them before any use); 6: blocks
                                       // with h_e for the two viscosities, no viscous powers;
                                       // 7: the piece count (decomposed runs' checkpoints);
                                       // 8: pieces without whole-grid node tables;
                                       // 9: fracture.criterion, epsilon, mesh.perturb keys
                                       // and the nodes' split times; 10: fracture.beta,
                                       // track_join, mesh.algorithm and the facet criterion's open
                                       // faces; 11: fracture.facet_link and the faces' opening
                                       // tractions; 12: run.step_bound;
                                       // 13: run.mass_scaling; 14: fracture.length, the
                                       // criterion's state after Fracture's own

/// A checkpoint file read whole and checked (magic, checksum), its header parsed.
struct CheckpointFile {
  std::string bytes;
  CheckpointHeader header;
  std::vector<std::string> section_names, section_bytes;
  std::uint64_t mesh_fingerprint = 0;
  std::size_t state_begin = 0, state_end = 0;
};

CheckpointFile load_file(const std::string& path) {
  const std::string what = "checkpoint '" + path + "'";
  std::error_code ec;
  BRITTLE_CHECK(fs::is_regular_file(path, ec), what, ": no such file (expected a run directory "
                                                     "with checkpoint.bin: output.checkpoint_interval "
                                                     "or a run stopped by SIGINT/SIGTERM)");
  CheckpointFile f;
  {
    std::ifstream in(path, std::ios::binary);
    BRITTLE_CHECK(in, what, ": cannot be opened");
    f.bytes.assign(std::istreambuf_iterator<char>(in), {});
    BRITTLE_CHECK(!in.bad(), what, ": cannot be read");
  }
  const std::size_t magic = sizeof kMagic - 1;
  BRITTLE_CHECK(f.bytes.size() >= magic + 8 && f.bytes.compare(0, magic, kMagic) == 0, what,
                ": not a brittle checkpoint");
  std::uint64_t sum = 0, state_size = 0;
  std::memcpy(&sum, f.bytes.data() + f.bytes.size() - 8, 8);
  BRITTLE_CHECK(f.bytes.size() >= magic + 16 && sum == fnv1a(f.bytes.data(), f.bytes.size() - 8),
                what, ": damaged (checksum does not match; expected a complete checkpoint)");
  std::memcpy(&state_size, f.bytes.data() + f.bytes.size() - 16, 8);
  f.state_end = f.bytes.size() - 16;
  BRITTLE_CHECK(state_size <= f.state_end - magic, what, ": damaged (state size)");
  f.state_begin = f.state_end - state_size;
  StateReader r(f.bytes.data() + magic, f.bytes.data() + f.state_begin, what);
  std::uint32_t format = 0;
  io(r, format);
  BRITTLE_CHECK(format == kFormat, what, ": format ", format, " (this brittle reads format ",
                kFormat, ")");
  CheckpointHeader& h = f.header;
  io_all(r, h.version, h.sources, f.section_names, f.section_bytes, f.mesh_fingerprint, h.time,
         h.steps, h.pieces);
  BRITTLE_CHECK(r.done(), what, ": damaged (header and state do not meet)");
  if (h.pieces > 0) {  // a decomposed run's: the state is in the pieces this names
    StateReader m(f.bytes.data() + f.state_begin, f.bytes.data() + f.state_end, what);
    io_all(m, h.generation, h.piece_sums);
    BRITTLE_CHECK(m.done() && h.piece_sums.size() == h.pieces, what, ": damaged (pieces)");
  }
  return f;
}

/// Opens `path`.tmp, lets `fill` write into it, fsyncs, renames it over `path` and fsyncs the
/// directory: a kill at any moment leaves the previous file (or none) whole. Returns the bytes
/// written.
template <class Fill>
std::size_t write_atomically(const std::string& path, bool kill, Fill&& fill) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  BRITTLE_CHECK(fd >= 0, "checkpoint: cannot write '", tmp, "': ", std::strerror(errno));
  StateWriter w(fd, kill);
  fill(w);
  w.flush();
  int error = w.error();
  if (!error && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && !error) error = errno;
  std::error_code ec;
  if (!error) fs::rename(tmp, path, ec);
  if (error || ec) {
    fs::remove(tmp, ec);
    throw Error(error_message("checkpoint: cannot write '", path, "': ",
                              error ? std::strerror(error) : ec.message()));
  }
  // The rename itself reaches the disk with the directory.
  const fs::path parent = fs::path(path).parent_path();
  const std::string dir = parent.empty() ? std::string(".") : parent.string();
  if (const int d = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) {
    ::fsync(d);
    ::close(d);
  }
  return w.written();
}

/// The header of a checkpoint of `sim` (magic to piece count), then `state(w)`, its size and
/// the checksum of everything before, which it returns.
template <class State>
std::uint64_t write_file(StateWriter& w, const Simulation& sim, std::uint32_t pieces,
                         State&& state) {
  w.raw(kMagic, sizeof kMagic - 1);
  std::uint32_t format = kFormat;
  std::string version = BRITTLE_VERSION;
  std::vector<std::string> sources;
  for (const std::string& s : sim.scene().sources)
    sources.push_back(s.starts_with("--set ") ? s : fs::absolute(s).lexically_normal().string());
  std::vector<std::string> names, bytes;
  for (auto& [name, b] : scene_sections(sim.scene())) names.push_back(name), bytes.push_back(b);
  std::uint64_t mesh = sim.mesh_fingerprint();
  double time = sim.time();
  long steps = sim.steps();
  io_all(w, format, version, sources, names, bytes, mesh, time, steps, pieces);
  const std::size_t state_begin = w.written();
  state(w);
  std::uint64_t state_size = w.written() - state_begin;
  io(w, state_size);
  std::uint64_t sum = w.hash();
  io(w, sum);
  return sum;
}

/// Test hook (docs/testing.md): BRITTLE_TEST_KILL_IN_CHECKPOINT=N kills the process after the
/// first block of its N-th checkpoint (a decomposed run: of its N-th piece) is written, as a
/// SIGKILL from outside would.
bool kill_in_this_checkpoint() {
  static int count = 0;
  const char* kill_at = std::getenv("BRITTLE_TEST_KILL_IN_CHECKPOINT");
  return kill_at && std::atoi(kill_at) == ++count;
}

/// The checks every restore makes of a checkpoint file against the simulation built to take
/// it: version, scene, mesh and end time.
void check_fits(const CheckpointFile& f, const Simulation& sim, const std::string& what) {
  BRITTLE_CHECK(f.header.version == BRITTLE_VERSION, what, " was written by brittle ",
                f.header.version, ", this is brittle ", BRITTLE_VERSION,
                " (expected the same version: run the scene again from the start)");
  const auto sections = scene_sections(sim.scene());
  BRITTLE_CHECK(f.section_names.size() == sections.size(), what, ": scene sections differ");
  for (std::size_t i = 0; i < sections.size(); ++i)
    BRITTLE_CHECK(f.section_names[i] == sections[i].first && f.section_bytes[i] == sections[i].second,
                  what, ": the scene's [", sections[i].first,
                  "] keys differ from the checkpoint's (on --resume only run.end_time, "
                  "run.threads and output.checkpoint_interval may change)");
  BRITTLE_CHECK(f.mesh_fingerprint == sim.mesh_fingerprint(), what,
                ": the mesh differs from the checkpoint's (expected the same mesh.file "
                "contents or generated plate)");
  BRITTLE_CHECK(f.header.time <= sim.scene().run.end_time * (1 + 1e-12), what, ": run.end_time = ",
                sim.scene().run.end_time, " s is before the checkpoint's time ", f.header.time,
                " s (expected a later end time)");
}

/// The state part of a loaded, checked file into `sim` (collective in a decomposed run:
/// the crack fronts are rebuilt from every rank's volumes).
void load_state(Simulation& sim, const CheckpointFile& f, const std::string& what) {
  StateReader r(f.bytes.data() + f.state_begin, f.bytes.data() + f.state_end, what);
  sim.state(r);
  BRITTLE_CHECK(r.done(), what, ": damaged (bytes left after the state)");
  sim.mark_resumed();
}

}  // namespace

std::string CheckpointWriter::path(const Simulation& sim) const {
  return checkpoint_path(sim.scene().output.directory);
}

std::size_t CheckpointWriter::write(const Simulation& sim) {
  return sim.halo() ? write_decomposed_checkpoint(sim, *sim.halo())
                    : write_checkpoint(sim, path(sim));
}

std::size_t write_checkpoint(const Simulation& sim, const std::string& path) {
  return write_atomically(path, kill_in_this_checkpoint(), [&](StateWriter& w) {
    write_file(w, sim, 0, [&](StateWriter& ww) {
      const_cast<Simulation&>(sim).state(ww);  // the writer only reads
    });
  });
}

std::string checkpoint_piece_path(const std::string& directory, std::uint64_t generation,
                                  int rank) {
  return directory + "/checkpoint_r" + std::to_string(rank) + "_g" + std::to_string(generation) +
         ".bin";
}

namespace {

/// Whether `name` is a checkpoint piece (or its .tmp), of rank `rank` if rank >= 0; its
/// generation in `generation`.
bool is_piece(const std::string& name, int rank, std::uint64_t* generation = nullptr) {
  unsigned long long r = 0, g = 0;
  int used = 0;
  if (std::sscanf(name.c_str(), "checkpoint_r%llu_g%llu.bin%n", &r, &g, &used) != 2) return false;
  const std::string rest = name.substr(static_cast<std::size_t>(used));
  if (!rest.empty() && rest != ".tmp") return false;
  if (generation) *generation = g;
  return rank < 0 || r == static_cast<unsigned long long>(rank);
}

}  // namespace

void remove_checkpoints(const std::string& directory) {
  std::error_code ec;
  fs::remove(checkpoint_path(directory), ec);
  fs::remove(checkpoint_path(directory) + ".tmp", ec);
  for (const auto& entry : fs::directory_iterator(directory, ec))
    if (is_piece(entry.path().filename().string(), -1)) fs::remove(entry.path(), ec);
}

std::size_t write_decomposed_checkpoint(const Simulation& sim, const Halo& halo) {
  const std::string dir = sim.scene().output.directory, manifest = checkpoint_path(dir);
  // The next generation: one past the set checkpoint.bin names now (rank 0 reads it).
  long generation = 1;
  if (halo.rank() == 0) {
    std::error_code ec;
    if (fs::is_regular_file(manifest, ec)) try {
        const CheckpointHeader h = read_checkpoint_header(manifest);
        generation = static_cast<long>(h.generation) + 1;
      } catch (const Error&) {  // a damaged one is replaced
      }
  }
  generation = halo.max(generation);
  const auto g = static_cast<std::uint64_t>(generation);
  // Every rank its piece (an ordinary checkpoint of its part, with its Halo), then rank 0 the
  // file that names the set, once every piece is on disk: until then checkpoint.bin names the
  // previous set, whole.
  std::uint64_t sum = 0;
  std::size_t bytes = 0;
  std::string error;
  const std::string piece = checkpoint_piece_path(dir, g, halo.rank());
  try {
    bytes = write_atomically(piece, kill_in_this_checkpoint(), [&](StateWriter& w) {
      sum = write_file(w, sim, 0, [&](StateWriter& ww) { const_cast<Simulation&>(sim).state(ww); });
    });
  } catch (const std::exception& e) {
    error = e.what();
  }
  std::string first = first_error(error);
  std::vector<double> word(1);
  std::memcpy(word.data(), &sum, sizeof sum);
  const std::vector<double> words = halo.gather_all(word);  // checksums travel as bits
  std::error_code ec;
  if (first.empty() && halo.rank() == 0) {
    std::vector<std::uint64_t> sums(words.size());
    std::memcpy(sums.data(), words.data(), sizeof(double) * words.size());
    try {
      bytes += write_atomically(manifest, false, [&](StateWriter& w) {
        write_file(w, sim, static_cast<std::uint32_t>(halo.size()), [&](StateWriter& ww) {
          std::uint64_t gen = g;
          io_all(ww, gen, sums);
        });
      });
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (first.empty()) first = first_error(error);
  // This rank's other pieces go (a failed set: this one; else the earlier sets).
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::uint64_t of = 0;
    if (is_piece(entry.path().filename().string(), halo.rank(), &of) &&
        (first.empty() ? of != g : of == g))
      fs::remove(entry.path(), ec);
  }
  if (!first.empty()) throw Error(first);
  return bytes;
}

CheckpointHeader read_checkpoint_header(const std::string& path) {
  return load_file(path).header;
}

void check_rank_count(const CheckpointHeader& h, const std::string& path, int ranks) {
  if (h.pieces == static_cast<std::uint32_t>(ranks)) return;
  const std::string by = h.pieces == 0 ? std::string("a serial run")
                                       : "a run over " + std::to_string(h.pieces) + " MPI ranks";
  const std::string run = ranks == 0 ? std::string("a serial run")
                                     : "a run over " + std::to_string(ranks) + " MPI ranks";
  throw Error(error_message("checkpoint '", path, "' was written by ", by,
                            ", this restore reads one of ", run,
                            " (expected the resume of brittle run --resume, which re-cuts it)"));
}

void restore_checkpoint(Simulation& sim, const std::string& path) {
  const CheckpointFile f = load_file(path);
  const std::string what = "checkpoint '" + path + "'";
  check_rank_count(f.header, path, 0);
  check_fits(f, sim, what);
  load_state(sim, f, what);
}

namespace {

/// Rank `rank`'s piece of the set `h` names in `directory`, loaded and checked against the
/// set's checksum and against `sim` (check_fits).
CheckpointFile load_piece(const Simulation& sim, const std::string& directory,
                          const CheckpointHeader& h, int rank, std::string& what) {
  const std::string piece = checkpoint_piece_path(directory, h.generation, rank);
  what = "checkpoint piece '" + piece + "'";
  CheckpointFile f = load_file(piece);
  const std::uint64_t sum = fnv1a(f.bytes.data(), f.bytes.size() - 8);
  BRITTLE_CHECK(sum == h.piece_sums[rank], what, ": not the piece '", checkpoint_path(directory),
                "' names (checksum; expected the set written with it)");
  check_fits(f, sim, what);
  return f;
}

}  // namespace

void restore_decomposed_checkpoint(Simulation& sim, const Halo& halo) {
  const std::string dir = sim.scene().output.directory, manifest = checkpoint_path(dir);
  CheckpointFile f;
  std::string what, error;
  try {  // every check on every rank, agreed, before the collective load
    const CheckpointHeader h = read_checkpoint_header(manifest);
    check_rank_count(h, manifest, halo.size());
    f = load_piece(sim, dir, h, halo.rank(), what);
  } catch (const std::exception& e) {
    error = e.what();
  }
  const std::string first = first_error(error);
  if (!first.empty()) throw Error(first);
  load_state(sim, f, what);
}

void read_checkpoint_piece(Simulation& part, Halo& halo, const std::string& directory,
                           const CheckpointHeader& h) {
  BRITTLE_CHECK(halo.rank() < static_cast<int>(h.pieces), "checkpoint '",
                checkpoint_path(directory), "': no piece ", halo.rank(), " (", h.pieces,
                " pieces)");
  std::string what;
  const CheckpointFile f = load_piece(part, directory, h, halo.rank(), what);
  StateReader r(f.bytes.data() + f.state_begin, f.bytes.data() + f.state_end, what);
  part.read_piece(r, halo);
}

}  // namespace brittle
