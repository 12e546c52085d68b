// The fuzzer's seeds (codec/fuzz/corpus) must be valid files of the current format: a seed
// the decoder rejects at its header only fuzzes the header check.  Each seed is one split
// byte and then an .fca file, or a prefix of one when its name says "truncated".
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "foldcast/codec/codec.hpp"
#include "paper_container.hpp"

namespace foldcast {
namespace {

TEST(FuzzCorpus, EverySeedDecodesInTheCurrentFormat) {
    const std::filesystem::path dir = std::filesystem::path(FOLDCAST_SOURCE_DIR) / "codec/fuzz/corpus";
    int seeds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        std::ifstream in(entry.path(), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_GT(bytes.size(), 1u) << entry.path();
        const std::string name = entry.path().filename().string();
        codec::StreamingDecoder decoder(name);
        ASSERT_NO_THROW(decoder.feed(std::string_view(bytes).substr(1))) << name;
        const codec::StreamStatus status = decoder.status();
        EXPECT_TRUE(status.header_ready) << name;
        EXPECT_GT(status.packets, 0u) << name;
        if (name.find("truncated") == std::string::npos)
            EXPECT_TRUE(status.complete) << name;
        else
            EXPECT_FALSE(status.complete) << name;
        ++seeds;
    }
    EXPECT_GE(seeds, 4);
}

}  // namespace
}  // namespace foldcast

namespace foldcast {
namespace {

// fuzz_fca_paper's seeds (codec/fuzz/corpus_paper) must reach the paper profile's packets:
// wrapped in the harness's container they decode completely.
TEST(FuzzCorpus, EveryPaperSeedDecodesInsideTheHarnessContainer) {
    const std::filesystem::path dir = std::filesystem::path(FOLDCAST_SOURCE_DIR) / "codec/fuzz/corpus_paper";
    int seeds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        std::ifstream in(entry.path(), std::ios::binary);
        const std::string seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_GT(seed.size(), 3u) << entry.path();
        const std::string file =
            codec::fuzz::paper_container(reinterpret_cast<const std::uint8_t*>(seed.data()), seed.size());
        const std::string name = entry.path().filename().string();
        codec::StreamingDecoder decoder(name, file.size());
        ASSERT_NO_THROW(decoder.feed(file)) << name;
        EXPECT_EQ(decoder.profile(), codec::Profile::paper) << name;
        EXPECT_TRUE(decoder.status().complete) << name;
        ASSERT_NO_THROW((void)decoder.animation()) << name;
        ++seeds;
    }
    EXPECT_GE(seeds, 2);
}

}  // namespace
}  // namespace foldcast
