// Stopping a long job cleanly (`trackbed run`, `trackbed build-sample`): Ctrl-C (SIGINT) and
// SIGTERM only raise a flag, which the job reads between steps to write a checkpoint and end with
// exit code 130; `trackbed resume DIR` goes on from there.
#pragma once

#include <utility>

namespace trackbed::cases {

// Installs the handlers of SIGINT and SIGTERM.
void catch_stop_signals();
// The signal received since, 0 if none.
int stop_signal();
// TRACKBED_TEST_SIGNAL="STEP SIGNAL": the job sends itself SIGNAL at its step STEP, so that tests
// can interrupt (SIGTERM) or kill (SIGKILL) it at a chosen point; {-1, 0} when unset.
std::pair<long, int> test_signal_from_environment();

}  // namespace trackbed::cases
