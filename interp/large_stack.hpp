// interp/large_stack.hpp — lowering recurses through expressions and the bodies of inlined
// functions, up to the 'nesting' limit (limits.def). A main-thread stack of 8 MiB holds
// that in a release build but not in a sanitizer build, whose frames are several times
// larger; so compile() runs on a thread of its own with a stack sized for the limit
// (reserved, not committed: only the pages used cost memory; 64 MiB, since sanitizers map
// shadow memory for the whole stack of every thread).
#pragma once

#include <cstddef>
#include <functional>

namespace fortu {

/// Runs `work` on a thread with a `bytes` stack and waits for it; an exception thrown by
/// `work` is rethrown here. Runs `work` on this thread if no thread can be created.
void run_on_large_stack(const std::function<void()>& work, std::size_t bytes = std::size_t{64} << 20);

}  // namespace fortu
