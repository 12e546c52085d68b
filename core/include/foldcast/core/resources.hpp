#pragma once
// Resource estimates before work: a command that would need more memory than this process
// may use refuses up front, naming the estimate, instead of failing minutes later with an
// allocation error.  The budget is the smaller of the memory the machine has available and
// the address space left under this process's limit (RLIMIT_AS).
#include <cstdint>
#include <string>

namespace foldcast {

// Bytes this process can still allocate (an estimate; at least the machine's
// MemAvailable and the RLIMIT_AS headroom both allow it).
std::uint64_t memory_budget_bytes();

// "1.5 GiB", "300 MiB": for the messages below.
std::string human_bytes(std::uint64_t bytes);

// Throws InputError "WHAT needs about N of memory, more than the M this process can use
// (HINT)" when `estimate_bytes` exceeds memory_budget_bytes() and `force` is false.
// `hint` says what to change (e.g. "a smaller --grid, or --force to try anyway").
void require_memory(std::uint64_t estimate_bytes, const std::string& what, const std::string& hint, bool force);

}  // namespace foldcast
