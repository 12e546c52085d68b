// Turntable videos browsers play: H.264 in MP4 (yuv420p, moov first) or VP9 in WebM, the same
// bytes whatever the thread count, options checked before any frame is rendered.
#include <gtest/gtest.h>

#include <opencv2/videoio.hpp>

#include <fstream>
#include <sstream>

#include "foldcast/batch/turntable.hpp"
#include "foldcast/core/error.hpp"
#include "render_fixtures.hpp"
#include "run_command.hpp"

namespace foldcast::batch {
namespace video_test {

std::string bytes_of(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string probe(const std::filesystem::path& video) {
    return test::run_command(
               "ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,pix_fmt,width,height "
               "-of csv=p=0 '" +
               video.string() + "'")
        .out;
}

int frames_in(const std::filesystem::path& video) {
    cv::VideoCapture capture(video.string());
    int frames = 0;
    cv::Mat f;
    while (capture.read(f)) ++frames;
    return frames;
}

TEST(TurntableVideo, CodecFollowsTheExtension) {
    EXPECT_EQ(video_codec_for("a/spin.mp4"), VideoCodec::h264);
    EXPECT_EQ(video_codec_for("spin.WEBM"), VideoCodec::vp9);
    try {
        video_codec_for("spin.avi");
        FAIL() << ".avi accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("spin.avi"), std::string::npos) << e.what();
    }
}

TEST(TurntableVideo, Mp4IsH264Yuv420pWithTheIndexFirst) {
    const auto dir = test::temp_dir();
    TurntableOptions o;
    o.total_frames = 3;
    o.render.spp = 2;
    // Odd sides: yuv420p needs even ones, so the encoder pads a row and a column.
    render_turntable(test::cloth_scene(65, 49, 2), dir / "spin.mp4", o);
    EXPECT_EQ(probe(dir / "spin.mp4"), "h264,66,50,yuv420p\n");
    EXPECT_EQ(frames_in(dir / "spin.mp4"), 3);
    const std::string mp4 = bytes_of(dir / "spin.mp4");
    const auto moov = mp4.find("moov"), mdat = mp4.find("mdat");
    ASSERT_NE(moov, std::string::npos);
    EXPECT_LT(moov, mdat) << "+faststart puts the index before the media data";
}

TEST(TurntableVideo, SameBytesWhateverTheThreadCount) {
    const auto dir = test::temp_dir();
    for (const char* name : {"spin.mp4", "spin.webm"}) {
        TurntableOptions one, two;
        one.total_frames = two.total_frames = 3;
        one.render.threads = 1;
        two.render.threads = 2;
        render_turntable(test::cloth_scene(48, 32, 2), dir / "one" / name, one);
        render_turntable(test::cloth_scene(48, 32, 2), dir / "two" / name, two);
        EXPECT_EQ(bytes_of(dir / "one" / name), bytes_of(dir / "two" / name)) << name;
    }
    EXPECT_EQ(probe(dir / "one" / "spin.webm"), "vp9,48,32,yuv420p\n");
    EXPECT_EQ(frames_in(dir / "one" / "spin.webm"), 3);
}

TEST(TurntableVideo, QualityAndBitrateChangeTheSize) {
    const auto dir = test::temp_dir();
    TurntableOptions o;
    o.total_frames = 3;
    render_turntable(test::cloth_scene(96, 64, 2), dir / "frames/", o);
    VideoOptions best, worst;
    best.crf = 0;
    worst.crf = 51;
    encode_mp4(dir / "frames", 3, 24.0, dir / "best.mp4", best);
    encode_mp4(dir / "frames", 3, 24.0, dir / "worst.mp4", worst);
    EXPECT_GT(std::filesystem::file_size(dir / "best.mp4"), 2 * std::filesystem::file_size(dir / "worst.mp4"));
    VideoOptions rate;
    rate.bitrate_kbps = 100;
    rate.preset = "veryfast";
    encode_mp4(dir / "frames", 3, 24.0, dir / "rate.mp4", rate);
    EXPECT_EQ(frames_in(dir / "rate.mp4"), 3);
}

TEST(TurntableVideo, BadOptionsAreRefusedBeforeRenderingAndLeaveNothing) {
    const auto dir = test::temp_dir();
    TurntableOptions o;
    o.total_frames = 2;
    o.video.crf = 60;  // VP9 allows 63, H.264 51
    EXPECT_THROW(render_turntable(test::cloth_scene(32, 32, 1), dir / "spin.mp4", o), InputError);
    o.video.crf = -1;
    o.video.preset = "fastest";
    EXPECT_THROW(render_turntable(test::cloth_scene(32, 32, 1), dir / "spin.mp4", o), InputError);
    EXPECT_THROW(render_turntable(test::cloth_scene(32, 32, 1), dir / "spin.webm", o), InputError);  // x264's
    o.video.preset.clear();
    o.video.crf = 20;
    EXPECT_THROW(render_turntable(test::cloth_scene(32, 32, 1), dir / "frames/", o), InputError);  // no video
    EXPECT_THROW(encode_mp4(dir, 2, 24.0, dir / "spin.avi"), InputError);
    std::vector<std::string> left;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) left.push_back(e.path().string());
    EXPECT_TRUE(left.empty()) << left.front();
}

}  // namespace video_test
}  // namespace foldcast::batch
