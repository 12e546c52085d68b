// A catalogue across its shards: the recorded split, --status's counts, the farm log lines.
#include <gtest/gtest.h>

#include <fstream>

#include "foldcast/core/error.hpp"
#include "foldcast/batch/catalogue.hpp"
#include "test_paths.hpp"

namespace foldcast::batch {
namespace {
namespace fs = std::filesystem;

// 2 garments x 3 looks x 2 views = 12 jobs.
BatchManifest manifest_in(const fs::path& dir) {
    std::ofstream(dir / "catalogue.toml") << R"(output_dir = "out"
looks = ["denim", "linen", "chiffon"]
[[garments]]
name = "shirt"
scene = "shirt.toml"
[[garments]]
name = "scarf"
scene = "scarf.toml"
[[views]]
name = "front"
[[views]]
name = "side"
azimuth_deg = 90
)";
    return load_manifest(dir / "catalogue.toml");
}

void fake_render(const BatchJob& job, const BatchManifest&) {
    std::ofstream(job.output, std::ios::binary) << job.garment.name << '|' << job.look << '|' << job.view.name;
}

TEST(BatchSplit, AnotherShardCountIsRefusedBeforeAnyWork) {
    const auto dir = test::temp_dir();
    const BatchManifest m = manifest_in(dir);
    EXPECT_TRUE(recorded_shard_counts(m).empty());  // no output directory yet
    run_batch(m, {1, 3}, fake_render);
    EXPECT_EQ(recorded_shard_counts(m), std::vector<int>{3});
    int rendered = 0;
    auto counting = [&](const BatchJob& job, const BatchManifest& manifest) {
        ++rendered;
        fake_render(job, manifest);
    };
    try {
        run_batch(m, {0, 2}, counting);
        FAIL() << "a split into 2 over a catalogue split into 3 ran";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("shard 0/2"), std::string::npos) << message;
        EXPECT_NE(message.find("split into 3 shards, not 2"), std::string::npos) << message;
        EXPECT_NE(message.find(m.output_dir.string() + "/outputs-*-of-3.json"), std::string::npos) << message;
    }
    EXPECT_EQ(rendered, 0);
    EXPECT_FALSE(fs::exists(m.output_dir / "outputs-0-of-2.json"));
    run_batch(m, {2, 3}, counting);  // the same split goes on
    EXPECT_EQ(rendered, 4);
    run_batch(m, {0, 1}, counting);  // unsharded: verifies and completes everything
    EXPECT_EQ(rendered, 8);
    // Deleting the lists of the old split allows a new one; finished images stay finished.
    for (int i : {1, 2}) fs::remove(m.output_dir / ("outputs-" + std::to_string(i) + "-of-3.json"));
    rendered = 0;
    run_batch(m, {0, 2}, counting);
    EXPECT_EQ(rendered, 0);
    EXPECT_EQ(recorded_shard_counts(m), std::vector<int>{2});
}

TEST(BatchSplit, JobDoneReportsEveryJobOfTheShard) {
    const auto dir = test::temp_dir();
    const BatchManifest m = manifest_in(dir);
    run_batch(m, {0, 4}, fake_render);
    fs::remove(all_jobs(m)[4].output);
    std::vector<std::string> lines;
    run_batch(m, {0, 4}, fake_render, [&](const BatchOutput& output, std::size_t done, std::size_t total) {
        lines.push_back(job_log_line(m, {0, 4}, output, done, total, 2.04));
    });
    const std::vector<std::string> expected = {
        "shard 0/4: job 1 of 3 already finished: shirt/denim/front.png",
        "shard 0/4: job 2 of 3 rendered in 2.0 s: shirt/chiffon/front.png",
        "shard 0/4: job 3 of 3 already finished: scarf/linen/front.png",
    };
    EXPECT_EQ(lines, expected);
}

TEST(BatchStatus, CountsFinishedImagesPerShard) {
    const auto dir = test::temp_dir();
    const BatchManifest m = manifest_in(dir);
    run_batch(m, {0, 3}, fake_render);
    run_batch(m, {2, 3}, fake_render);
    std::ofstream(all_jobs(m)[3].output, std::ios::app) << "damaged";  // shard 0's second job
    const CatalogueStatus status = catalogue_status(m);
    EXPECT_EQ(status.shard_count, 3);
    EXPECT_EQ(status.jobs, 12u);
    EXPECT_EQ(status.finished, 7u);
    EXPECT_EQ(status.unverified, 1u);
    ASSERT_EQ(status.shards.size(), 3u);
    EXPECT_EQ(status.shards[0].finished, 3u);
    EXPECT_TRUE(status.shards[0].listed);
    EXPECT_EQ(status.shards[1].finished, 0u);
    EXPECT_FALSE(status.shards[1].listed);
    EXPECT_EQ(status.shards[2].finished, 4u);
    const std::string report = status_report(m, status);
    EXPECT_NE(report.find("catalogue.toml: 7 of 12 images finished (58%), 5 to do"), std::string::npos) << report;
    EXPECT_NE(report.find("1 image(s) there do not match"), std::string::npos) << report;
    EXPECT_NE(report.find("shard 0/3: 3 of 4 finished, outputs-0-of-3.json written\n"), std::string::npos) << report;
    EXPECT_NE(report.find("shard 1/3: 0 of 4 finished\n"), std::string::npos) << report;
    EXPECT_NE(report.find("shards with work left: 0 1 (of 3)\n"), std::string::npos) << report;

    // Another split asked for explicitly; without any recorded split, no breakdown.
    EXPECT_EQ(catalogue_status(m, 2).shards.size(), 2u);
    const fs::path empty_dir = dir / "fresh";
    fs::create_directories(empty_dir);
    const CatalogueStatus none = catalogue_status(manifest_in(empty_dir));
    EXPECT_EQ(none.finished, 0u);
    EXPECT_TRUE(none.shards.empty());
    EXPECT_NE(status_report(manifest_in(empty_dir), none).find("0 of 12 images finished (0%), 12 to do"),
              std::string::npos);
}

}  // namespace
}  // namespace foldcast::batch
