#pragma once
// Catalogue rendering: garments x looks x views from a manifest, split deterministically
// into shards so several machines can share it, resumable (finished, verified outputs are
// skipped) and recorded in a JSON list of outputs with SHA-256 hashes.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>


namespace foldcast::batch {

struct BatchView {
    std::string name;
    double azimuth_deg = 0.0;  // camera orbit around the garment, 0 = front
    double elevation_deg = 0.0;
};

struct BatchGarment {
    std::string name;
    std::filesystem::path scene;  // a scene file (absolute, resolved against the manifest)
};

struct BatchManifest {
    std::filesystem::path path;        // the manifest file
    std::filesystem::path output_dir;  // absolute, resolved against the manifest
    std::vector<BatchGarment> garments;
    std::vector<std::string> looks;
    std::vector<BatchView> views;
    int width = 640;
    int height = 640;
    int spp = 16;
    unsigned seed = 1;
};

struct BatchJob {
    std::size_t index = 0;  // position in the full, unsharded job list
    BatchGarment garment;
    std::string look;
    BatchView view;
    std::filesystem::path output;  // <output_dir>/<garment>/<look>/<view>.png
};

struct Shard {
    int index = 0;  // 0-based, as Slurm array tasks from 0 and Kubernetes completion indices
    int count = 1;
};

// Parses "I/N" (0 <= I < N); throws InputError naming the value otherwise.
Shard parse_shard(const std::string& text);

// Reads and validates a manifest (toml++); errors name the file, key and what is allowed.
BatchManifest load_manifest(const std::filesystem::path& path);

// Every job in manifest order (garments, then looks, then views); shard I of N takes the
// jobs whose index is I modulo N, so shards are disjoint, cover everything and balance.
std::vector<BatchJob> all_jobs(const BatchManifest& manifest);
std::vector<BatchJob> shard_jobs(const BatchManifest& manifest, Shard shard);

// Hex SHA-256 of a file's bytes.
std::string sha256_file(const std::filesystem::path& path);

// What decides a job's pixels, hashed (hex SHA-256): the scene file's bytes and those of the
// garment files it names, the look, the view's angles and the manifest's width, height, spp
// and seed.  A resumed run re-renders an output whose recorded identity differs.
std::string job_identity(const BatchJob& job, const BatchManifest& manifest);

// True when `output` exists with a sidecar `<output>.sha256` (sha256sum format, its first
// line a "# foldcast-job IDENTITY" comment that sha256sum -c skips) that matches its bytes
// and `identity`: a finished, verified output of the same job a resumed run may skip.
bool is_finished(const std::filesystem::path& output, const std::string& identity);

struct BatchOutput {
    BatchJob job;
    std::string sha256;
    bool skipped = false;  // already finished before this run
};

// Called after each of the shard's jobs with its output (rendered or skipped), how many of
// the shard's jobs are done so far (from 1) and how many the shard has.
using JobDoneFn = std::function<void(const BatchOutput& output, std::size_t done, std::size_t total)>;

// Renders the shard's jobs that are not finished with `render_job` (which must write the
// image at job.output), writes each sidecar hash, and records every output of the shard in
// `<output_dir>/outputs-<I>-of-<N>.json` (or outputs.json unsharded).  Returns the outputs.
// Checks the shard count against earlier runs first (check_shard_count).
using JobRenderer = std::function<void(const BatchJob& job, const BatchManifest& manifest)>;
std::vector<BatchOutput> run_batch(const BatchManifest& manifest, Shard shard, const JobRenderer& render_job,
                                   const JobDoneFn& job_done = {});

// The shard counts N of the outputs-I-of-N.json lists in the output directory: how earlier
// sharded runs split this catalogue.
std::vector<int> recorded_shard_counts(const BatchManifest& manifest);

// Throws InputError, naming the directory, both counts and the ways on, when a sharded run
// would split the catalogue into another N than earlier runs recorded: the shards of two
// splittings overlap and leave gaps, so their lists would not add up to the catalogue.  An
// unsharded run (N = 1) is always allowed: it verifies and completes everything.
void check_shard_count(const BatchManifest& manifest, Shard shard);

// A log line for a farm's job log (no terminal to redraw a bar on), e.g.
// "shard 1/4: job 2 of 3 rendered in 3.2 s: tall/denim/front.png".
std::string job_log_line(const BatchManifest& manifest, Shard shard, const BatchOutput& output, std::size_t done,
                         std::size_t total, double seconds);

// How much of a catalogue is finished, read from the images and their .sha256 files (each
// verified as a resumed run would).
struct CatalogueStatus {
    struct ShardStatus {
        int index = 0;
        std::size_t jobs = 0, finished = 0;
        bool listed = false;  // its outputs-I-of-N.json exists: the shard ran to its end
    };
    std::size_t jobs = 0, finished = 0;
    std::size_t unverified = 0;  // an image without a matching .sha256 (interrupted, damaged or changed job)
    int shard_count = 1;         // the split `shards` describes (1: none)
    std::vector<ShardStatus> shards;
};
// `shard_count` 0 takes the split earlier runs recorded (recorded_shard_counts), if exactly one.
CatalogueStatus catalogue_status(const BatchManifest& manifest, int shard_count = 0);
// The summary `foldcast batch MANIFEST --status` prints.
std::string status_report(const BatchManifest& manifest, const CatalogueStatus& status);

// The JSON list of outputs of a run (what run_batch writes), for reports.
std::string outputs_json(const BatchManifest& manifest, const std::vector<BatchOutput>& outputs);

}  // namespace foldcast::batch
