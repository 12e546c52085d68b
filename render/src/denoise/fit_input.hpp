#pragma once
// What every fit of the denoiser's last stages (the cloth's, the supports') reads, one entry
// per pixel: the light it fits, the a-trous result that guides its colour weight, and the
// first hit's surface that decides which taps are alike.
#include <vector>

#include "cloth_bsdf.hpp"

namespace foldcast::render {

struct RegressionInput {
    int width = 0, height = 0;
    const std::vector<V3>* light = nullptr;               // the light to fit, demodulated (colour / albedo)
    const std::vector<float>* guide = nullptr;            // luminance of the a-trous result: the colour weight's
    const std::vector<float>* variance = nullptr;         // of the guide's luminance
    const std::vector<float>* fitted_variance = nullptr;  // of the light's luminance: its noise
    const std::vector<float>* nx = nullptr;               // unit shading normal
    const std::vector<float>* ny = nullptr;
    const std::vector<float>* nz = nullptr;
    const std::vector<float>* depth = nullptr;
    const std::vector<float>* ax = nullptr;  // first-hit albedo
    const std::vector<float>* ay = nullptr;
    const std::vector<float>* az = nullptr;
};

}  // namespace foldcast::render
