#include <algorithm>
#include <chrono>
#include <map>
#include <utility>

#include "foldcast/core/error.hpp"
#include "foldcast/render/render.hpp"
#include "foldcast/render/studio_setup.hpp"
#include "foldcast/render/tracer.hpp"

namespace foldcast::render {

std::vector<Aov> parse_aovs(const std::string& list) {
    static const std::map<std::string, Aov> names = {
        {"albedo", Aov::albedo}, {"normal", Aov::normal}, {"depth", Aov::depth}, {"fold", Aov::fold}};
    std::vector<Aov> out;
    std::size_t start = 0;
    while (start <= list.size() && !list.empty()) {
        const std::size_t comma = list.find(',', start);
        const std::string name = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const auto it = names.find(name);
        if (it == names.end())
            throw InputError("AOV list '" + list + "': unknown AOV '" + name +
                             "' (allowed: albedo, normal, depth, fold)");
        if (std::find(out.begin(), out.end(), it->second) == out.end()) out.push_back(it->second);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

const char* aov_name(Aov aov) {
    switch (aov) {
        case Aov::albedo:
            return "albedo";
        case Aov::normal:
            return "normal";
        case Aov::depth:
            return "depth";
        case Aov::fold:
            return "fold";
    }
    return "?";
}

RenderResult render_still(const SceneSpec& scene, GarmentData garment, const RenderOptions& options,
                          const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    const StudioSetup setup(scene, std::move(garment));
    const int frame = scene.garment.frame;
    if (frame >= setup.frame_count())
        throw InputError("garment.frame = " + std::to_string(frame) + ": the garment has " +
                         std::to_string(setup.frame_count()) + " frame(s) (allowed 0.." +
                         std::to_string(setup.frame_count() - 1) + ")");
    const TraceSettings settings = trace_settings(scene, options);
    const Camera camera = frame_camera(scene.camera, {setup.framing_points(frame, 0.0)},
                                       static_cast<double>(settings.width) / settings.height);
    const Tracer tracer(setup.lit_scene(), setup.geometry(frame, 0.0));
    RenderResult result = tracer.render(camera, settings, progress);
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

RenderResult render_still(const SceneSpec& scene, const RenderOptions& options, const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    RenderResult result = render_still(scene, load_garment(scene, progress), options, progress);
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace foldcast::render
