// foldcast batch MANIFEST.toml [--shard I/N] [--status]: a catalogue of garments x looks x views.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "foldcast/core/error.hpp"
#include "validators.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/render/render.hpp"
#include "foldcast/batch/catalogue.hpp"
#include "progress_bar.hpp"
#include "resource_estimates.hpp"

namespace foldcast::app {

namespace {
// A bar on a terminal; otherwise (a Slurm or Kubernetes log) a line per job, with the shard.
batch::JobDoneFn job_progress(const batch::BatchManifest& manifest, batch::Shard shard, ProgressBar& bar) {
    if (bar.on_terminal()) {
        ProgressFn draw = bar.callback();
        return [draw](const batch::BatchOutput&, std::size_t done, std::size_t total) {
            draw("batch", static_cast<double>(done) / static_cast<double>(total));
        };
    }
    std::fprintf(stderr, "shard %d/%d: %zu of the catalogue's %zu jobs, images in %s\n", shard.index, shard.count,
                 batch::shard_jobs(manifest, shard).size(), batch::all_jobs(manifest).size(),
                 manifest.output_dir.c_str());
    auto last = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
    return [&manifest, shard, last](const batch::BatchOutput& output, std::size_t done, std::size_t total) {
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - *last).count();
        *last = now;
        std::fprintf(stderr, "%s\n", batch::job_log_line(manifest, shard, output, done, total, seconds).c_str());
        std::fflush(stderr);
    };
}
// Before any image: each garment's drape and each image within what this machine can do,
// and the shard's images together within a week.
void check_batch_estimates(const batch::BatchManifest& manifest, batch::Shard shard, bool force) {
    for (const batch::BatchGarment& garment : manifest.garments) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(garment.scene, ec))
            throw InputError(manifest.path.string() + ": garments.scene of '" + garment.name + "': no scene file '" +
                             garment.scene.string() + "' (relative to the manifest)");
        check_scene_drape_work(render::load_scene(garment.scene), garment.scene.string(), force);
    }
    check_batch_work(manifest.width, manifest.height, manifest.spp,
                     static_cast<long long>(batch::shard_jobs(manifest, shard).size()),
                     manifest.path.string() + ": width = " + std::to_string(manifest.width) +
                         ", height = " + std::to_string(manifest.height) + ", spp = " + std::to_string(manifest.spp),
                     force);
}
}  // namespace

Command batch_command(CLI::App& app) {
    struct Args {
        std::string manifest, shard = "0/1";
        int threads = 0;
        bool dry_run = false, json = false, quiet = false, status = false, force = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* sub = app.add_subcommand(
        "batch", "Render a catalogue (garments x looks x views) from a manifest; resumable and shardable");
    sub->add_option("manifest", args->manifest, "Catalogue manifest (TOML), e.g. gallery/catalogue.toml")->required();
    sub->add_option("--shard", args->shard,
                    "Render only shard I of N (0-based, e.g. 2/8): jobs whose index is I modulo N")
        ->check(library_validator([](const std::string& v) { batch::parse_shard(v); }, "I/N"))
        ->capture_default_str();
    sub->add_option("--threads", args->threads, "Render threads per image (default: all cores)")
        ->check(CLI::Range(1, 1024));
    sub->add_flag("--dry-run", args->dry_run, "List this shard's jobs and whether each is finished; render nothing");
    sub->add_flag("--json", args->json, "Print the shard's outputs (paths, SHA-256, skipped) as JSON");
    sub->add_flag("--status", args->status,
                  "Say how much of the catalogue is finished, over all shards (verifies every image against its "
                  ".sha256); render nothing")
        ->excludes("--dry-run")
        ->excludes("--json");
    sub->add_flag("--quiet", args->quiet,
                  "No progress (a bar on a terminal; otherwise, as in a Slurm log, a line per job)");
    sub->add_flag("--force", args->force, "Render even when the memory or time estimate exceeds this machine's");
    return {sub, [args] {
                const batch::Shard shard = batch::parse_shard(args->shard);
                const batch::BatchManifest manifest = batch::load_manifest(args->manifest);
                const looks::Library library = looks::Library::load_default();
                for (const std::string& look : manifest.looks) library.get(look);  // fail before any work
                if (args->status) {
                    const int split = shard.count > 1 ? shard.count : 0;  // 0: the split earlier runs recorded
                    std::printf("%s", batch::status_report(manifest, batch::catalogue_status(manifest, split)).c_str());
                    return 0;
                }
                if (args->dry_run) {
                    for (const batch::BatchJob& job : batch::shard_jobs(manifest, shard))
                        std::printf(
                            "%4zu %s %s\n", job.index,
                            batch::is_finished(job.output, batch::job_identity(job, manifest)) ? "done" : "todo",
                            job.output.c_str());
                    return 0;
                }
                auto render_job = [&](const batch::BatchJob& job, const batch::BatchManifest& m) {
                    render::SceneSpec scene = render::load_scene(job.garment.scene);
                    scene.look = library.get(job.look);
                    scene.camera.azimuth_deg = job.view.azimuth_deg;
                    scene.camera.elevation_deg = job.view.elevation_deg;
                    render::RenderOptions options;
                    options.width = m.width;
                    options.height = m.height;
                    options.spp = m.spp;
                    options.seed = m.seed;
                    options.threads = args->threads;
                    render::write_render(job.output, render::render_still(scene, options), scene);
                };
                batch::check_shard_count(manifest, shard);  // before the log's first line
                check_batch_estimates(manifest, shard, args->force);
                std::vector<batch::BatchOutput> outputs;
                {
                    const bool quiet = args->quiet || args->json;
                    ProgressBar bar(quiet);
                    outputs = batch::run_batch(manifest, shard, render_job,
                                               quiet ? batch::JobDoneFn{} : job_progress(manifest, shard, bar));
                }
                if (args->json) {
                    std::printf("%s", batch::outputs_json(manifest, outputs).c_str());
                } else if (!args->quiet) {
                    std::size_t skipped = 0;
                    for (const auto& o : outputs) skipped += o.skipped;
                    std::fprintf(stderr, "shard %d/%d: %zu images (%zu already finished) in %s\n", shard.index,
                                 shard.count, outputs.size(), skipped, manifest.output_dir.c_str());
                }
                return 0;
            }};
}

}  // namespace foldcast::app
