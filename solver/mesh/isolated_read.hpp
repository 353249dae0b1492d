// Third-party readers on untrusted files, where their crash cannot take the run down
// (docs/mesh.md, "Reading files safely"): the reader runs in a child process (fork), with a
// memory limit and a deadline, and hands back its result through a pipe, or a message.
#pragma once

#include <functional>
#include <string>

#include <vtkCommand.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "archive.hpp"

namespace brittle {

/// Observes a VTK reader's error (and warning) events instead of letting them print: `failed`
/// says whether one came.
class VtkErrorFlag : public vtkCommand {
 public:
  static VtkErrorFlag* New() { return new VtkErrorFlag; }
  void Execute(vtkObject*, unsigned long, void*) override { failed = true; }
  bool failed = false;
};

/// Runs `read` in a child process; it writes its result into the StateWriter. Returns the
/// bytes it wrote, or throws brittle::Error "<what>: <reader> crashed (SIGSEGV) on this file
/// (expected <expected>)" when the child died, ran out of memory or time, and "<what>: <its
/// message> (expected ...)" when `read` threw. `file_bytes` sizes the deadline and memory limit.
std::string read_isolated(const std::string& what, const std::string& reader,
                          const std::string& expected, std::uintmax_t file_bytes,
                          const std::function<void(StateWriter&)>& read);

/// A VTK XML unstructured grid (.vtu) with all its arrays, read in a child process: for
/// frames of `brittle render`. Throws brittle::Error naming the file if it cannot be read.
vtkSmartPointer<vtkUnstructuredGrid> read_vtu_isolated(const std::string& path,
                                                       const std::string& what);

/// The pieces of a decomposed run's frame, appended into `g`, as the serial run's grid: a node
/// shared by pieces once, nodes and cells in the serial order (their global_node / global_cell
/// arrays, then dropped), so that piece boundaries are not seen as crack faces and frames
/// render as the serial ones. `g` itself if it has no such arrays.
vtkSmartPointer<vtkUnstructuredGrid> joined_by_serial_ids(vtkUnstructuredGrid& g,
                                                          const std::string& what);

/// Replaces control bytes (and bytes that are not UTF-8) with \xNN escapes, so that a message
/// that quotes a binary file prints as one harmless line.
std::string escape_control(const std::string& text);

}  // namespace brittle
