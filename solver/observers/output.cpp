// What a run writes besides its frames and summary (SPEC 9): files written whole (through a
// .tmp and a rename) or grown by checked rows, energies.csv, crack_tip.csv, and the standard
// set of writers. The frames are in frames.cpp, summary.json in summary.cpp.
#include "output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "crack_pattern.hpp"
#include "error.hpp"
#include "sensors.hpp"
#include "tip_fields.hpp"

namespace fs = std::filesystem;

namespace brittle {

namespace {

/// One line naming the file and the operating system's reason.
Error write_error(const std::string& path, int err) {
  return Error(error_message("output: cannot write '", path, "': ", std::strerror(err)));
}

/// Writes all `size` bytes to `fd`; 0 or the errno of the failure (ENOSPC, EIO, ...).
int write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return EIO;  // a regular file that takes nothing: treat as an I/O error
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return 0;
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& text) {
  // Every call is checked (write, fsync, close, rename): a full disk or an I/O error must not
  // leave a truncated file under the final name, and fsync is where some file systems report
  // what write accepted. On any failure the temporary file goes and nothing is renamed.
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw write_error(path, errno);
  int err = write_all(fd, text.data(), text.size());
  if (err == 0 && ::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && ::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    throw write_error(path, err);
  }
}

RowFile::RowFile(std::string path, bool truncate) : path_(std::move(path)) {
  fd_ =
      ::open(path_.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (truncate ? O_TRUNC : O_APPEND), 0644);
  if (fd_ < 0) throw write_error(path_, errno);
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  if (end < 0) {
    const int err = errno;
    ::close(fd_);
    throw write_error(path_, err);
  }
  size_ = end;
}

RowFile::~RowFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RowFile::append(const std::string& rows) {
  if (fd_ < 0) throw Error(error_message("output: '", path_, "' was closed by an earlier error"));
  const int err = write_all(fd_, rows.data(), rows.size());
  if (err == 0) {
    size_ += static_cast<long long>(rows.size());
    return;
  }
  // Cut what did land of these rows, so that the file ends with a whole row (best effort:
  // the error reported is the write's).
  [[maybe_unused]] const int cut = ::ftruncate(fd_, static_cast<off_t>(size_));
  ::close(fd_);
  fd_ = -1;
  throw write_error(path_, err);
}

namespace {
constexpr const char* kEnergyHeader =
    "time,kinetic,elastic,viscous_dissipated,cohesive_stored,cohesive_dissipated,"
    "damage_dissipated,external_work,total,relative_imbalance\n";
}

EnergyCsvWriter::EnergyCsvWriter(const std::string& directory, bool resume)
    : path_(directory + "/energies.csv") {
  if (resume) return;  // on_resume opens it
  out_ = std::make_unique<RowFile>(path_, /*truncate=*/true);
  out_->append(kEnergyHeader);
}

void EnergyCsvWriter::on_resume(const Simulation& sim) {
  const long keep = sim.progress().energy_rows;
  std::ifstream in(path_);
  BRITTLE_CHECK(in, "resume: cannot read '", path_, "'");
  std::string text, line;
  long rows = -1;  // the header first
  while (rows < keep && std::getline(in, line)) text += line + "\n", ++rows;
  BRITTLE_CHECK(rows == keep, "resume: '", path_, "' has ", std::max(rows, 0L),
                " rows, the checkpoint was taken after ", keep);
  in.close();
  write_file_atomically(path_, text);
  out_ = std::make_unique<RowFile>(path_, /*truncate=*/false);
  initial_ = sim.initial_energy();
  first_ = false;
}

void EnergyCsvWriter::on_energy(const Simulation&, const Energies& e) {
  if (first_) initial_ = e.total(), first_ = false;
  const double imbalance = e.reference > 0 ? (e.total() - initial_) / e.reference : 0.0;
  std::ostringstream row;
  row << std::setprecision(12) << e.time << ',' << e.kinetic << ',' << e.elastic << ','
      << e.viscous_dissipated << ',' << e.cohesive_stored << ',' << e.cohesive_dissipated << ','
      << e.damage_dissipated << ',' << e.external_work << ',' << e.total() << ',' << imbalance
      << '\n';
  out_->append(row.str());
}

void CrackTipCsvWriter::on_finish(const Simulation& sim, const RunSummary&) {
  const auto& samples = sim.tip_samples();
  const std::vector<double> speed = smoothed_speed(samples, 0.5e-6);
  std::ostringstream csv;
  csv << "time,tip_x,tip_y,splits,speed,max_split_x,nucleations\n" << std::setprecision(12);
  for (std::size_t i = 0; i < samples.size(); ++i)
    csv << samples[i].t << ',' << samples[i].x << ',' << samples[i].y << ',' << samples[i].splits
        << ',' << speed[i] << ',' << samples[i].max_split_x << ',' << samples[i].nucleations
        << '\n';
  write_file_atomically(directory_ + "/crack_tip.csv", csv.str());
}

OutputWriters::OutputWriters(const Simulation& sim) {
  const std::string& dir = sim.scene().output.directory;
  fs::create_directories(dir);
  if (sim.scene().output.vtu) writers_.push_back(std::make_unique<VtuSeriesWriter>(dir));
  writers_.push_back(std::make_unique<EnergyCsvWriter>(dir, sim.resumed()));
  if (sim.fracture().enabled()) writers_.push_back(std::make_unique<CrackTipCsvWriter>(dir));
  if (sim.fracture().enabled()) writers_.push_back(std::make_unique<PatternWriter>(dir));
  if (sim.fracture().enabled()) writers_.push_back(std::make_unique<TipFieldsWriter>(dir));
  if (!sim.scene().sensors.empty())
    writers_.push_back(std::make_unique<SensorRecorder>(sim.scene(), dir));
  writers_.push_back(std::make_unique<SummaryWriter>(dir));
}

std::vector<Observer*> OutputWriters::observers() {
  std::vector<Observer*> list;
  for (auto& w : writers_) list.push_back(w.get());
  return list;
}

}  // namespace brittle
