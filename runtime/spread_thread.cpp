// runtime/spread_thread.cpp — see spread_thread.hpp.
#include "runtime/spread_thread.hpp"

#include <sched.h>

#include <cerrno>
#include <memory>
#include <system_error>

namespace fortu {

namespace {

struct Start {
    std::function<void()> work;
    cpu_set_t allowed;       ///< the process's cores when the thread was made
    bool narrowed = false;   ///< started on fewer, so widen back
};

void* run_started(void* argument) {
    std::unique_ptr<Start> start(static_cast<Start*>(argument));
    if (start->narrowed) pthread_setaffinity_np(pthread_self(), sizeof start->allowed, &start->allowed);
    start->work();   // the callers catch their work's exceptions themselves
    return nullptr;
}

}  // namespace

SpreadThread::SpreadThread(std::function<void()> work) {
    auto start = std::make_unique<Start>();
    start->work = std::move(work);
    pthread_attr_t attributes;
    if (int error = pthread_attr_init(&attributes)) throw std::system_error(error, std::generic_category(), "thread");
    cpu_set_t elsewhere;
    const int here = sched_getcpu();
    if (sched_getaffinity(0, sizeof start->allowed, &start->allowed) == 0 && here >= 0 && here < CPU_SETSIZE &&
        CPU_ISSET(here, &start->allowed) && CPU_COUNT(&start->allowed) > 1) {
        elsewhere = start->allowed;
        CPU_CLR(here, &elsewhere);
        start->narrowed = pthread_attr_setaffinity_np(&attributes, sizeof elsewhere, &elsewhere) == 0;
    }
    int error = pthread_create(&thread_, &attributes, run_started, start.get());
    if (error == EINVAL && start->narrowed) {   // a core gone offline since: start anywhere
        pthread_attr_destroy(&attributes);
        pthread_attr_init(&attributes);
        start->narrowed = false;
        error = pthread_create(&thread_, &attributes, run_started, start.get());
    }
    pthread_attr_destroy(&attributes);
    if (error) throw std::system_error(error, std::generic_category(), "thread");
    start.release();   // run_started owns it now
    joinable_ = true;
}

void SpreadThread::join() {
    if (!joinable_) return;
    joinable_ = false;
    pthread_join(thread_, nullptr);
}

}  // namespace fortu
