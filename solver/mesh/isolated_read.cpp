// Readers in a child process (docs/mesh.md, "Reading files safely").
#include "isolated_read.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <SMP/Common/vtkSMPToolsAPI.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "error.hpp"

// AddressSanitizer in this build (GCC: __SANITIZE_ADDRESS__, clang: __has_feature).
#if defined(__SANITIZE_ADDRESS__)
#define BRITTLE_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BRITTLE_ASAN 1
#endif
#endif
#ifdef BRITTLE_ASAN
#include <sanitizer/common_interface_defs.h>
#endif

namespace brittle {
namespace {

/// Writes all of `bytes` to fd (the child's end of the pipe).
void write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::string read_isolated(const std::string& what, const std::string& reader,
                          const std::string& expected, std::uintmax_t file_bytes,
                          const std::function<void(StateWriter&)>& read) {
  int fds[2];
  BRITTLE_CHECK(::pipe2(fds, O_CLOEXEC) == 0, what, ": cannot start the reader (", std::strerror(errno), ")");
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]), ::close(fds[1]);
    throw Error(error_message(what, ": cannot start the reader (", std::strerror(errno), ")"));
  }
  if (pid == 0) {  // the child: read, send, _exit (no destructors, no atexit handlers)
    ::close(fds[0]);
    // Whatever the library prints (or a sanitizer's report) is not the user's: the parent
    // says what happened in one line. A fault ends the child with its signal.
    if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, 2), ::close(null);
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) ::signal(sig, SIG_DFL);
    // The child has one thread: the parent's thread pools (TBB's workers behind vtkSMPTools,
    // OpenMP's, Mesa's) did not come with it, and a task handed to a pool whose threads are
    // gone waits for ever. The reader runs its SMP loops on this thread instead (through
    // vtkSMPToolsAPI: VTK 9.1's vtkSMPTools.h does not compile as C++20 under GCC 12).
    vtk::detail::smp::vtkSMPToolsAPI::GetInstance().SetBackend("Sequential");
#ifdef BRITTLE_ASAN
    // A sanitizer report in the child is the child's failure, not the parent's (libFuzzer
    // registers a death callback that would record the input as a crash of the fuzzer).
    __sanitizer_set_death_callback(nullptr);
#else
    // A header that claims billions of points must not take the machine's memory.
    const rlim_t limit = std::max<rlim_t>(rlim_t(4) << 30, rlim_t(200) * file_bytes);
    const rlimit as{limit, limit};
    ::setrlimit(RLIMIT_AS, &as);
#endif
    std::string out;
    try {
      StateWriter w;
      std::uint8_t ok = 1;
      io(w, ok);
      read(w);
      out = std::move(w.bytes());
    } catch (const std::exception& e) {
      StateWriter w;
      std::uint8_t ok = 0;
      std::string message = e.what();
      io_all(w, ok, message);
      out = std::move(w.bytes());
    } catch (...) {
      StateWriter w;
      std::uint8_t ok = 0;
      std::string message = "the reader failed";
      io_all(w, ok, message);
      out = std::move(w.bytes());
    }
    write_all(fds[1], out);
    ::_exit(0);
  }
  ::close(fds[1]);
  // Generous: a valid 1.8 M-tet file reads in seconds.
  const double seconds = 60.0 + 2.0 * static_cast<double>(file_bytes) / 1e6;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  std::string bytes;
  bool timed_out = false;
  char buffer[1 << 16];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string tail = " (expected " + expected + ")";
  BRITTLE_CHECK(!timed_out, what, ": the ", reader, " did not finish in ", seconds, " s", tail);
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = sig == SIGSEGV ? "SIGSEGV" : sig == SIGFPE ? "SIGFPE" : sig == SIGABRT ? "SIGABRT"
                     : sig == SIGBUS ? "SIGBUS" : sig == SIGKILL ? "SIGKILL, out of memory?" : "a signal";
    throw Error(error_message(what, ": the ", reader, " crashed (", name, ") on this file", tail));
  }
  BRITTLE_CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0 && !bytes.empty(), what, ": the ",
                reader, " failed on this file (exit ", WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                ")", tail);
  StateReader r(bytes.data(), bytes.data() + bytes.size(), what);
  std::uint8_t ok = 0;
  io(r, ok);
  if (!ok) {
    std::string message;
    io(r, message);
    throw Error(error_message(what, ": cannot be read (", escape_control(message), ")", tail));
  }
  return bytes.substr(1);
}

vtkSmartPointer<vtkUnstructuredGrid> joined_by_serial_ids(vtkUnstructuredGrid& g,
                                                          const std::string& what) {
  vtkDataArray* nodes = g.GetPointData()->GetArray("global_node");
  vtkDataArray* cells = g.GetCellData()->GetArray("global_cell");
  if (!nodes || !cells) return vtkSmartPointer<vtkUnstructuredGrid>(&g);
  const vtkIdType np = g.GetNumberOfPoints(), nc = g.GetNumberOfCells();
  vtkIdType most = -1;
  for (vtkIdType p = 0; p < np; ++p) most = std::max(most, static_cast<vtkIdType>(nodes->GetTuple1(p)));
  BRITTLE_CHECK(most >= 0 && most < np, what, ": global_node ids out of range (expected ids "
                "below the pieces' ", np, " points)");
  std::vector<vtkIdType> first(most + 1, -1);  // serial node -> a point holding it
  for (vtkIdType p = 0; p < np; ++p) {
    const auto id = static_cast<vtkIdType>(nodes->GetTuple1(p));
    BRITTLE_CHECK(id >= 0, what, ": negative global_node id");
    if (first[id] < 0) first[id] = p;
  }
  std::vector<vtkIdType> order(nc);  // cells by serial id
  for (vtkIdType c = 0; c < nc; ++c) order[c] = c;
  std::sort(order.begin(), order.end(), [&](vtkIdType a, vtkIdType b) {
    return cells->GetTuple1(a) < cells->GetTuple1(b);
  });
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(most + 1);
  out->GetPointData()->CopyAllocate(g.GetPointData(), most + 1);
  for (vtkIdType id = 0; id <= most; ++id) {
    BRITTLE_CHECK(first[id] >= 0, what, ": node ", id, " is in no piece");
    points->SetPoint(id, g.GetPoint(first[id]));
    out->GetPointData()->CopyData(g.GetPointData(), first[id], id);
  }
  out->SetPoints(points);
  auto connectivity = vtkSmartPointer<vtkCellArray>::New();
  out->GetCellData()->CopyAllocate(g.GetCellData(), nc);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < nc; ++c) {
    g.GetCellPoints(order[c], ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      ids->SetId(k, static_cast<vtkIdType>(nodes->GetTuple1(ids->GetId(k))));
    connectivity->InsertNextCell(ids);
    out->GetCellData()->CopyData(g.GetCellData(), order[c], c);
  }
  out->SetCells(VTK_TETRA, connectivity);
  out->GetFieldData()->ShallowCopy(g.GetFieldData());
  out->GetPointData()->RemoveArray("global_node");
  out->GetCellData()->RemoveArray("global_cell");
  return out;
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu_isolated(const std::string& path,
                                                       const std::string& what) {
  std::error_code ec;
  BRITTLE_CHECK(std::filesystem::is_regular_file(path, ec), what, " '", path, "' does not exist");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  // A decomposed run's frame (.pvtu) names its pieces: VTK's parallel reader joins them.
  const bool pieces = path.ends_with(".pvtu");
  const std::string bytes = read_isolated(
      what + " '" + path + "'", "VTK reader",
      pieces ? "a VTK XML parallel unstructured grid (.pvtu) and its pieces"
             : "a VTK XML unstructured grid (.vtu)",
      size, [&](StateWriter& w) {
        vtkSmartPointer<vtkXMLReader> reader;
        if (pieces)
          reader = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
        else
          reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
        vtkNew<VtkErrorFlag> failed;
        reader->AddObserver(vtkCommand::ErrorEvent, failed);
        if (!reader->CanReadFile(path.c_str()))
          throw std::runtime_error("not a VTK XML unstructured grid");
        reader->SetFileName(path.c_str());
        reader->Update();
        vtkUnstructuredGrid* grid = vtkUnstructuredGrid::SafeDownCast(reader->GetOutputDataObject(0));
        if (failed->failed || !grid || grid->GetNumberOfCells() == 0)
          throw std::runtime_error("the VTK reader found no cells or reported an error");
        vtkNew<vtkXMLUnstructuredGridWriter> writer;  // back to the parent in VTK's own form
        writer->SetInputData(grid);
        writer->WriteToOutputStringOn();
        writer->SetDataModeToAppended();
        writer->EncodeAppendedDataOff();
        writer->SetCompressorTypeToNone();
        if (writer->Write() != 1) throw std::runtime_error("cannot pass the grid on");
        std::string text = writer->GetOutputString();
        io(w, text);
      });
  StateReader r(bytes.data(), bytes.data() + bytes.size(), what);
  std::string text;
  io(r, text);
  vtkNew<vtkXMLUnstructuredGridReader> reader;  // the child's own output: trusted
  reader->ReadFromInputStringOn();
  reader->SetInputString(text);
  reader->Update();
  auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
  copy->ShallowCopy(reader->GetOutput());
  BRITTLE_CHECK(copy->GetNumberOfCells() > 0, what, " '", path, "' has no cells");
  return pieces ? joined_by_serial_ids(*copy, what + " '" + path + "'") : copy;
}

std::string escape_control(const std::string& text) {
  std::string out;
  auto escape = [&](unsigned char c) {
    char code[8];
    std::snprintf(code, sizeof code, "\\x%02x", c);
    out += code;
  };
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      escape(c), ++i;
      continue;
    }
    if (c < 0x80) {
      out += static_cast<char>(c), ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (no C1 controls) passes; any other byte is escaped.
    const int n = c >= 0xf0 && c < 0xf5 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 && c < 0xe0 ? 2 : 0;
    bool valid = n > 0 && i + n <= text.size();
    for (int k = 1; valid && k < n; ++k) valid = (static_cast<unsigned char>(text[i + k]) & 0xc0) == 0x80;
    if (valid && n == 2 && c == 0xc2 && static_cast<unsigned char>(text[i + 1]) < 0xa0) valid = false;
    if (!valid) {
      escape(c), ++i;
      continue;
    }
    out.append(text, i, n);
    i += n;
  }
  return out;
}

}  // namespace brittle
