// VTU/PVD time series, energy CSV and run summary (SPEC 9).
#include "output.hpp"

#include "isolated_read.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkXMLUtilities.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "crack_pattern.hpp"
#include "tip_fields.hpp"
#include "halo.hpp"
#include "sensors.hpp"
#include "build_info.hpp"
#include "error.hpp"

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

void PvdCollection::add(double time, const std::string& relative_file) {
  // The entry is kept only once the file that lists it is written.
  entries_.emplace_back(time, relative_file);
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n"
      << std::setprecision(17);
  for (const auto& [t, file] : entries_)
    pvd << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file
        << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  try {
    write_file_atomically(path_, pvd.str());
  } catch (...) {
    entries_.pop_back();
    throw;
  }
}

void PvdCollection::resume(std::size_t keep) {
  entries_.clear();
  if (keep == 0) {  // an empty collection is written by the first add()
    std::error_code ec;
    fs::remove(path_, ec);
    return;
  }
  const fs::path base = fs::path(path_).parent_path();
  std::vector<PvdEntry> old = read_pvd(path_);
  BRITTLE_CHECK(old.size() >= keep, "resume: '", path_, "' lists ", old.size(),
                " files, the checkpoint was taken after ", keep);
  for (std::size_t i = 0; i + 1 < keep; ++i)
    entries_.emplace_back(old[i].time, fs::path(old[i].file).lexically_relative(base).string());
  add(old[keep - 1].time, fs::path(old[keep - 1].file).lexically_relative(base).string());
}

namespace {

/// Writes a VTK XML file (binary, appended, zlib): VTK writes into memory, and the file is
/// written and checked by write_file_atomically (VTK's own file output does not notice a
/// full disk: a truncated file would be renamed into place).
void write_xml(vtkXMLWriter* writer, vtkDataObject* data, const std::string& path) {
  writer->SetInputData(data);
  writer->WriteToOutputStringOn();
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  BRITTLE_CHECK(writer->Write() == 1 && writer->GetErrorCode() == 0, "output: cannot write '", path,
                "': VTK could not encode the data (error code ", writer->GetErrorCode(), ")");
  write_file_atomically(path, writer->GetOutputString());
}

}  // namespace

void write_vtu_file(vtkUnstructuredGrid& grid, const std::string& path) {
  write_xml(vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New(), &grid, path);
}

namespace {

/// The cohesive links as line cells between their current end points.
vtkSmartPointer<vtkPolyData> link_lines(const Simulation& sim) {
  const auto& links = sim.fracture().links();
  const double* x = sim.grid().x();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto data = vtkSmartPointer<vtkPolyData>::New();
  const char* names[] = {"f", "f0", "delta", "delta_max", "delta_c", "omega", "A_c"};
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (const char* name : names) {
    arrays.push_back(vtkSmartPointer<vtkDoubleArray>::New());
    arrays.back()->SetName(name);
    data->GetCellData()->AddArray(arrays.back());
  }
  for (const CohesiveLink& l : links) {
    const vtkIdType ids[2] = {points->InsertNextPoint(x + 3 * l.a),
                              points->InsertNextPoint(x + 3 * l.b)};
    lines->InsertNextCell(2, ids);
    const double values[] = {l.f, l.f0, l.delta, l.delta_max, l.delta_c, l.omega, l.A_c};
    for (std::size_t i = 0; i < arrays.size(); ++i) arrays[i]->InsertNextValue(values[i]);
  }
  data->SetPoints(points);
  data->SetLines(lines);
  auto time = vtkSmartPointer<vtkDoubleArray>::New();
  time->SetName(field::time);
  time->InsertNextValue(sim.time());
  data->GetFieldData()->AddArray(time);
  return data;
}

}  // namespace

VtuSeriesWriter::VtuSeriesWriter(std::string directory)
    : directory_(std::move(directory)),
      grid_series_(directory_ + "/run.pvd"),
      link_series_(directory_ + "/links.pvd") {
  fs::create_directories(directory_ + "/frames");
}

void VtuSeriesWriter::on_frame(const Simulation& sim) {
  std::ostringstream number;
  number << std::setw(4) << std::setfill('0') << frames_++;
  const std::string grid_file = "frames/frame_" + number.str() + ".vtu";
  write_xml(vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New(), sim.grid().vtk(),
            directory_ + "/" + grid_file);
  grid_series_.add(sim.time(), grid_file);
  if (!sim.fracture().enabled()) return;
  const std::string link_file = "frames/links_" + number.str() + ".vtp";
  write_xml(vtkSmartPointer<vtkXMLPolyDataWriter>::New(), link_lines(sim),
            directory_ + "/" + link_file);
  link_series_.add(sim.time(), link_file);
}

namespace {

/// Removes the frame files <dir>/frames/frame_NNNN and links_NNNN with NNNN >= keep (those
/// the stopped run wrote after its checkpoint): serial (.vtu, .vtp) and decomposed (.pvtu,
/// .pvtp and the pieces _rR.vtu, _rR.vtp of any rank: the run may resume on another count).
void remove_frames_from(const std::string& directory, long keep) {
  for (const auto& entry : fs::directory_iterator(directory + "/frames")) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("frame_") && !name.starts_with("links_")) continue;
    const std::size_t dot = name.rfind('.');
    if (dot == std::string::npos) continue;
    const std::string ext = name.substr(dot);
    if (ext != ".vtu" && ext != ".vtp" && ext != ".pvtu" && ext != ".pvtp") continue;
    std::string stem = name.substr(6, dot - 6);
    if (const std::size_t r = stem.find("_r"); r != std::string::npos && ext.size() == 4) {
      const std::string rank = stem.substr(r + 2);
      if (rank.empty() || rank.find_first_not_of("0123456789") != std::string::npos) continue;
      stem.resize(r);
    }
    if (stem.empty() || stem.find_first_not_of("0123456789") != std::string::npos) continue;
    if (std::stol(stem) >= keep) fs::remove(entry.path());
  }
}

}  // namespace

void VtuSeriesWriter::on_resume(const Simulation& sim) {
  const long keep = sim.progress().frames_written;
  grid_series_.resume(keep);
  if (sim.fracture().enabled()) link_series_.resume(keep);
  frames_ = static_cast<int>(keep);
  remove_frames_from(directory_, keep);
}

namespace {

/// The VTK XML name of an array's type (as the serial writers write it).
std::string xml_type(vtkAbstractArray* a) {
  switch (a->GetDataType()) {
    case VTK_DOUBLE: return "Float64";
    case VTK_FLOAT: return "Float32";
    case VTK_UNSIGNED_CHAR: return "UInt8";
    case VTK_CHAR: case VTK_SIGNED_CHAR: return "Int8";
    case VTK_INT: return "Int32";
    case VTK_LONG: case VTK_LONG_LONG: case VTK_ID_TYPE: return "Int64";
    default: break;
  }
  throw Error(error_message("output: array '", a->GetName(), "' of VTK type ",
                            a->GetDataTypeAsString(), " has no parallel XML name here"));
}

/// The <PDataArray> declarations of a piece's arrays.
std::string declare_arrays(vtkFieldData* data) {
  std::ostringstream out;
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    vtkAbstractArray* a = data->GetAbstractArray(i);
    out << "      <PDataArray type=\"" << xml_type(a) << "\" Name=\"" << a->GetName()
        << "\" NumberOfComponents=\"" << a->GetNumberOfComponents() << "\"/>\n";
  }
  return out.str();
}

/// A parallel XML summary (.pvtu / .pvtp) naming `pieces`, with the arrays of `piece`.
std::string parallel_summary(const char* type, vtkDataSet* piece,
                             const std::vector<std::string>& pieces) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"P" << type
      << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <P" << type
      << " GhostLevel=\"0\">\n    <PPointData>\n"
      << declare_arrays(piece->GetPointData()) << "    </PPointData>\n    <PCellData>\n"
      << declare_arrays(piece->GetCellData()) << "    </PCellData>\n    <PPoints>\n"
      << "      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const std::string& p : pieces) out << "    <Piece Source=\"" << p << "\"/>\n";
  out << "  </P" << type << ">\n</VTKFile>\n";
  return out.str();
}

}  // namespace

vtkSmartPointer<vtkUnstructuredGrid> grid_piece(const Grid& grid, const Halo& halo) {
  vtkUnstructuredGrid* g = grid.vtk();
  std::vector<vtkIdType> node(grid.num_points(), -1), nodes, cells;
  for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
    if (!halo.owns_cell(e)) continue;
    cells.push_back(e);
    for (int k = 0; k < 4; ++k) {
      const vtkIdType p = grid.cells()[4 * e + k];
      if (node[p] < 0) node[p] = 0, nodes.push_back(p);
    }
  }
  std::sort(nodes.begin(), nodes.end(), [&](vtkIdType p, vtkIdType q) {
    return halo.global_node()[p] < halo.global_node()[q];  // the serial order
  });
  auto piece = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(nodes.size()));
  piece->GetPointData()->CopyAllocate(g->GetPointData(), static_cast<vtkIdType>(nodes.size()));
  auto global_node = vtkSmartPointer<vtkIdTypeArray>::New();
  global_node->SetName("global_node");
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    node[nodes[i]] = static_cast<vtkIdType>(i);
    points->SetPoint(static_cast<vtkIdType>(i), grid.x() + 3 * nodes[i]);
    piece->GetPointData()->CopyData(g->GetPointData(), nodes[i], static_cast<vtkIdType>(i));
    global_node->InsertNextValue(halo.global_node()[nodes[i]]);
  }
  piece->SetPoints(points);
  piece->GetPointData()->AddArray(global_node);
  auto connectivity = vtkSmartPointer<vtkCellArray>::New();
  piece->GetCellData()->CopyAllocate(g->GetCellData(), static_cast<vtkIdType>(cells.size()));
  auto global_cell = vtkSmartPointer<vtkIdTypeArray>::New();
  global_cell->SetName("global_cell");
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const vtkIdType* c = grid.cells() + 4 * cells[i];
    const vtkIdType ids[4] = {node[c[0]], node[c[1]], node[c[2]], node[c[3]]};
    connectivity->InsertNextCell(4, ids);
    piece->GetCellData()->CopyData(g->GetCellData(), cells[i], static_cast<vtkIdType>(i));
    global_cell->InsertNextValue(halo.global_cell()[cells[i]]);
  }
  piece->SetCells(VTK_TETRA, connectivity);
  piece->GetCellData()->AddArray(global_cell);
  piece->GetFieldData()->ShallowCopy(g->GetFieldData());
  return piece;
}

vtkSmartPointer<vtkUnstructuredGrid> whole_grid(const Simulation& sim) {
  const Halo* halo = sim.halo();
  if (!halo) return sim.grid().vtk();
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->SetInputData(grid_piece(sim.grid(), *halo));
  writer->SetDataModeToBinary();  // the values' bytes, exactly
  writer->SetCompressorTypeToNone();
  writer->WriteToOutputStringOn();
  writer->Write();
  const std::vector<std::string> pieces = halo->gather_to_root(writer->GetOutputString());
  if (halo->rank() != 0) return nullptr;
  // The pieces one after the other (as VTK's parallel reader gives a .pvtu), then joined.
  auto all = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> grids;
  vtkIdType np = 0, nc = 0;
  for (const std::string& bytes : pieces) {
    auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    reader->ReadFromInputStringOn();
    reader->SetInputString(bytes);
    reader->Update();
    grids.push_back(reader->GetOutput());
    np += grids.back()->GetNumberOfPoints(), nc += grids.back()->GetNumberOfCells();
  }
  all->GetPointData()->CopyAllocate(grids.front()->GetPointData(), np);
  all->GetCellData()->CopyAllocate(grids.front()->GetCellData(), nc);
  vtkNew<vtkIdList> ids;
  vtkIdType offset = 0;
  for (const auto& g : grids) {
    for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p) {
      const vtkIdType q = points->InsertNextPoint(g->GetPoint(p));
      all->GetPointData()->CopyData(g->GetPointData(), p, q);
    }
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
      g->GetCellPoints(c, ids);
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) ids->SetId(k, ids->GetId(k) + offset);
      const vtkIdType d = cells->InsertNextCell(ids);
      all->GetCellData()->CopyData(g->GetCellData(), c, d);
    }
    offset += g->GetNumberOfPoints();
  }
  all->SetPoints(points);
  all->SetCells(VTK_TETRA, cells);
  all->GetFieldData()->ShallowCopy(grids.front()->GetFieldData());
  return joined_by_serial_ids(*all, "the run's pieces");
}

namespace {

}  // namespace

int remove_earlier_frames(const std::string& dir) {
  const fs::path frames = fs::path(dir) / "frames";
  std::error_code ec;
  if (!fs::is_directory(frames, ec)) return 0;
  auto digits = [](const std::string& s) {
    return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
  };
  // frame_NNNN[_rR].vtu, frame_NNNN.pvtu, links_NNNN[_rR].vtp, links_NNNN.pvtp
  auto ours = [&](const std::string& name) {
    for (const auto& [prefix, ext, pext] :
         {std::tuple{"frame_", ".vtu", ".pvtu"}, std::tuple{"links_", ".vtp", ".pvtp"}}) {
      if (!name.starts_with(prefix)) continue;
      std::string rest = name.substr(std::string(prefix).size());
      if (rest.ends_with(pext)) return digits(rest.substr(0, rest.size() - std::string(pext).size()));
      if (!rest.ends_with(ext)) return false;
      rest.resize(rest.size() - std::string(ext).size());
      const std::size_t r = rest.find("_r");
      return r == std::string::npos ? digits(rest) : digits(rest.substr(0, r)) && digits(rest.substr(r + 2));
    }
    return false;
  };
  int removed = 0;
  for (const auto& entry : fs::directory_iterator(frames, ec))
    if (entry.is_regular_file(ec) && ours(entry.path().filename().string()) &&
        fs::remove(entry.path(), ec))
      ++removed;
  return removed;
}

PieceSeriesWriter::PieceSeriesWriter(std::string directory, const Halo& halo)
    : directory_(std::move(directory)),
      halo_(halo),
      grid_series_(directory_ + "/run.pvd"),
      link_series_(directory_ + "/links.pvd") {
  fs::create_directories(directory_ + "/frames");
}

void PieceSeriesWriter::on_frame(const Simulation& sim) {
  std::ostringstream number;
  number << std::setw(4) << std::setfill('0') << frames_++;
  const std::string base = "frame_" + number.str(), links = "links_" + number.str();
  const std::string piece = "_r" + std::to_string(halo_.rank());
  const auto grid = grid_piece(sim.grid(), halo_);
  write_vtu_file(*grid, directory_ + "/frames/" + base + piece + ".vtu");
  vtkSmartPointer<vtkPolyData> lines;
  if (sim.fracture().enabled()) {
    lines = link_lines(sim);
    write_xml(vtkSmartPointer<vtkXMLPolyDataWriter>::New(), lines,
              directory_ + "/frames/" + links + piece + ".vtp");
  }
  if (halo_.rank() != 0) return;
  std::vector<std::string> grid_pieces, link_pieces;
  for (int r = 0; r < halo_.size(); ++r) {
    grid_pieces.push_back(base + "_r" + std::to_string(r) + ".vtu");
    link_pieces.push_back(links + "_r" + std::to_string(r) + ".vtp");
  }
  write_file_atomically(directory_ + "/frames/" + base + ".pvtu",
                        parallel_summary("UnstructuredGrid", grid, grid_pieces));
  grid_series_.add(sim.time(), "frames/" + base + ".pvtu");
  if (!lines) return;
  write_file_atomically(directory_ + "/frames/" + links + ".pvtp",
                        parallel_summary("PolyData", lines, link_pieces));
  link_series_.add(sim.time(), "frames/" + links + ".pvtp");
}

void PieceSeriesWriter::on_resume(const Simulation& sim) {
  const long keep = sim.progress().frames_written;
  frames_ = static_cast<int>(keep);
  if (halo_.rank() != 0) return;  // (no rank writes a frame before every rank has stepped)
  grid_series_.resume(keep);
  if (sim.fracture().enabled()) link_series_.resume(keep);
  remove_frames_from(directory_, keep);  // every rank's pieces, of any rank count
}

std::vector<PvdEntry> read_pvd(const std::string& path) {
  BRITTLE_CHECK(fs::is_regular_file(path), "time series '", path, "': no such file");
  vtkSmartPointer<vtkXMLDataElement> root;
  root.TakeReference(vtkXMLUtilities::ReadElementFromFile(path.c_str()));
  BRITTLE_CHECK(
      root && root->GetAttribute("type") && std::string(root->GetAttribute("type")) == "Collection",
      "time series '", path, "': not a VTK .pvd collection");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  BRITTLE_CHECK(collection, "time series '", path, "': no <Collection> element");
  const fs::path base = fs::path(path).parent_path();
  std::vector<PvdEntry> entries;
  for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* d = collection->GetNestedElement(i);
    const char* file = d->GetAttribute("file");
    double t = 0;
    BRITTLE_CHECK(file && d->GetScalarAttribute("timestep", t), "time series '", path,
                  "': DataSet ", i, " lacks 'file' or 'timestep'");
    entries.push_back({t, (base / file).string()});
  }
  return entries;
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

namespace {
/// JSON has no NaN or infinity: a number that is not finite is written as null.
nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}
}  // namespace

void add_branchings_json(nlohmann::ordered_json& j, const std::string& key,
                         const std::vector<BranchingEvent>& branchings,
                         const std::vector<Nucleation>& nucleations) {
  j[key] = nlohmann::ordered_json::array();
  for (const BranchingEvent& b : branchings)
    j[key].push_back({{"t", number(b.t)},
                      {"x", number(b.x)},
                      {"y", number(b.y)},
                      {"angle_deg", number(b.angle_deg)},
                      {"parent", b.parent},
                      {"children", {b.child_a, b.child_b}}});
  j["nucleations"] = nlohmann::ordered_json::array();
  for (const Nucleation& n : nucleations)
    j["nucleations"].push_back(
        {{"t", number(n.t)}, {"x", number(n.x)}, {"y", number(n.y)}, {"tip", n.tip}});
}

std::string summary_json(const Simulation& sim, const RunSummary& s) {
  const Energies& e = s.final_energies;
  nlohmann::ordered_json j;
  j["status"] = s.status;
  // Values every run defines (energies, times, dt, the load): one that is not finite means
  // the run went wrong (a blow-up); it is null, and the status names it. Values that may be
  // undefined (a speed fitted to fewer than 3 samples, a tip that has not moved yet) are
  // null without a word: docs/scenes.md, "When a run fails".
  std::vector<std::string> non_finite;
  auto measured = [&](const std::string& key, double v) {
    if (!std::isfinite(v)) non_finite.push_back(key);
    return number(v);
  };
  j["scene_sources"] = sim.scene().sources;
  j["brittle_version"] = BRITTLE_VERSION;
  const BuildInfo& build = build_info();  // what made this binary
  j["build"] = {{"version", build.version},
                {"commit", build.commit},
                {"compiler", build.compiler},
                {"build_type", build.build_type},
                {"flags", build.flags}};
  if (!sim.scene().resolved.empty()) {  // every key's value, as in the run's scene.ini
    nlohmann::json scene = nlohmann::json::object();
    for (const auto& [key, value] : sim.scene().resolved) scene[key] = value;
    j["scene"] = scene;
  }
  j["nodes"] = s.nodes;
  j["tets"] = s.tets;
  j["fixed_nodes"] = s.fixed_nodes;
  j["sigma"] = measured("sigma", s.sigma);
  j["sigma_over_sigmac"] = measured("sigma_over_sigmac", s.sigma / sim.scene().material.sigma_c);
  j["dt"] = measured("dt", s.dt);
  j["final_dt"] = measured("final_dt", s.final_dt);
  // Where the step comes from (issue 38; docs/performance.md), to 9 significant digits: a
  // decomposed run's part computes a few elements' steps from its own copy of their corners
  // and volumes, which can differ from the serial run's in the last bit (dt itself does not).
  if (const StepDistribution& d = sim.step_distribution(); d.elements > 0) {
    const auto nine = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.9g", v);
      return number(std::strtod(text, nullptr));
    };
    j["step_distribution"] = {
        {"smallest", nine(d.smallest)},
        {"p1", nine(d.p1)},
        {"median", nine(d.median)},
        {"element", d.element},
        {"centroid", {nine(d.centroid[0]), nine(d.centroid[1]), nine(d.centroid[2])}},
        {"altitude", nine(d.altitude)},
        {"damping_ratio", nine(d.xi)},
        {"median_altitude", nine(d.median_altitude)},
        {"within_10_percent", d.within_10_percent}};
  } else {
    j["step_distribution"] = nullptr;
  }
  j["dt_reductions"] = s.dt_reductions;
  j["substep_cap_steps"] = s.substep_cap_steps;
  j["end_time"] = measured("end_time", s.end_time);
  j["time"] = measured("time", s.time);
  j["steps"] = s.steps;
  j["threads"] = s.threads;
  j["wall_seconds"] = measured("wall_seconds", s.wall_seconds);
  j["tet_updates_per_second"] = measured("tet_updates_per_second", s.tet_updates_per_second);
  for (const auto& [name, seconds] : s.phases.named())
    j["phases"][name] = measured(std::string("phases.") + name, seconds);
  if (!s.ranks.empty()) {  // a decomposed run: what each rank held, used and sent
    nlohmann::ordered_json& d = j["decomposition"];
    d["collectives"] = s.collectives;
    d["collectives_per_step"] = s.steps > 0 ? double(s.collectives) / s.steps : 0.0;
    for (std::size_t r = 0; r < s.ranks.size(); ++r) {
      const RunSummary::Rank& k = s.ranks[r];
      d["ranks"].push_back({{"rank", r},
                            {"tets", k.tets},
                            {"peak_rss_mb", k.peak_rss_kb / 1024.0},
                            {"ghost_bytes_per_step", s.steps > 0 ? double(k.bytes_sent) / s.steps : 0.0},
                            {"messages_per_step", s.steps > 0 ? double(k.messages) / s.steps : 0.0}});
    }
  }
  j["initial_energy"] = measured("initial_energy", s.initial_elastic);
  j["final_kinetic"] = measured("final_kinetic", e.kinetic);
  j["final_elastic"] = measured("final_elastic", e.elastic);
  j["viscous_dissipated"] = measured("viscous_dissipated", e.viscous_dissipated);
  j["cohesive_stored"] = measured("cohesive_stored", e.cohesive_stored);
  j["cohesive_dissipated"] = measured("cohesive_dissipated", e.cohesive_dissipated);
  j["damage_dissipated"] = measured("damage_dissipated", e.damage_dissipated);
  j["external_work"] = measured("external_work", e.external_work);
  j["warnings"] = s.warnings;
  j["max_relative_imbalance"] = measured("max_relative_imbalance", s.max_relative_imbalance);
  j["splits"] = s.splits;
  j["live_links"] = s.live_links;
  j["crack_area"] = measured("crack_area", s.crack_area);
  j["tip_x"] = measured("tip_x", s.tip_x);
  j["tip_y"] = measured("tip_y", s.tip_y);
  if (s.cut_through.happened)  // the plate cut through: when, where, and whether the run stopped
    j["cut_through"] = {{"t", number(s.cut_through.t)},
                        {"x", number(s.cut_through.x)},
                        {"y", number(s.cut_through.y)},
                        {"tip", s.cut_through.tip},
                        {"stopped", s.stopped_at_cut}};
  else
    j["cut_through"] = nullptr;
  j["crack_speed"] = number(s.crack_speed.speed);
  j["crack_speed_samples"] = s.crack_speed.samples;
  j["crack_speed_window"] = {number(s.crack_speed.t_begin), number(s.crack_speed.t_end)};
  j["crack_speed_r2"] = number(s.crack_speed.r2);
  j["crack_speed_window_end"] = s.speed_window_end;
  j["max_split_x"] = number(s.max_split_x);
  j["nucleated_cracks"] = nlohmann::ordered_json::array();  // ConnectedCracks: issue 16
  for (const ConnectedCracks::Start& n : sim.cracks().nucleations())
    j["nucleated_cracks"].push_back({{"t", number(n.t)}, {"x", number(n.x)}, {"y", number(n.y)}});
  if (s.super_cp_front.happened)
    j["super_cp_front"] = {{"t", number(s.super_cp_front.t)},
                           {"speed", number(s.super_cp_front.speed)},
                           {"c_p", number(s.super_cp_front.c_p)},
                           {"x", number(s.super_cp_front.x)},
                           {"y", number(s.super_cp_front.y)}};
  else
    j["super_cp_front"] = nullptr;
  j["speed_stop_x"] = measured("speed_stop_x", s.speed_stop_x);
  j["checkpoint"] = nullptr;  // the last checkpoint written (docs/checkpoint.md), if any
  j["checkpoint_time"] = nullptr;
  if (!s.checkpoint.empty()) j["checkpoint"] = s.checkpoint, j["checkpoint_time"] = number(s.checkpoint_time);
  j["checkpoints_written"] = s.checkpoints;
  j["checkpoint_bytes"] = s.checkpoint_bytes;
  j["checkpoint_seconds"] = number(s.checkpoint_seconds);
  j["W"] = measured("W", s.W);
  j["W_clamped"] = measured("W_clamped", s.W_clamped);
  j["zhou_speed"] = measured("zhou_speed", s.zhou_speed);
  // Every crack tip, branching and nucleation (docs/crack_fronts.md); positions reference.
  const CrackFronts& fronts = sim.fronts();
  j["tips"] = nlohmann::ordered_json::array();
  for (const TipTrack& t : fronts.tips()) {
    const TipSample head = fronts.head(t.id);
    const SpeedFit v = fronts.speed(t.id);
    nlohmann::ordered_json tip;
    tip["id"] = t.id;
    tip["origin"] = t.origin == TipTrack::Origin::seed         ? "notch"
                    : t.origin == TipTrack::Origin::nucleation ? "nucleation"
                                                               : "branch";
    tip["parent"] = t.parent;
    tip["start"] = {number(t.t_start), number(t.x_start), number(t.y_start)};
    tip["start_angle_deg"] = number(t.start_angle_deg);
    tip["departure_angle_deg"] = number(fronts.departure_angle_deg(t.id, fronts.separation()));
    tip["head"] = {number(head.t), number(head.x), number(head.y)};
    tip["length"] = number(t.arc.empty() ? 0.0 : t.arc.back());
    tip["speed"] = number(v.speed);
    tip["speed_samples"] = v.samples;
    tip["active"] = t.active;
    j["tips"].push_back(tip);
  }
  j["leading_tip"] = fronts.leading();
  add_branchings_json(j, "branchings", fronts.branchings(), fronts.nucleations());
  if (!non_finite.empty()) {
    std::string names;
    for (const std::string& name : non_finite) names += (names.empty() ? "" : ", ") + name;
    j["status"] = s.status + "; non-finite values written as null: " + names;
  }
  return j.dump(2) + "\n";
}

void SummaryWriter::on_finish(const Simulation& sim, const RunSummary& s) {
  write_file_atomically(directory_ + "/summary.json", summary_json(sim, s));
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
