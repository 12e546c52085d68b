// The coarse first frame (preview packet), the header's first-frame size and metadata
// (format version 4), and version 3 files still read as before.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "container.hpp"
#include "crc32.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "preview.hpp"
#include "test_animations.hpp"
#include "test_paths.hpp"

namespace foldcast::codec {
namespace {

// Where each packet of a file starts: (offset, type, payload bytes).
struct PacketAt {
    std::size_t at;
    int type;
    std::uint32_t length;
};
std::vector<PacketAt> packets_of(const std::string& file) {
    std::vector<PacketAt> out;
    for (std::size_t at = sizeof(kMagic); at + kPacketOverhead <= file.size();) {
        std::uint32_t length = 0;
        std::memcpy(&length, file.data() + at, 4);
        out.push_back({at, static_cast<std::uint8_t>(file[at + 4]), length});
        at += kPacketOverhead + length;
    }
    return out;
}

double largest_error_m(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    double worst = 0.0;
    for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, double((a[v] - b[v]).norm()));
    return worst;
}

class Preview : public ::testing::TestWithParam<Profile> {};

TEST_P(Preview, ComesRightAfterTheHeaderAndShowsFrameZeroWithinItsGrid) {
    // paper's encoder searches its threshold (seconds on a large grid): a smaller one there.
    const int side = GetParam() == Profile::paper ? 24 : 64;
    const Animation a = test::wave_grid(side, side, GetParam() == Profile::paper ? 40 : 160);
    EncodeOptions options;
    options.profile = GetParam();
    const std::string file = encode(a, options);
    const auto packets = packets_of(file);
    ASSERT_GE(packets.size(), 4u);
    EXPECT_EQ(packets[0].type, int(PacketType::header));
    EXPECT_EQ(packets[1].type, int(PacketType::preview));
    EXPECT_EQ(packets[2].type, int(PacketType::data));
    const std::size_t preview_end = packets[2].at, first_frame_end = packets[3].at;
    // Under 1.5 bytes per vertex, far less than data packet 0.
    EXPECT_LT(packets[1].length, a.vertex_count() * 3 / 2);
    EXPECT_LT(packets[1].length * 4, packets[2].length);

    StreamingDecoder decoder("prefix", file.size());
    decoder.feed(std::string_view(file).substr(0, preview_end - 1));
    StreamStatus s = decoder.status();
    EXPECT_TRUE(s.header_ready);
    EXPECT_FALSE(s.frame_ready);
    EXPECT_EQ(s.first_frame_bytes, first_frame_end);  // from the header
    try {
        (void)decoder.frame(0);
        ADD_FAILURE() << "a frame from the header alone";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("the first frame needs " + std::to_string(first_frame_end) + " bytes"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW((void)decoder.animation(), InputError);

    decoder.feed(std::string_view(file).substr(preview_end - 1, 1));
    s = decoder.status();
    EXPECT_TRUE(s.frame_ready);
    EXPECT_TRUE(s.preview_only);
    EXPECT_EQ(s.playable_frames, 0u);
    const std::vector<Vec3f> coarse = decoder.frame(0);
    const Bounds b = bounds(a);
    const double step = double((b.max - b.min).maxCoeff()) / kPreviewLevels;
    EXPECT_LE(largest_error_m(coarse, a.frames[0]), std::sqrt(3.0) / 2.0 * step * 1.001);
    EXPECT_GT(largest_error_m(coarse, a.frames[0]), 0.0);  // coarse: not the data packets' frame
    EXPECT_EQ(decoder.frame(a.frame_count() - 1), coarse);  // held until data packet 0
    EXPECT_EQ(decoder.animation().frames.back(), coarse);

    decoder.feed(std::string_view(file).substr(preview_end, first_frame_end - preview_end));
    s = decoder.status();
    EXPECT_FALSE(s.preview_only);
    EXPECT_NE(decoder.frame(0), coarse);
    decoder.feed(std::string_view(file).substr(first_frame_end));
    EXPECT_TRUE(decoder.status().complete);
    EXPECT_EQ(decoder.animation().frames, decode(file).frames);
}

INSTANTIATE_TEST_SUITE_P(Profiles, Preview, ::testing::Values(Profile::predictive, Profile::paper, Profile::cascade),
                         [](const auto& info) { return profile_name(info.param); });

TEST(Preview, DrapeSizedGarmentNeedsAFewKilobytes) {
    const Animation a = test::wave_grid(128, 128, 8);
    const std::string file = encode(a, {});
    const auto packets = packets_of(file);
    ASSERT_EQ(packets[1].type, int(PacketType::preview));
    EXPECT_LT(packets[1].length, 40000u) << "16,384 vertices";
}

TEST(Metadata, RoundTripsAndIsChecked) {
    const Animation a = test::wave_grid(8, 8, 10);
    EncodeOptions options;
    options.metadata = {{"look", "denim"}, {"note", "Ünïcode ok"}};
    StreamingDecoder decoder;
    decoder.feed(encode(a, options));
    EXPECT_EQ(decoder.metadata(), options.metadata);
    EXPECT_EQ(decoder.metadata("look"), std::optional<std::string>("denim"));
    EXPECT_EQ(decoder.metadata("absent"), std::nullopt);
    for (const Metadata& bad : std::vector<Metadata>{{{"Look", "x"}}, {{"", "x"}}, {{"look", "a\nb"}},
                                                     {{"look", "a"}, {"look", "b"}}, {{"look", std::string(1025, 'x')}}}) {
        options.metadata = bad;
        EXPECT_THROW((void)encode(a, options), InputError) << bad.front().first;
    }
}

// A version 3 file (written by the encoder before the preview existed) decodes to the
// same frames as it did then (tests/data/fca: the file and its decode by that build).
TEST(FormatVersion3, StillDecodesBitForBit) {
    const std::string file = read_fca(test::test_data("fca/v3_drape16.fca"));
    const auto expected = read_pc2(test::test_data("fca/v3_drape16.pc2"));
    StreamingDecoder decoder("v3", file.size());
    decoder.feed(file);
    ASSERT_TRUE(decoder.status().complete);
    EXPECT_TRUE(decoder.metadata().empty());
    EXPECT_EQ(decoder.animation().frames, expected);

    // Its prefixes: nothing before data packet 0, whose size is known once its length is in.
    const auto packets = packets_of(file);
    ASSERT_EQ(packets[1].type, int(PacketType::data));
    StreamingDecoder prefix("v3 prefix", file.size());
    prefix.feed(std::string_view(file).substr(0, packets[1].at));
    EXPECT_EQ(prefix.status().first_frame_bytes, 0u);
    EXPECT_THROW((void)prefix.frame(0), InputError);
    prefix.feed(std::string_view(file).substr(packets[1].at, 5));
    EXPECT_EQ(prefix.status().first_frame_bytes, packets[2].at);
    EXPECT_FALSE(prefix.status().frame_ready);
}

// `file` with one more packet at byte `at` and its header's total size fixed to match.
std::string with_packet_inserted(const std::string& file, std::size_t at, PacketType type, std::string_view payload) {
    std::string packet;
    append_packet(packet, type, payload);
    const std::string body = file.substr(0, at) + packet + file.substr(at);
    const PacketAt head = packets_of(file)[0];
    Header h = parse_header(std::string_view(file).substr(head.at + 5, head.length), "test", std::nullopt);
    h.total_bytes = body.size();
    std::string out(kMagic, sizeof(kMagic));
    append_packet(out, PacketType::header, header_payload(h));
    return out + body.substr(head.at + kPacketOverhead + head.length);
}

void expect_error_naming(const std::string& file, const std::string& words) {
    StreamingDecoder decoder("test");
    try {
        decoder.feed(file);
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(Preview, MisplacedOrMalformedIsAnError) {
    const Animation a = test::wave_grid(8, 8, 10);
    const std::string file = encode(a, {});
    const auto packets = packets_of(file);
    const std::string preview = file.substr(packets[1].at + 5, packets[1].length);
    // A second preview after data packet 0, and a preview in a version 3 file.
    expect_error_naming(with_packet_inserted(file, packets[3].at, PacketType::preview, preview),
                        "must directly follow the header");
    const std::string v3 = read_fca(test::test_data("fca/v3_drape16.fca"));
    expect_error_naming(with_packet_inserted(v3, packets_of(v3)[1].at, PacketType::preview, preview),
                        "must directly follow the header");
    // Off its grid: levels 1 leaves no room for the encoded residuals.
    std::string tiny = preview;
    tiny[0] = 1;
    tiny[1] = 0;
    std::string bad = file;
    bad.replace(packets[1].at + 5, tiny.size(), tiny);
    const std::uint32_t crc = crc32(std::string_view(bad).substr(packets[1].at + 4, 1 + packets[1].length));
    std::memcpy(bad.data() + packets[1].at + 5 + packets[1].length, &crc, 4);
    expect_error_naming(bad, "preview");
}

}  // namespace
}  // namespace foldcast::codec
