// VTU/PVD time series, energy CSV and run summary (SPEC 9).
#include "output.hpp"

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <vtkXMLDataElement.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLUtilities.h>

#include "error.hpp"

namespace fs = std::filesystem;

namespace brittle {

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    BRITTLE_CHECK(out, "output: cannot write '", tmp, "'");
    out << text;
    BRITTLE_CHECK(out.flush(), "output: cannot write '", tmp, "'");
  }
  fs::rename(tmp, path);
}

VtuSeriesWriter::VtuSeriesWriter(std::string directory)
    : directory_(std::move(directory)), pvd_path_(directory_ + "/run.pvd") {
  fs::create_directories(directory_ + "/frames");
}

void VtuSeriesWriter::on_frame(const Simulation& sim) {
  std::ostringstream name;
  name << "frames/frame_" << std::setw(4) << std::setfill('0') << frames_.size() << ".vtu";
  const std::string path = directory_ + "/" + name.str();
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->SetInputData(sim.grid().vtk());
  writer->SetFileName((path + ".tmp").c_str());
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  BRITTLE_CHECK(writer->Write() == 1, "output: cannot write '", path, "'");
  fs::rename(path + ".tmp", path);
  frames_.emplace_back(sim.time(), name.str());

  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n"
      << std::setprecision(17);
  for (const auto& [t, file] : frames_)
    pvd << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file
        << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  write_file_atomically(pvd_path_, pvd.str());
}

std::vector<PvdEntry> read_pvd(const std::string& path) {
  BRITTLE_CHECK(fs::is_regular_file(path), "time series '", path, "': no such file");
  vtkSmartPointer<vtkXMLDataElement> root;
  root.TakeReference(vtkXMLUtilities::ReadElementFromFile(path.c_str()));
  BRITTLE_CHECK(root && root->GetAttribute("type") &&
                    std::string(root->GetAttribute("type")) == "Collection",
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

EnergyCsvWriter::EnergyCsvWriter(const std::string& directory)
    : out_(directory + "/energies.csv", std::ios::trunc) {
  BRITTLE_CHECK(out_, "output: cannot write '", directory, "/energies.csv'");
  out_ << "time,kinetic,elastic,viscous_dissipated,total,relative_imbalance\n";
}

void EnergyCsvWriter::on_energy(const Simulation&, const Energies& e) {
  if (initial_ < 0) initial_ = e.total();
  const double imbalance = initial_ > 0 ? (e.total() - initial_) / initial_ : 0.0;
  out_ << std::setprecision(12) << e.time << ',' << e.kinetic << ',' << e.elastic << ','
       << e.viscous_dissipated << ',' << e.total() << ',' << imbalance << '\n';
  out_.flush();
}

void SummaryWriter::on_finish(const Simulation& sim, const RunSummary& s) {
  std::string status;
  for (char c : s.status) status += (c == '"' || c == '\\') ? '\'' : c;
  const Energies& e = s.final_energies;
  std::ostringstream j;
  j << std::setprecision(10) << "{\n"
    << "  \"status\": \"" << status << "\",\n"
    << "  \"nodes\": " << s.nodes << ",\n"
    << "  \"tets\": " << s.tets << ",\n"
    << "  \"fixed_nodes\": " << s.fixed_nodes << ",\n"
    << "  \"sigma\": " << s.sigma << ",\n"
    << "  \"sigma_over_sigmac\": " << s.sigma / sim.scene().material.sigma_c << ",\n"
    << "  \"dt\": " << s.dt << ",\n"
    << "  \"end_time\": " << s.end_time << ",\n"
    << "  \"time\": " << s.time << ",\n"
    << "  \"steps\": " << s.steps << ",\n"
    << "  \"threads\": " << s.threads << ",\n"
    << "  \"wall_seconds\": " << s.wall_seconds << ",\n"
    << "  \"tet_updates_per_second\": " << s.tet_updates_per_second << ",\n"
    << "  \"initial_energy\": " << s.initial_elastic << ",\n"
    << "  \"final_kinetic\": " << e.kinetic << ",\n"
    << "  \"final_elastic\": " << e.elastic << ",\n"
    << "  \"viscous_dissipated\": " << e.viscous_dissipated << ",\n"
    << "  \"max_relative_imbalance\": " << s.max_relative_imbalance << "\n"
    << "}\n";
  write_file_atomically(directory_ + "/summary.json", j.str());
}

OutputWriters::OutputWriters(const Simulation& sim) {
  const std::string& dir = sim.scene().output.directory;
  fs::create_directories(dir);
  if (sim.scene().output.vtu) writers_.push_back(std::make_unique<VtuSeriesWriter>(dir));
  writers_.push_back(std::make_unique<EnergyCsvWriter>(dir));
  writers_.push_back(std::make_unique<SummaryWriter>(dir));
}

std::vector<Observer*> OutputWriters::observers() {
  std::vector<Observer*> list;
  for (auto& w : writers_) list.push_back(w.get());
  return list;
}

}  // namespace brittle
