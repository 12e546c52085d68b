#pragma once
// A path-traced render as the compare library reads a photo: 8-bit sRGB (exposure applied,
// no alpha) scaled to 0-1.  Shared by the tests that use foldcast's own renders as photos.
#include "foldcast/compare/image.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::test {

inline compare::Image photo_of(const render::Image& beauty, double exposure_ev) {
    const auto srgb = render::to_srgb8(beauty, exposure_ev, false);
    compare::Image photo(beauty.width, beauty.height, 3);
    for (std::size_t k = 0; k < photo.values.size(); ++k) photo.values[k] = srgb[k] / 255.0f;
    return photo;
}

}  // namespace foldcast::test
