// Errors: an always-on check for input boundaries and a debug-only assert for hot loops.
#pragma once

#include <cassert>
#include <sstream>
#include <stdexcept>
#include <string>

namespace brittle {

/// Thrown for bad input or a run that cannot go on; the message is one line that names
/// the file / key / value and what was expected. `main` prints it and exits non-zero.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Builds a message from stream-able parts: error_message("key ", k, " must be > 0").
template <class... Parts>
std::string error_message(const Parts&... parts) {
  std::ostringstream s;
  (s << ... << parts);
  return s.str();
}

}  // namespace brittle

/// Always-on check: throws brittle::Error built from the remaining arguments.
#define BRITTLE_CHECK(cond, ...) \
  do {                           \
    if (!(cond)) throw ::brittle::Error(::brittle::error_message(__VA_ARGS__)); \
  } while (0)

/// Debug-only check for hot loops.
#define BRITTLE_ASSERT(cond) assert(cond)
