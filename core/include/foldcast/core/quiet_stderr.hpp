#pragma once
// Some libraries (libpng and libjpeg through OpenCV) print their own warnings straight to
// file descriptor 2 before we can report the problem in one line naming the file.  While a
// QuietStderr lives, what is written to fd 2 goes to a temporary file instead; text()
// returns it (for a message) and the destructor restores fd 2.  Output other threads write to
// stderr meanwhile is captured too, so keep the scope to the library call.
#include <string>

namespace foldcast {

class QuietStderr {
public:
    QuietStderr();
    ~QuietStderr();
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

    // What was written to fd 2 so far, trimmed to its first line (at most 200 characters).
    std::string first_line() const;

private:
    int saved_ = -1;
    int capture_ = -1;
};

}  // namespace foldcast
