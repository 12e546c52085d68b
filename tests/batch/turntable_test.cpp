// Turntables: frame counts, sub-ranges, the MP4 and joining ranges rendered separately.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "foldcast/core/error.hpp"
#include "foldcast/batch/turntable.hpp"
#include "render_fixtures.hpp"

namespace foldcast::batch {
namespace {

int png_count(const std::filesystem::path& dir) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) n += e.path().extension() == ".png";
    return n;
}

TEST(Turntable, WritesEveryFrameAndAnMp4) {
    const auto dir = test::temp_dir();
    const SceneSpec s = test::cloth_scene(32, 32, 1);
    TurntableOptions o;
    o.total_frames = 5;
    const TurntableResult r = render_turntable(s, dir / "spin.mp4", o);
    EXPECT_EQ(r.frames_rendered, 5);
    EXPECT_EQ(png_count(dir / "spin_frames"), 5);
    ASSERT_TRUE(std::filesystem::exists(dir / "spin.mp4"));
    cv::VideoCapture video((dir / "spin.mp4").string());
    ASSERT_TRUE(video.isOpened());
    int frames = 0;
    cv::Mat f;
    while (video.read(f)) ++frames;
    EXPECT_EQ(frames, 5);
    // The garment turns: the first and second frames differ.
    const cv::Mat a = cv::imread(turntable_frame_path(dir / "spin_frames", 0).string());
    const cv::Mat b = cv::imread(turntable_frame_path(dir / "spin_frames", 1).string());
    EXPECT_GT(cv::norm(a, b, cv::NORM_L1), 0.0);
}

TEST(Turntable, RangesRenderSeparatelyAndJoin) {
    const auto dir = test::temp_dir();
    const SceneSpec s = test::cloth_scene(24, 24, 1);
    TurntableOptions part;
    part.total_frames = 4;
    part.first_frame = 0;
    part.last_frame = 2;
    EXPECT_EQ(render_turntable(s, dir / "frames/", part).frames_rendered, 2);
    EXPECT_EQ(png_count(dir / "frames"), 2);
    EXPECT_THROW(encode_mp4(dir / "frames", 4, 24.0, dir / "out.mp4"), InputError);  // incomplete
    part.first_frame = 2;
    part.last_frame = 4;
    render_turntable(s, dir / "frames/", part);
    EXPECT_EQ(png_count(dir / "frames"), 4);
    encode_mp4(dir / "frames", 4, 24.0, dir / "out.mp4");
    EXPECT_TRUE(std::filesystem::exists(dir / "out.mp4"));
    part.first_frame = 3;
    part.last_frame = 9;
    EXPECT_THROW(render_turntable(s, dir / "frames/", part), InputError);
}

TEST(Turntable, PartialRangeFramesEqualFullRunFrames) {
    const auto dir = test::temp_dir();
    const SceneSpec s = test::cloth_scene(24, 24, 2);
    TurntableOptions all, part;
    all.total_frames = part.total_frames = 3;
    part.first_frame = 2;
    part.last_frame = 3;
    render_turntable(s, dir / "all/", all);
    render_turntable(s, dir / "part/", part);
    const cv::Mat a = cv::imread(turntable_frame_path(dir / "all", 2).string());
    const cv::Mat b = cv::imread(turntable_frame_path(dir / "part", 2).string());
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(cv::norm(a, b, cv::NORM_L1), 0.0);
}

}  // namespace
}  // namespace foldcast::batch
