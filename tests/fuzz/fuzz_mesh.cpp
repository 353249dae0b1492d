// Fuzzes the mesh.file path for one extension (BRITTLE_FUZZ_EXTENSION: ".vtu" -> fuzz_vtu,
// ".msh" -> fuzz_msh): brittle's checks, the reader in its child process and the result coming
// back (plate_mesh.cpp, isolated_read.cpp). A crash of the library in the child is an expected
// outcome for some inputs (an error message); a crash, leak or undefined behaviour in this
// process is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "error.hpp"
#include "plate_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string file =
      "/tmp/brittle_fuzz_" + std::to_string(getpid()) + BRITTLE_FUZZ_EXTENSION;
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    auto mesh = brittle::read_mesh(file);
    if (!mesh || mesh->GetNumberOfCells() == 0) std::abort();  // a mesh or an error, nothing else
  } catch (const brittle::Error& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) std::abort();  // one line only
  }
  return 0;
}
