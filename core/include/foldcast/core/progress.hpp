#pragma once
// Long-running library calls report progress through a callback; the command line draws
// it on stderr.  Libraries never print.
#include <functional>
#include <string_view>

namespace foldcast {

// fraction in [0, 1]; `stage` names the work ("frames", "tiles", ...).  May be called from
// several threads at once: implementations must be thread-safe.
using ProgressFn = std::function<void(std::string_view stage, double fraction)>;

}  // namespace foldcast
