#include "foldcast/core/resources.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "foldcast/core/error.hpp"

namespace foldcast {
namespace {
// A field of /proc/self/status or /proc/meminfo in kB ("MemAvailable:  123 kB"); 0 if absent.
std::uint64_t proc_kib(const char* file, const std::string& field) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(field + ":", 0) == 0) {
            std::istringstream value(line.substr(field.size() + 1));
            std::uint64_t kib = 0;
            value >> kib;
            return kib;
        }
    return 0;
}
}  // namespace

std::uint64_t memory_budget_bytes() {
    std::uint64_t budget = proc_kib("/proc/meminfo", "MemAvailable") * 1024;
    if (budget == 0) budget = UINT64_MAX;  // no /proc: no estimate to refuse by
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
        const std::uint64_t used = proc_kib("/proc/self/status", "VmSize") * 1024;
        budget = std::min<std::uint64_t>(budget, limit.rlim_cur > used ? limit.rlim_cur - used : 0);
    }
    return budget;
}

std::string human_bytes(std::uint64_t bytes) {
    char text[32];
    if (bytes >= (std::uint64_t(1) << 30))
        std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(std::uint64_t(1) << 30));
    else
        std::snprintf(text, sizeof text, "%.0f MiB", double(bytes) / double(1 << 20));
    return text;
}

void require_memory(std::uint64_t estimate_bytes, const std::string& what, const std::string& hint, bool force) {
    if (force) return;
    const std::uint64_t budget = memory_budget_bytes();
    if (estimate_bytes > budget)
        throw InputError(what + " needs about " + human_bytes(estimate_bytes) + " of memory, more than the " +
                         human_bytes(budget) + " this process can use (" + hint + ")");
}

}  // namespace foldcast
