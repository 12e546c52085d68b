#include <openssl/evp.h>

#include <nlohmann/json.hpp>

#include <array>
#include <fstream>
#include <memory>
#include <sstream>
#include <string_view>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/batch/catalogue.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::batch {
namespace fs = std::filesystem;

std::string sha256_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read '" + path.string() + "' to hash it");
    std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context(EVP_MD_CTX_new(), EVP_MD_CTX_free);
    if (!context || EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) != 1)
        throw std::runtime_error("SHA-256 is not available from OpenSSL");
    std::array<char, 1 << 16> buffer;
    while (in) {
        in.read(buffer.data(), buffer.size());
        if (in.gcount() > 0) EVP_DigestUpdate(context.get(), buffer.data(), static_cast<std::size_t>(in.gcount()));
    }
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_DigestFinal_ex(context.get(), digest, &length);
    static const char* hex = "0123456789abcdef";
    std::string text;
    for (unsigned i = 0; i < length; ++i) {
        text += hex[digest[i] >> 4];
        text += hex[digest[i] & 15];
    }
    return text;
}

namespace {
fs::path sidecar(const fs::path& output) {
    fs::path s = output;
    s += ".sha256";
    return s;
}

// The sidecar's first line: a comment for sha256sum -c, the job's identity for us.
constexpr std::string_view kJobTag = "# foldcast-job ";

std::string sha256_text(std::string_view text) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1)
        throw std::runtime_error("SHA-256 is not available from OpenSSL");
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (unsigned i = 0; i < length; ++i) {
        out += hex[digest[i] >> 4];
        out += hex[digest[i] & 15];
    }
    return out;
}

std::string hash_if_file(const fs::path& path) {
    std::error_code ec;
    return fs::is_regular_file(path, ec) ? sha256_file(path) : std::string("none");
}
}  // namespace

std::string job_identity(const BatchJob& job, const BatchManifest& manifest) {
    std::ostringstream text;
    text.precision(17);
    text << "foldcast batch job 1\nscene " << hash_if_file(job.garment.scene) << "\n";
    // The garment files a scene names change the pixels as much as the scene itself.
    std::error_code ec;
    if (fs::is_regular_file(job.garment.scene, ec)) {
        const render::SceneSpec scene = render::load_scene(job.garment.scene);
        fs::path topology = scene.garment.topology;
        if (topology.empty() && !scene.garment.path.empty())
            topology = fs::path(scene.garment.path).replace_extension(".obj");
        text << "garment " << hash_if_file(scene.garment.path) << " " << hash_if_file(topology) << "\n";
    }
    // A look's values live in its file (FOLDCAST_LOOKS_DIR's or the shipped one) and its
    // texture: an edited look changes the pixels under the same name.
    text << "look " << job.look;
    if (const looks::Library library = looks::Library::load_default(); library.contains(job.look)) {
        const looks::Look& look = library.find(job.look);
        text << " " << hash_if_file(look.source) << " " << hash_if_file(look.appearance.texture);
    }
    text << "\nview " << job.view.azimuth_deg << " " << job.view.elevation_deg << "\n"
         << "image " << manifest.width << "x" << manifest.height << " spp " << manifest.spp << " seed " << manifest.seed
         << "\n";
    return sha256_text(text.str());
}

bool is_finished(const fs::path& output, const std::string& identity) {
    std::error_code ec;
    if (!fs::is_regular_file(output, ec) || !fs::is_regular_file(sidecar(output), ec)) return false;
    std::ifstream in(sidecar(output));
    std::string tag_line, recorded;
    std::getline(in, tag_line);
    in >> recorded;
    return tag_line == std::string(kJobTag) + identity && recorded.size() == 64 && recorded == sha256_file(output);
}

std::string outputs_json(const BatchManifest& manifest, const std::vector<BatchOutput>& outputs) {
    nlohmann::json list = nlohmann::json::array();
    for (const BatchOutput& o : outputs)
        list.push_back({{"index", o.job.index},
                        {"garment", o.job.garment.name},
                        {"look", o.job.look},
                        {"view", o.job.view.name},
                        {"path", fs::relative(o.job.output, manifest.output_dir).generic_string()},
                        {"sha256", o.sha256},
                        {"skipped", o.skipped}});
    return list.dump(2) + "\n";
}

std::vector<BatchOutput> run_batch(const BatchManifest& manifest, Shard shard, const JobRenderer& render_job,
                                   const JobDoneFn& job_done) {
    check_shard_count(manifest, shard);
    const std::vector<BatchJob> jobs = shard_jobs(manifest, shard);
    std::vector<BatchOutput> outputs;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const BatchJob& job = jobs[i];
        const std::string identity = job_identity(job, manifest);
        BatchOutput out{job, "", is_finished(job.output, identity)};
        if (!out.skipped) {
            fs::create_directories(job.output.parent_path());
            render_job(job, manifest);
            out.sha256 = sha256_file(job.output);
            write_file_atomically(sidecar(job.output), std::string(kJobTag) + identity + "\n" + out.sha256 + "  " +
                                                           job.output.filename().string() + "\n");
        } else {
            out.sha256 = sha256_file(job.output);
        }
        outputs.push_back(std::move(out));
        if (job_done) job_done(outputs.back(), i + 1, jobs.size());
    }
    const std::string name =
        shard.count == 1 ? std::string("outputs.json")
                         : "outputs-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".json";
    fs::create_directories(manifest.output_dir);
    write_file_atomically(manifest.output_dir / name, outputs_json(manifest, outputs));
    return outputs;
}

}  // namespace foldcast::batch
