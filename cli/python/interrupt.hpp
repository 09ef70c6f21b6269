// cli/python/interrupt.hpp — long evaluations run without the GIL and stop on Ctrl-C.
//
// Why a second thread: Python runs signal handlers (KeyboardInterrupt) only in the main
// thread, between bytecodes, so an evaluation holding the main thread would ignore Ctrl-C
// until it ended. The work runs on its own thread; the caller waits with the GIL released
// (other Python threads run) and every 20 ms takes the GIL to ask PyErr_CheckSignals; on
// an exception it sets the engines' cancel flag (EvalOptions::cancel), waits for the work
// to stop, and raises.
#pragma once

#include <atomic>
#include <functional>

namespace fortu::python {

/// Runs work(cancel) as described above; called with the GIL held. Exceptions from `work`
/// are rethrown here; a pending Python exception (KeyboardInterrupt) is raised as
/// pybind11::error_already_set.
void run_interruptible(const std::function<void(const std::atomic<bool>* cancel)>& work);

}  // namespace fortu::python
