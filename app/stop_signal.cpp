// SIGINT / SIGTERM -> a stop request; the second signal -> the default action.
#include "stop_signal.hpp"

#include <signal.h>

#include <csignal>

namespace brittle {
namespace {

std::atomic<int> requested{0};
static_assert(std::atomic<int>::is_always_lock_free);  // safe in a signal handler

extern "C" void on_stop_signal(int sig) {
  if (requested.exchange(sig) != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

}  // namespace

std::atomic<int>& stop_signal() { return requested; }

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace brittle
