// foldcast render SCENE.toml -o OUT.png|OUT.exr: a still of the scene.
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "validators.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/render/render.hpp"
#include "progress_bar.hpp"
#include "resource_estimates.hpp"

namespace foldcast::app {

Command render_command(CLI::App& app) {
    struct Args {
        std::string scene, out, aovs;
        int width = 0, height = 0, spp = 0, threads = 0;
        std::uint64_t seed = 0;
        double noise_threshold = 0.0;
        bool json = false, quiet = false, denoise = false, keep_raw = false, force = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* sub = app.add_subcommand("render", "Path-trace a still of a scene file (PNG or EXR, optional AOVs)");
    sub->add_option("scene", args->scene, "Scene file (TOML), e.g. gallery/default.toml")->required();
    sub->add_option("-o,--output", args->out, "Output image: OUT.png (8-bit sRGB) or OUT.exr (linear float)")
        ->required();
    sub->add_option("--width", args->width, "Image width in pixels (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    sub->add_option("--height", args->height, "Image height in pixels (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    sub->add_option("--spp", args->spp, "Samples per pixel (default: the scene's)")->check(CLI::Range(1, 1 << 20));
    CLI::Option* seed =
        sub->add_option("--seed", args->seed, "Random seed (default: the scene's)")->check(non_negative_integer);
    sub->add_option("--threads", args->threads,
                    "Render threads (default: all cores); the image is the same for any count")
        ->check(CLI::Range(1, 1024));
    sub->add_option("--aov", args->aovs, "Extra images beside OUT: albedo,normal,depth,fold (OUT.<aov>.png|exr)")
        ->check(library_validator([](const std::string& v) { render::parse_aovs(v); }, "AOV,..."));
    sub->add_flag("--denoise", args->denoise,
                  "Denoise, guided by the first hit's albedo, normal and depth (keeps the weave)");
    sub->add_flag("--keep-raw", args->keep_raw, "With --denoise: also write the image before it as OUT.raw.png|exr")
        ->needs("--denoise");
    sub->add_option("--noise-threshold", args->noise_threshold,
                    "Adaptive sampling: from 4 samples on, each 4x4 block of pixels stops once its estimated error "
                    "(in sRGB display units; with --denoise, the error left after denoising) is below this, e.g. 0.02; "
                    "--spp is then the most a pixel takes (with --denoise, 4x --spp for pixels on two surfaces "
                    "or on metal)")
        ->check(finite_in(0.0, 1.0));
    sub->add_flag("--json", args->json,
                  "Print width, height, spp, mean_spp (also garment_mean_spp, backdrop_mean_spp), seconds, rays, "
                  "rays_per_second and the files as JSON");
    sub->add_flag("--quiet", args->quiet, "No progress bar");
    sub->add_flag("--force", args->force, "Render even when the memory or time estimate exceeds this machine's");
    return {sub, [args, seed] {
                render::RenderOptions options;
                options.width = args->width;
                options.height = args->height;
                options.spp = args->spp;
                if (seed->count() > 0) options.seed = args->seed;
                options.threads = args->threads;
                options.denoise = args->denoise;
                options.keep_raw = args->keep_raw;
                options.noise_threshold = args->noise_threshold;
                if (!args->aovs.empty()) options.aovs = render::parse_aovs(args->aovs);
                const render::SceneSpec scene = render::load_scene(args->scene);
                check_writable(args->out);
                check_not_input(args->out, args->scene, "-o");
                if (!scene.look.appearance.texture.empty())
                    check_not_input(args->out, scene.look.appearance.texture, "-o");
                if (!scene.garment.path.empty()) check_not_input(args->out, scene.garment.path, "-o");
                check_scene_drape_work(scene, args->scene, args->force);
                check_render_work(options.width ? options.width : scene.width,
                                  options.height ? options.height : scene.height,
                                  options.spp ? options.spp : scene.spp, 1, 1, "render " + args->out, args->force);
                render::RenderResult result;
                {
                    ProgressBar bar(args->quiet || args->json);
                    result = render::render_still(scene, options, bar.callback());
                }
                const auto written = render::write_render(args->out, result, scene);
                const render::RenderStats& s = result.stats;
                if (args->json) {
                    nlohmann::json j = {{"width", s.width},
                                        {"height", s.height},
                                        {"spp", s.spp},
                                        {"mean_spp", s.mean_spp},
                                        {"garment_mean_spp", s.garment_mean_spp},
                                        {"backdrop_mean_spp", s.backdrop_mean_spp},
                                        {"seconds", s.seconds},
                                        {"rays", s.rays},
                                        {"rays_per_second", s.rays_per_second()}};
                    for (const auto& p : written) j["files"].push_back(p.string());
                    std::printf("%s\n", j.dump().c_str());
                } else if (!args->quiet) {
                    std::fprintf(stderr, "wrote %s (%dx%d, %.1f spp) in %.1f s, %.2f Mrays/s\n", args->out.c_str(),
                                 s.width, s.height, s.mean_spp, s.seconds, s.rays_per_second() / 1e6);
                }
                return 0;
            }};
}

}  // namespace foldcast::app
