// cli/python/interrupt.cpp — the worker thread and the caller's signal polling.
#include "cli/python/interrupt.hpp"

#include <pybind11/pybind11.h>

#include <chrono>
#include <exception>
#include <future>
#include <thread>

namespace py = pybind11;

namespace fortu::python {

void run_interruptible(const std::function<void(const std::atomic<bool>* cancel)>& work) {
    std::atomic<bool> cancel{false};
    std::packaged_task<void()> task([&] { work(&cancel); });
    std::future<void> done = task.get_future();
    bool interrupted = false;
    {
        py::gil_scoped_release release;
        std::thread worker(std::move(task));
        while (done.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) {
            if (interrupted) continue;
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) {
                interrupted = true;
                cancel = true;
            }
        }
        worker.join();
    }
    if (interrupted) throw py::error_already_set();   // the KeyboardInterrupt PyErr_CheckSignals set
    done.get();   // rethrows the work's exception
}

}  // namespace fortu::python
