#pragma once
// The looks shipped in looks/data, loaded once per test binary from the source tree (not
// through FOLDCAST_LOOKS_DIR: these tests check the files in the repository).
#include <filesystem>

#include "foldcast/looks/looks.hpp"

namespace foldcast::test {

inline const looks::Library& shipped_looks() {
    static const looks::Library library =
        looks::Library::load_directory(std::filesystem::path(FOLDCAST_SOURCE_DIR) / "looks" / "data");
    return library;
}

}  // namespace foldcast::test
