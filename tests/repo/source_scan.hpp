#pragma once
// Reading the repository's own sources and docs for the checks in tests/repo: function
// lengths, doc references, the dependency table.  Deliberately small lexers, not a C++ or
// CMake parser: they need only braces, parentheses and argument lists.
#include <filesystem>
#include <string>
#include <vector>

namespace foldcast::repo_scan {

struct FunctionSpan {
    std::string file;
    std::string name;
    int first_line = 0;  // the line its signature starts on
    int lines = 0;       // signature to closing brace, both included
};

std::string read_text(const std::filesystem::path& path);

// Every function body defined at namespace or class scope in `source` (lambdas count with the
// function that holds them).
std::vector<FunctionSpan> function_spans(const std::string& source, const std::string& file);

// The C++ sources and headers under `roots` (relative to `repo`), sorted.
std::vector<std::filesystem::path> cpp_files(const std::filesystem::path& repo, const std::vector<std::string>& roots);

}  // namespace foldcast::repo_scan
