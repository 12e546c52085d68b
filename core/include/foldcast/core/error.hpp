#pragma once
// Error types shared by every module.  The command line maps them to exit statuses:
// InputError -> 2 (usage or input error), anything else -> 1.
#include <stdexcept>
#include <string>

namespace foldcast {

// Something a user gave us is wrong: a file, key, flag or value.  The message names it and
// says what is allowed, in one line.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace foldcast
