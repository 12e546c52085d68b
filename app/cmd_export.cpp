// foldcast export SCENE.toml -o garment.glb: the scene's garment (its animation when it has
// several frames) with the scene's look as a glTF 2.0 binary (docs/gltf.md).
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/export/gltf.hpp"
#include "foldcast/render/render.hpp"
#include "gltf_report.hpp"
#include "progress_bar.hpp"

namespace foldcast::app {

Command export_command(CLI::App& app) {
    struct Args {
        std::string scene, out;
        int texture_px = 256;
        bool uncompressed = false, json = false, quiet = false;
        double max_error_m = 0.0;
    };
    auto args = std::make_shared<Args>();
    CLI::App* sub = app.add_subcommand(
        "export",
        "Write a scene's garment with its look as glTF 2.0 (.glb): the animation as morph targets when the "
        "garment moves, the look as a material with the weave baked into textures (docs/gltf.md)");
    sub->add_option("scene", args->scene, "Scene file (TOML), e.g. gallery/default.toml")->required();
    sub->add_option("-o,--output", args->out, "Output OUT.glb")->required();
    sub->add_option("--texture-px", args->texture_px, "Side of the baked weave textures in pixels (a power of two)")
        ->capture_default_str()
        ->check(CLI::IsMember({64, 128, 256, 512, 1024, 2048}));
    sub->add_flag("--uncompressed", args->uncompressed,
                  "Animations: float attributes without KHR_mesh_quantization / EXT_meshopt_compression "
                  "(larger; for importers without meshopt, e.g. Blender)");
    sub->add_option("--max-error-m", args->max_error_m,
                    "Animations: the largest position error the quantization may add (m; default: the finest, 15 "
                    "bits over the largest side)")
        ->check(finite_in(0.0, 1.0))
        ->excludes("--uncompressed");
    sub->add_flag("--json", args->json, "Print what was written as JSON");
    sub->add_flag("-q,--quiet", args->quiet, "No progress bar");
    return {sub, [args] {
                require_glb_extension(args->out);
                check_not_input(args->out, args->scene, "-o");
                const render::SceneSpec scene = render::load_scene(args->scene);
                check_writable(args->out);
                render::GarmentData garment;
                {
                    ProgressBar bar(args->quiet || args->json);
                    garment = render::load_garment(scene, bar.callback());
                }
                gltf::GlbOptions options;
                options.look = scene.look;
                options.compress = !args->uncompressed;
                options.max_position_error_m = args->max_error_m;
                options.texture_px = args->texture_px;
                const gltf::GlbSummary summary = gltf::write_glb(args->out, garment.animation, options);
                print_glb_summary(args->out, summary, args->json, scene.look.name);
                return 0;
            }};
}

}  // namespace foldcast::app
