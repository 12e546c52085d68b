#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "foldcast/serve/serve.hpp"
#include "test_paths.hpp"

namespace foldcast::serve {
namespace safe_path_test {
namespace fs = std::filesystem;

void write(const fs::path& file, const std::string& text) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
}

struct Tree {
    fs::path root, outside;
};
// root/{a.fca, sub/b.fca, link_in.fca -> a.fca, link_out.fca -> ../outside/secret.fca, dir_out -> ../outside}
Tree make_tree() {
    const fs::path dir = test::temp_dir();
    Tree t{dir / "root", dir / "outside"};
    write(t.root / "a.fca", "a");
    write(t.root / "sub" / "b.fca", "b");
    write(t.outside / "secret.fca", "secret");
    fs::create_symlink("a.fca", t.root / "link_in.fca");
    fs::create_symlink("../outside/secret.fca", t.root / "link_out.fca");
    fs::create_directory_symlink("../outside", t.root / "dir_out");
    return t;
}

TEST(ResolveInside, FilesBelowRootAndSymlinksThatStayInside) {
    const Tree t = make_tree();
    EXPECT_EQ(resolve_inside(t.root, "a.fca"), fs::canonical(t.root / "a.fca"));
    EXPECT_EQ(resolve_inside(t.root, "sub/b.fca"), fs::canonical(t.root / "sub/b.fca"));
    EXPECT_EQ(resolve_inside(t.root, "link_in.fca"), fs::canonical(t.root / "a.fca"));
}

TEST(ResolveInside, RefusesEveryWayOut) {
    const Tree t = make_tree();
    const std::string secret = fs::canonical(t.outside / "secret.fca").string();
    for (const std::string& path : std::vector<std::string>{
             "../outside/secret.fca", "sub/../../outside/secret.fca", "..", "sub/..", secret, "/" + secret,
             "link_out.fca", "dir_out/secret.fca", "sub\\..\\..\\outside\\secret.fca", std::string("a.fca\0x", 7), "",
             ".", "sub", "sub/", "./a.fca", "sub//b.fca", "missing.fca"})
        EXPECT_FALSE(resolve_inside(t.root, path).has_value()) << path;
}

TEST(ResolveInside, MissingRootServesNothing) {
    EXPECT_FALSE(resolve_inside(test::temp_dir() / "nope", "a.fca").has_value());
}

}  // namespace safe_path_test
}  // namespace foldcast::serve
