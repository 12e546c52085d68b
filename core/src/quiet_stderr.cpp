#include "foldcast/core/quiet_stderr.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>

namespace foldcast {

QuietStderr::QuietStderr() {
    std::fflush(stderr);
    char name[] = "/tmp/foldcast-stderr-XXXXXX";
    capture_ = ::mkstemp(name);
    if (capture_ < 0) return;  // nothing captured: the library's text stays visible
    ::unlink(name);
    saved_ = ::dup(2);
    if (saved_ < 0 || ::dup2(capture_, 2) < 0) {
        if (saved_ >= 0) ::close(saved_);
        ::close(capture_);
        saved_ = capture_ = -1;
    }
}

QuietStderr::~QuietStderr() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    ::close(capture_);
}

std::string QuietStderr::first_line() const {
    if (capture_ < 0) return {};
    std::fflush(stderr);
    char buffer[256];
    const ssize_t n = ::pread(capture_, buffer, sizeof buffer - 1, 0);
    if (n <= 0) return {};
    std::string text(buffer, static_cast<std::size_t>(n));
    const auto end = text.find('\n');
    if (end != std::string::npos) text.resize(end);
    if (text.size() > 200) text.resize(200);
    return text;
}

}  // namespace foldcast
