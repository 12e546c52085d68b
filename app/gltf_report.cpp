#include "gltf_report.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "foldcast/core/error.hpp"

namespace foldcast::app {

bool is_glb(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".glb";
}

void require_glb_extension(const std::string& path) {
    if (!is_glb(path)) throw InputError("-o '" + path + "' must end in .glb (glTF 2.0 binary)");
}

void print_glb_summary(const std::string& path, const gltf::GlbSummary& s, bool json, const std::string& look) {
    if (json) {
        const nlohmann::json j = {{"output", path},
                                  {"bytes", s.bytes},
                                  {"vertices", s.vertices},
                                  {"triangles", s.triangles},
                                  {"frames", s.frames},
                                  {"morph_targets", s.morph_targets},
                                  {"compressed", s.compressed},
                                  {"max_position_error_m", s.max_position_error_m},
                                  {"look", look.empty() ? nlohmann::json(nullptr) : nlohmann::json(look)}};
        std::printf("%s\n", j.dump().c_str());
        return;
    }
    std::printf("wrote %s (%zu bytes: %zu vertices, %zu triangles, %zu frame%s%s%s)\n", path.c_str(), s.bytes,
                s.vertices, s.triangles, s.frames, s.frames == 1 ? "" : "s",
                s.compressed ? ", quantized + meshopt" : "", look.empty() ? "" : (", look " + look).c_str());
}

}  // namespace foldcast::app
