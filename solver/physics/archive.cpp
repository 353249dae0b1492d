// StateWriter's file output (archive.hpp).
#include "archive.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>

namespace brittle {

void StateWriter::write_out(const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0 && error_ == 0) {
    const ssize_t n = ::write(fd_, p, std::min<std::size_t>(size, kBlock << 4));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error_ = n < 0 ? errno : EIO;
      break;
    }
    p += n, size -= static_cast<std::size_t>(n);
    if (kill_) std::raise(SIGKILL);  // tests only: a kill after the first block is out
  }
}

void StateWriter::flush() {
  if (fd_ < 0 || bytes_.empty()) return;
  write_out(bytes_.data(), bytes_.size());
  bytes_.clear();
}

}  // namespace brittle
