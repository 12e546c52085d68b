// A catalogue across its shards: which split earlier runs used, how much is finished, and
// the lines a farm's job log shows.
#include <cmath>
#include <cstdio>
#include <regex>
#include <set>
#include <sstream>

#include "foldcast/core/error.hpp"
#include "foldcast/batch/catalogue.hpp"

namespace foldcast::batch {
namespace fs = std::filesystem;

namespace {
std::string list_name(int index, int count) {
    return "outputs-" + std::to_string(index) + "-of-" + std::to_string(count) + ".json";
}

std::string relative_output(const BatchManifest& manifest, const BatchJob& job) {
    return fs::relative(job.output, manifest.output_dir).generic_string();
}
}  // namespace

std::vector<int> recorded_shard_counts(const BatchManifest& manifest) {
    static const std::regex kList(R"(outputs-([0-9]{1,6})-of-([0-9]{1,6})\.json)");
    std::set<int> counts;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(manifest.output_dir, ec)) {
        std::smatch match;
        const std::string name = entry.path().filename().string();
        if (!std::regex_match(name, match, kList)) continue;
        const int index = std::stoi(match[1].str()), count = std::stoi(match[2].str());
        if (count > 1 && index < count) counts.insert(count);
    }
    return {counts.begin(), counts.end()};
}

void check_shard_count(const BatchManifest& manifest, Shard shard) {
    if (shard.count == 1) return;
    for (int recorded : recorded_shard_counts(manifest)) {
        if (recorded == shard.count) continue;
        const std::string dir = manifest.output_dir.string();
        throw InputError("shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ": '" + dir +
                         "' holds outputs-*-of-" + std::to_string(recorded) +
                         ".json, so this catalogue was split into " + std::to_string(recorded) + " shards, not " +
                         std::to_string(shard.count) + " (the two splittings overlap); run its shards 0.." +
                         std::to_string(recorded - 1) + "/" + std::to_string(recorded) +
                         " (finished images are skipped), or delete '" + dir + "/outputs-*-of-" +
                         std::to_string(recorded) + ".json' to split it anew");
    }
}

std::string job_log_line(const BatchManifest& manifest, Shard shard, const BatchOutput& output, std::size_t done,
                         std::size_t total, double seconds) {
    char what[64];
    if (output.skipped)
        std::snprintf(what, sizeof what, "already finished");
    else
        std::snprintf(what, sizeof what, "rendered in %.1f s", seconds);
    std::ostringstream line;
    line << "shard " << shard.index << "/" << shard.count << ": job " << done << " of " << total << " " << what << ": "
         << relative_output(manifest, output.job);
    return line.str();
}

CatalogueStatus catalogue_status(const BatchManifest& manifest, int shard_count) {
    CatalogueStatus status;
    if (shard_count == 0) {
        const std::vector<int> recorded = recorded_shard_counts(manifest);
        shard_count = recorded.size() == 1 ? recorded.front() : 1;
    }
    status.shard_count = shard_count;
    if (shard_count > 1)
        for (int i = 0; i < shard_count; ++i) {
            CatalogueStatus::ShardStatus s;
            s.index = i;
            std::error_code ec;
            s.listed = fs::is_regular_file(manifest.output_dir / list_name(i, shard_count), ec);
            status.shards.push_back(s);
        }
    for (const BatchJob& job : all_jobs(manifest)) {
        const bool finished = is_finished(job.output, job_identity(job, manifest));
        std::error_code ec;
        ++status.jobs;
        status.finished += finished;
        status.unverified += !finished && fs::is_regular_file(job.output, ec);
        if (shard_count > 1) {
            CatalogueStatus::ShardStatus& s = status.shards[job.index % static_cast<std::size_t>(shard_count)];
            ++s.jobs;
            s.finished += finished;
        }
    }
    return status;
}

std::string status_report(const BatchManifest& manifest, const CatalogueStatus& status) {
    std::ostringstream out;
    const double percent =
        status.jobs ? 100.0 * static_cast<double>(status.finished) / static_cast<double>(status.jobs) : 100.0;
    char share[32];
    std::snprintf(share, sizeof share, "%.0f%%", std::floor(percent));
    out << manifest.path.string() << ": " << status.finished << " of " << status.jobs << " images finished (" << share
        << "), " << status.jobs - status.finished << " to do, in " << manifest.output_dir.string() << "\n";
    if (status.unverified > 0)
        out << status.unverified
            << " image(s) there do not match their .sha256 or job (interrupted, damaged or changed): they will be "
               "rendered again\n";
    std::vector<int> unfinished;
    for (const CatalogueStatus::ShardStatus& s : status.shards) {
        out << "shard " << s.index << "/" << status.shard_count << ": " << s.finished << " of " << s.jobs << " finished"
            << (s.listed ? ", " + list_name(s.index, status.shard_count) + " written" : "") << "\n";
        if (s.finished < s.jobs || !s.listed) unfinished.push_back(s.index);
    }
    if (!unfinished.empty()) {
        out << "shards with work left:";
        for (int i : unfinished) out << " " << i;
        out << " (of " << status.shard_count << ")\n";
    }
    return out.str();
}

}  // namespace foldcast::batch
