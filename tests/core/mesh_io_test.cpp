#include <gtest/gtest.h>

#include <fstream>

#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {

Mesh small_mesh() {
    Mesh m;
    m.positions = {Vec3f(0, 0, 0), Vec3f(1, 0, 0.5f), Vec3f(1, 1, 0), Vec3f(0, 1, -0.25f)};
    m.topology.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.topology.uvs = {Vec2f(0, 0), Vec2f(0.3f, 0), Vec2f(0.3f, 0.3f), Vec2f(0, 0.3f)};
    m.normals = vertex_normals(m.positions, m.topology.triangles);
    return m;
}

TEST(Obj, RoundTripKeepsPositionsUvsAndTriangles) {
    const auto dir = test::temp_dir();
    const Mesh m = small_mesh();
    write_obj(dir / "m.obj", m);
    const Mesh r = read_obj(dir / "m.obj");
    ASSERT_EQ(r.positions.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR((r.positions[i] - m.positions[i]).norm(), 0.0f, 1e-6f);
        EXPECT_NEAR((r.topology.uvs[i] - m.topology.uvs[i]).norm(), 0.0f, 1e-6f);
    }
    EXPECT_EQ(r.topology.triangles, m.topology.triangles);
}

TEST(Obj, ReadsBlenderExport) {
    const Mesh m = read_obj(test::test_data("animations/basicCloth.obj"));
    EXPECT_EQ(m.positions.size(), 81u);
    EXPECT_EQ(m.topology.triangles.size(), 128u);
    EXPECT_TRUE(m.topology.uvs.empty());
}

TEST(Obj, MissingFileIsInputError) { EXPECT_THROW(read_obj("/nonexistent/x.obj"), InputError); }

TEST(Ply, HeaderAndSize) {
    const auto dir = test::temp_dir();
    const Mesh m = small_mesh();
    write_ply(dir / "m.ply", m);
    std::ifstream in(dir / "m.ply", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    ASSERT_EQ(all.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    const auto body = all.size() - (all.find("end_header\n") + 11);
    EXPECT_EQ(body, 4u * 8u * 4u + 2u * (1u + 12u));
}

TEST(Pc2, RoundTripIsExact) {
    const auto dir = test::temp_dir();
    std::vector<std::vector<Vec3f>> frames(3, small_mesh().positions);
    frames[2][1] = Vec3f(1e-7f, -3.25f, 12345.5f);
    write_pc2(dir / "a.pc2", frames, {2.0f, 0.5f});
    Pc2Info info;
    const auto r = read_pc2(dir / "a.pc2", &info);
    EXPECT_EQ(r, frames);
    EXPECT_EQ(info.start_frame, 2.0f);
    EXPECT_EQ(info.sampling, 0.5f);
    EXPECT_EQ(std::filesystem::file_size(dir / "a.pc2"), 32u + 3u * 4u * 12u);
}

TEST(Pc2, ReadsBlenderCache) {
    Pc2Info info;
    const auto frames = read_pc2(test::test_data("animations/basicCloth.pc2"), &info);
    EXPECT_EQ(frames.size(), 150u);
    EXPECT_EQ(frames[0].size(), 81u);
    EXPECT_EQ(info.start_frame, 1.0f);
}

TEST(Pc2, TruncatedFileIsInputError) {
    const auto dir = test::temp_dir();
    std::ifstream in(test::test_data("animations/basicCloth.pc2"), std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "cut.pc2", std::ios::binary).write(all.data(), 1000);
    EXPECT_THROW(read_pc2(dir / "cut.pc2"), InputError);
    std::ofstream(dir / "junk.pc2", std::ios::binary) << "POINTCACHE3 and more bytes than a header";
    EXPECT_THROW(read_pc2(dir / "junk.pc2"), InputError);
}

TEST(Pc2, AnimationWithTopologyBeside) {
    const auto dir = test::temp_dir();
    Animation a;
    a.frames = {small_mesh().positions, small_mesh().positions};
    a.topology = small_mesh().topology;
    write_pc2_animation(dir / "anim.pc2", a);
    ASSERT_TRUE(std::filesystem::exists(dir / "anim.obj"));
    const Animation r = read_pc2_animation(dir / "anim.pc2", dir / "anim.obj");
    EXPECT_EQ(r.frames, a.frames);
    EXPECT_EQ(r.topology.triangles, a.topology.triangles);
}

TEST(Pc2, MismatchedTopologyIsInputError) {
    EXPECT_THROW(
        read_pc2_animation(test::test_data("animations/basicCloth.pc2"), test::test_data("animations/missing.obj")),
        InputError);
}

}  // namespace
}  // namespace foldcast
