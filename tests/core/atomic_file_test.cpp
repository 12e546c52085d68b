#include <gtest/gtest.h>

#include <fstream>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {

std::size_t entries(const std::filesystem::path& dir) {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir), {}));
}

TEST(AtomicFile, NothingVisibleUntilCommit) {
    const auto dir = test::temp_dir();
    {
        AtomicFile f(dir / "out.txt");
        f.stream() << "hello";
        EXPECT_FALSE(std::filesystem::exists(dir / "out.txt"));
        f.commit();
    }
    std::ifstream in(dir / "out.txt");
    std::string s;
    in >> s;
    EXPECT_EQ(s, "hello");
    EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AbandonedWriteLeavesNoFile) {
    const auto dir = test::temp_dir();
    write_file_atomically(dir / "keep.txt", "old");
    try {
        AtomicFile f(dir / "keep.txt");
        f.stream() << "half";
        throw std::runtime_error("interrupted");
    } catch (const std::runtime_error&) {
    }
    std::ifstream in(dir / "keep.txt");
    std::string s;
    in >> s;
    EXPECT_EQ(s, "old");
    EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, MissingDirectoryIsInputError) {
    const auto dir = test::temp_dir();
    EXPECT_THROW(AtomicFile(dir / "no" / "such" / "x.txt"), InputError);
    EXPECT_THROW(check_writable(dir), InputError);
    EXPECT_NO_THROW(check_writable(dir / "fine.txt"));
}

}  // namespace
}  // namespace foldcast
