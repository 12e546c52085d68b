#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "foldcast/core/error.hpp"
#include "foldcast/batch/catalogue.hpp"
#include "test_paths.hpp"

namespace foldcast::batch {
namespace {
namespace fs = std::filesystem;

fs::path write_manifest(const fs::path& dir, const std::string& text) {
    const fs::path path = dir / "catalogue.toml";
    std::ofstream(path) << text;
    return path;
}

const char* kManifest = R"(output_dir = "out"
width = 32
height = 24
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

// Stands in for the renderer: deterministic bytes that depend on the job only.
void fake_render(const BatchJob& job, const BatchManifest&) {
    std::ofstream(job.output, std::ios::binary)
        << job.garment.name << '|' << job.look << '|' << job.view.name << '|' << job.view.azimuth_deg;
}

TEST(BatchManifest, ExpandsGarmentsLooksViewsInOrder) {
    const auto dir = test::temp_dir();
    const BatchManifest m = load_manifest(write_manifest(dir, kManifest));
    EXPECT_EQ(m.width, 32);
    EXPECT_EQ(m.garments[1].scene, fs::absolute(dir) / "scarf.toml");
    const auto jobs = all_jobs(m);
    ASSERT_EQ(jobs.size(), 2u * 3u * 2u);
    EXPECT_EQ(jobs[3].garment.name, "shirt");
    EXPECT_EQ(jobs[3].look, "linen");
    EXPECT_EQ(jobs[3].view.name, "side");
    EXPECT_EQ(jobs[3].output, fs::absolute(dir) / "out" / "shirt" / "linen" / "side.png");
}

TEST(BatchManifest, ErrorsNameTheKey) {
    const auto dir = test::temp_dir();
    try {
        load_manifest(write_manifest(dir, std::string(kManifest) + "colour = 3\n"));
        FAIL() << "unknown key accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown key 'views.colour'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(load_manifest(write_manifest(dir, "looks = [\"../etc\"]\n[[garments]]\nname=\"a\"\nscene=\"s\"\n")),
                 InputError);
    EXPECT_THROW(load_manifest(write_manifest(dir, "spp = 0\nlooks=[\"a\"]\n[[garments]]\nname=\"a\"\nscene=\"s\"\n")),
                 InputError);
    EXPECT_THROW(load_manifest(dir / "missing.toml"), InputError);
}

TEST(BatchShard, ParsesAndRejects) {
    EXPECT_EQ(parse_shard("2/5").index, 2);
    EXPECT_EQ(parse_shard("2/5").count, 5);
    for (const char* bad : {"5/5", "-1/3", "1/0", "a/b", "1", "1/2/3"})
        EXPECT_THROW(parse_shard(bad), InputError) << bad;
}

TEST(BatchShard, ShardsAreDisjointAndCoverEverything) {
    const auto dir = test::temp_dir();
    const BatchManifest m = load_manifest(write_manifest(dir, kManifest));
    for (int n : {1, 2, 3, 5, 12, 20}) {
        std::multiset<std::size_t> seen;
        for (int i = 0; i < n; ++i)
            for (const BatchJob& job : shard_jobs(m, {i, n})) seen.insert(job.index);
        ASSERT_EQ(seen.size(), all_jobs(m).size()) << n;
        for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen.count(k), 1u) << n;
    }
}

TEST(BatchRun, ShardsTogetherGiveTheUnshardedOutputs) {
    const auto dir = test::temp_dir();
    write_manifest(dir, kManifest);
    fs::create_directories(dir / "whole");
    fs::create_directories(dir / "split");
    const BatchManifest whole_m = load_manifest(write_manifest(dir / "whole", kManifest));
    const BatchManifest split_m = load_manifest(write_manifest(dir / "split", kManifest));
    std::set<std::pair<std::string, std::string>> whole, split;
    for (const BatchOutput& o : run_batch(whole_m, {0, 1}, fake_render))
        whole.insert({fs::relative(o.job.output, whole_m.output_dir).string(), o.sha256});
    for (int i = 0; i < 3; ++i)
        for (const BatchOutput& o : run_batch(split_m, {i, 3}, fake_render))
            split.insert({fs::relative(o.job.output, split_m.output_dir).string(), o.sha256});
    EXPECT_EQ(whole, split);
    EXPECT_TRUE(fs::exists(whole_m.output_dir / "outputs.json"));
    EXPECT_TRUE(fs::exists(split_m.output_dir / "outputs-2-of-3.json"));
}

TEST(BatchRun, ResumeSkipsVerifiedOutputsAndRedoesDamagedOnes) {
    const auto dir = test::temp_dir();
    const BatchManifest m = load_manifest(write_manifest(dir, kManifest));
    int rendered = 0;
    auto counting = [&](const BatchJob& job, const BatchManifest& manifest) {
        ++rendered;
        fake_render(job, manifest);
    };
    run_batch(m, {0, 1}, counting);
    EXPECT_EQ(rendered, 12);
    rendered = 0;
    const auto again = run_batch(m, {0, 1}, counting);
    EXPECT_EQ(rendered, 0);
    EXPECT_TRUE(again.front().skipped);
    std::ofstream(all_jobs(m)[4].output, std::ios::app) << "corrupted";
    fs::remove(all_jobs(m)[7].output.string() + ".sha256");
    rendered = 0;
    run_batch(m, {0, 1}, counting);
    EXPECT_EQ(rendered, 2);
    EXPECT_TRUE(is_finished(all_jobs(m)[4].output, job_identity(all_jobs(m)[4], m)));
}

// Issue #17 item 8: a resumed batch must not keep images of another spp, seed, size, view
// or scene; each of these changes the job's identity and so re-renders every image.
TEST(BatchRun, ResumeRedoesJobsWhoseSettingsChanged) {
    const auto dir = test::temp_dir();
    std::ofstream(dir / "shirt.toml") << "[garment]\nwidth_m = 0.5\n";
    std::ofstream(dir / "scarf.toml") << "[garment]\nwidth_m = 0.3\n";
    const BatchManifest base = load_manifest(write_manifest(dir, kManifest));
    int rendered = 0;
    auto counting = [&](const BatchJob& job, const BatchManifest& manifest) {
        ++rendered;
        fake_render(job, manifest);
    };
    run_batch(base, {0, 1}, counting);
    ASSERT_EQ(rendered, 12);
    auto rerun = [&](const BatchManifest& changed) {
        rendered = 0;
        run_batch(changed, {0, 1}, counting);
        return rendered;
    };
    EXPECT_EQ(rerun(base), 0);
    BatchManifest m = base;
    m.spp += 1;
    EXPECT_EQ(rerun(m), 12) << "spp";
    m.seed += 1;
    EXPECT_EQ(rerun(m), 12) << "seed";
    m.width += 8;
    EXPECT_EQ(rerun(m), 12) << "width";
    EXPECT_EQ(rerun(m), 0);
    std::ofstream(dir / "scarf.toml") << "[garment]\nwidth_m = 0.35\n";
    EXPECT_EQ(rerun(m), 6) << "the scarf's scene file";
    // The sidecar stays a sha256sum file: its identity line is a comment.
    std::ifstream sidecar(all_jobs(m)[0].output.string() + ".sha256");
    std::string first;
    std::getline(sidecar, first);
    EXPECT_EQ(first.rfind("# foldcast-job ", 0), 0u) << first;
}

TEST(BatchRun, Sha256OfKnownBytes) {
    const auto dir = test::temp_dir();
    std::ofstream(dir / "abc", std::ios::binary) << "abc";
    EXPECT_EQ(sha256_file(dir / "abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace foldcast::batch
