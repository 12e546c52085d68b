// foldcast preview SCENE.toml -o OUT.png: a rasterised still through EGL, in a fraction of
// a second.  Exits 2 with one line where no EGL context can be made.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/preview/preview.hpp"
#include "resource_estimates.hpp"

namespace foldcast::app {

Command preview_command(CLI::App& app) {
    struct Args {
        std::string scene, out, aovs;
        int width = 0, height = 0, msaa = 4;
        bool json = false, quiet = false, force = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* sub = app.add_subcommand(
        "preview", "Rasterise a quick preview of a scene file with OpenGL through EGL (no display needed)");
    sub->add_option("scene", args->scene, "Scene file (TOML), e.g. gallery/default.toml")->required();
    sub->add_option("-o,--output", args->out, "Output image: OUT.png (8-bit sRGB) or OUT.exr (linear float)")
        ->required();
    sub->add_option("--width", args->width, "Image width in pixels (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    sub->add_option("--height", args->height, "Image height in pixels (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    sub->add_option("--msaa", args->msaa, "Multisample anti-aliasing samples per pixel")->check(CLI::Range(1, 16));
    sub->add_option("--aov", args->aovs, "Extra image beside OUT: depth (OUT.depth.png|exr)")
        ->check(CLI::IsMember({"depth"}));
    sub->add_flag("--json", args->json, "Print width, height, seconds and the OpenGL device as JSON");
    sub->add_flag("--quiet", args->quiet, "Print nothing on success");
    sub->add_flag("--force", args->force, "Rasterise even when the memory estimate exceeds this machine's");
    return {sub, [args] {
                render::RenderOptions options;
                options.width = args->width;
                options.height = args->height;
                if (!args->aovs.empty()) options.aovs = render::parse_aovs(args->aovs);
                const render::SceneSpec scene = render::load_scene(args->scene);
                check_writable(args->out);
                check_scene_drape_work(scene, args->scene, args->force);
                const long long width = args->width ? args->width : scene.width;
                const long long height = args->height ? args->height : scene.height;
                check_preview_work(width, height, args->msaa,
                                   "preview " + args->out + " (" + std::to_string(width) + "x" +
                                       std::to_string(height) + ", --msaa " + std::to_string(args->msaa) + ")",
                                   args->force);
                const render::RenderResult result = preview::preview_still(scene, options, args->msaa);
                const auto written = render::write_render(args->out, result, scene);
                const render::RenderStats& s = result.stats;
                if (args->json) {
                    nlohmann::json j = {{"width", s.width}, {"height", s.height}, {"seconds", s.seconds}};
                    for (const auto& p : written) j["files"].push_back(p.string());
                    std::printf("%s\n", j.dump().c_str());
                } else if (!args->quiet) {
                    std::fprintf(stderr, "wrote %s (%dx%d preview) in %.2f s\n", args->out.c_str(), s.width, s.height,
                                 s.seconds);
                }
                return 0;
            }};
}

}  // namespace foldcast::app
