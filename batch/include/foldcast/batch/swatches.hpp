#pragma once
// A swatch sheet: every look draped the same way (same cloth size, supports, camera and
// lights), path-traced side by side and labelled, so a user sees at a glance how each fabric
// folds and shines.  `foldcast looks --swatches OUT.png` draws it.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "foldcast/core/progress.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::batch {

struct SwatchOptions {
    std::vector<std::string> looks;  // empty = every look of the library, sorted by name
    double width_m = 0.5;            // the same drape for every look
    double height_m = 0.7;
    double inset_m = 0.1;
    int tile_width = 240;  // pixels of each rendered tile (the label strip is extra)
    int tile_height = 300;
    int columns = 0;  // 0 = about twice as many columns as rows (12 looks: 6 x 2)
    int spp = 32;
    bool denoise = false;          // each tile denoised (render's --denoise)
    double noise_threshold = 0.0;  // adaptive sampling (render's --noise-threshold); 0 = off
    std::uint64_t seed = 1;
    int threads = 0;  // 0 = all cores
};

struct SwatchTile {
    std::string look;
    int folds = 0;  // drape's fold count for this look and size
    double gsm = 0.0;
};

struct SwatchSheet {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  // 8-bit sRGB, row-major from the top, 3 bytes per pixel
    std::vector<SwatchTile> tiles;  // in sheet order: left to right, top to bottom
    render::RenderStats stats;      // summed over tiles
};

// Throws InputError for unknown look names or impossible sizes.  Deterministic: the same
// options give the same bytes whatever the thread count.
SwatchSheet render_swatch_sheet(const looks::Library& library, const SwatchOptions& options,
                                const ProgressFn& progress = {});
// Writes the sheet as a PNG, atomically.
void write_swatch_sheet(const std::filesystem::path& png, const SwatchSheet& sheet);

}  // namespace foldcast::batch
