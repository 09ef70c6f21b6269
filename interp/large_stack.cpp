// interp/large_stack.cpp — see large_stack.hpp. pthreads because std::thread cannot set
// the stack size.
#include "interp/large_stack.hpp"

#include <exception>

#include <pthread.h>

namespace fortu {
namespace {

struct Job {
    const std::function<void()>* work;
    std::exception_ptr error;
};

extern "C" void* run_job(void* argument) {
    auto* job = static_cast<Job*>(argument);
    try {
        (*job->work)();
    } catch (...) {
        job->error = std::current_exception();
    }
    return nullptr;
}

}  // namespace

void run_on_large_stack(const std::function<void()>& work, std::size_t bytes) {
    Job job{&work, nullptr};
    pthread_attr_t attributes;
    pthread_t thread;
    const bool ready = pthread_attr_init(&attributes) == 0;
    const bool started = ready && pthread_attr_setstacksize(&attributes, bytes) == 0 &&
                         pthread_create(&thread, &attributes, run_job, &job) == 0;
    if (ready) pthread_attr_destroy(&attributes);
    if (!started) {
        work();
        return;
    }
    pthread_join(thread, nullptr);
    if (job.error) std::rethrow_exception(job.error);
}

}  // namespace fortu
