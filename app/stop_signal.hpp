// SIGINT / SIGTERM as a request to stop (docs/checkpoint.md): the first sets a flag that runs
// and sweeps poll; a second one ends the process at once (the signal's default action).
#pragma once

#include <atomic>

namespace brittle {

/// The signal that asked for a stop (SIGINT or SIGTERM), 0 while none did.
std::atomic<int>& stop_signal();

/// Installs the handler for SIGINT and SIGTERM (without SA_RESTART: a blocking wait returns
/// EINTR so that the caller sees the flag).
void install_stop_handlers();

}  // namespace brittle
