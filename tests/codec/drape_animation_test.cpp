// The codec on foldcast's own garments: a drape animation (regular grid, folds forming).
// Only the test links drape; the codec library itself never does.
#include <gtest/gtest.h>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "foldcast/drape/drape.hpp"
#include "run_command.hpp"
#include "test_paths.hpp"

namespace foldcast::codec {
namespace {

Animation small_drape() {
    drape::AnimationOptions options;
    options.frames = 40;
    return drape::animate(drape::ClothParams{}, drape::GridSize{16, 12}, options);
}

TEST(DrapeAnimation, BothProfilesMeetTheBoundAndKeepUvs) {
    const Animation a = small_drape();
    for (Profile p : {Profile::predictive, Profile::paper}) {
        EncodeOptions o;
        o.profile = p;
        o.max_error_m = 2e-4;
        const std::string bytes = encode(a, o);
        const Animation b = decode(bytes);
        EXPECT_EQ(b.topology.uvs, a.topology.uvs);
        EXPECT_LE(measure(a, b, bytes.size()).max_error_m, 2e-4 * (1.0 + 1e-5)) << profile_name(p);
    }
}

TEST(DrapeAnimation, DefaultProfileBeatsRawFloatsByFar) {
    const Animation a = small_drape();
    const std::string bytes = encode(a, {});
    EXPECT_LT(measure(a, decode(bytes), bytes.size()).bpvf, 96.0 / 4.0);
}

TEST(DrapeAnimation, DrapeWritesFcaThatDecodesToPc2) {
    const auto dir = test::temp_dir();
    const std::string bin = test::foldcast_binary();
    const std::string fca = (dir / "anim.fca").string(), pc2 = (dir / "anim.pc2").string();
    ASSERT_EQ(test::run_command(bin + " drape --grid 12x10 --frames 20 -q -o '" + fca + "'").exit_code, 0);
    ASSERT_EQ(test::run_command(bin + " decode '" + fca + "' -o '" + pc2 + "'").exit_code, 0);
    EXPECT_EQ(read_pc2(pc2).size(), 20u);
    EXPECT_TRUE(std::filesystem::exists(dir / "anim.obj"));
}

}  // namespace
}  // namespace foldcast::codec
