// VTU/PVD time series (SPEC 9): a serial run's frames, a decomposed run's pieces and the
// .pvtu that names them, the .pvd collections, and the whole grid gathered from the pieces.

#include "output.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLUtilities.h>

#include <filesystem>
#include <iomanip>
#include <sstream>
#include <tuple>

#include "error.hpp"
#include "halo.hpp"
#include "isolated_read.hpp"

namespace fs = std::filesystem;

namespace brittle {

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
  const int corners = grid.corners();
  for (vtkIdType e = 0; e < grid.num_cells(); ++e) {
    if (!halo.owns_cell(e)) continue;
    cells.push_back(e);
    for (int k = 0; k < corners; ++k) {
      const vtkIdType p = grid.cells()[corners * e + k];
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
    const vtkIdType* c = grid.cells() + corners * cells[i];
    vtkIdType ids[4];
    for (int k = 0; k < corners; ++k) ids[k] = node[c[k]];
    connectivity->InsertNextCell(corners, ids);
    piece->GetCellData()->CopyData(g->GetCellData(), cells[i], static_cast<vtkIdType>(i));
    global_cell->InsertNextValue(halo.global_cell()[cells[i]]);
  }
  piece->SetCells(corners == 3 ? VTK_TRIANGLE : VTK_TETRA, connectivity);
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
  all->SetCells(sim.grid().corners() == 3 ? VTK_TRIANGLE : VTK_TETRA, cells);
  all->GetFieldData()->ShallowCopy(grids.front()->GetFieldData());
  return joined_by_serial_ids(*all, "the run's pieces");
}

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

}  // namespace brittle
