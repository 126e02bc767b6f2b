#include "cases/app/stop_signal.h"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <sstream>

namespace trackbed::cases {

namespace {

std::atomic<int> g_signal{0};
extern "C" void on_signal(int s) {
  g_signal = s;
}

}  // namespace

void catch_stop_signals() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

int stop_signal() {
  return g_signal;
}

std::pair<long, int> test_signal_from_environment() {
  std::pair<long, int> s{-1, 0};
  if (const char* v = std::getenv("TRACKBED_TEST_SIGNAL")) {
    std::istringstream in(v);
    in >> s.first >> s.second;
  }
  return s;
}

}  // namespace trackbed::cases
