#include "mixed_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include <Eigen/Dense>

#include "denoise.hpp"

namespace foldcast::render {
namespace {

// 7 x 7 window: the first-order fit below needs the candidates of two pixels more along the
// edge to pin its slope (default scene, 320x180, seeds 1-3: squared error 19.28 x1e-6 with the
// 5 x 5 mean, 19.14 with this fit).
constexpr int kMixedRadius = 3;
constexpr float kSpatialSigma = 2.0f;  // pixels
// Relative depth: a layer on a fold's back sheet must not take the front sheet's light,
// 2-4% nearer (pixel_layers.hpp).
constexpr float kMixedDepthTolerance = 0.01f;
constexpr int kMixedNormalSquarings = 4;  // cos^16
constexpr float kAlbedoSigma = 0.05f;
// A pure pixel's denoised light, next to a mixed pixel's noisy layer of the same share: it
// lies farther from the edge, so it counts less.  With the first-order fit taking the light's
// slope towards the edge (a fold's contact shadow), it may count more than with a mean
// (0.3): default scene, 320x180, seeds 1-3 (a prototype): squared error 19.22 / 19.14 / 19.11
// x1e-6 at 0.3 / 0.6 / 1.0, the garment's edges 2.92 / 2.94 / 3.00.
constexpr float kPureWeight = 0.6f;
// A pure pixel beside a rebuilt one is refitted too, its own denoised light counting as
// much as this many of its neighbours' samples' worth (a mixed layer of share 1 counts 1):
// default scene, 320x180, seeds 1-3 (a prototype): squared error 19.14 x1e-6 not refitted,
// 19.09 / 18.99 / 19.00 at 3 / 6 / 12.
constexpr float kOwnWeight = 6.0f;
// The fit's slope is held towards 0 by this share of the weights' sum (per pixel squared): a
// layer whose candidates lie along one line (an edge's mixed pixels alone) has no slope
// across it to fit.
constexpr double kSlopeRidge = 0.03;

// One layer of a pixel: its share of the samples and means.
struct Layer {
    float share = 0.0f, depth = 0.0f;
    V3 albedo = V3::Zero(), normal = V3::Zero(), light = V3::Zero();  // light: demodulated
};

V3 divisor(const V3& albedo) {
    return V3(demodulation_divisor(albedo.x()), demodulation_divisor(albedo.y()), demodulation_divisor(albedo.z()));
}

// How well a candidate layer stands in for `layer`: depth, normal and albedo.
float match(const Layer& layer, float depth, const V3& normal, const V3& albedo) {
    const float d = (depth - layer.depth) / (kMixedDepthTolerance * layer.depth);
    float c = std::max(0.0f, normal.dot(layer.normal));
    for (int k = 0; k < kMixedNormalSquarings; ++k) c *= c;
    return std::exp(-d * d - (albedo - layer.albedo).squaredNorm() / (kAlbedoSigma * kAlbedoSigma)) * c;
}

// The weighted first-order fit of the light over the window's offsets from the pixel (light =
// c + g.(dx, dy)), of which the pixel's is c: near a fold's edge the light changes across it
// (the front sheet shades the back one), and a layer's candidates lie on its side of the edge
// only, so their mean is that of light farther from the edge.
class PlaneFit {
public:
    void add(double weight, int dx, int dy, const V3& light) {
        const Eigen::Vector3d x(1.0, dx, dy);
        normal_ += weight * x * x.transpose();
        rhs_ += weight * x * light.cast<double>().transpose();
    }
    // The fit at the pixel; needs a candidate with weight > 0.  Not below 0: a steep slope
    // extrapolated to the pixel could be.
    V3 at_pixel() const {
        Eigen::Matrix3d a = normal_;
        a(1, 1) += kSlopeRidge * normal_(0, 0);
        a(2, 2) += kSlopeRidge * normal_(0, 0);
        const Eigen::Matrix3d coefficients = a.ldlt().solve(rhs_);
        return coefficients.row(0).transpose().cwiseMax(0.0).cast<float>();
    }

private:
    Eigen::Matrix3d normal_ = Eigen::Matrix3d::Zero(), rhs_ = Eigen::Matrix3d::Zero();
};

}  // namespace

void rebuild_mixed_pixels(Image& rgba, const PixelFeatures& features, const std::vector<V3>& light) {
    const int w = rgba.width, h = rgba.height;
    const std::size_t count = static_cast<std::size_t>(w) * h;
    if (features.layer_share.size() != count) return;
    const auto layer = [&](std::size_t i, int l) {
        Layer out;
        out.share = l == 0 ? 1.0f - features.layer_share[i] : features.layer_share[i];
        out.depth = features.layer_depth[l][i];
        out.albedo = features.layer_albedo[l][i];
        out.normal = features.layer_normal[l][i];
        out.light = features.layer_colour[l][i].cwiseQuotient(divisor(out.albedo));
        return out;
    };
    // Two surfaces, neither of them sky (no normal) nor mostly metal.
    const auto rebuilt = [&](std::size_t i) {
        return features.layer_share[i] > 0.0f && rgba.pixels[4 * i + 3] > 0.0f && !features.layer_metal[i] &&
               features.layer_normal[0][i].squaredNorm() > 0.0f &&
               features.layer_normal[1][i].squaredNorm() > 0.0f;
    };
    // A pure pixel of the garment beside a rebuilt one (4-neighbours): the passes and
    // regressions took light from across a fold's edge into it too.  The backdrop's pixels
    // beside the silhouette are left: its light is flat there, and the mixed layers' noise
    // would only be added (default scene, 320x180, seeds 1-3, a prototype: squared error
    // 19.14 x1e-6 none refitted, 18.97 the garment's, 18.99 all).
    const bool has_cloth = features.cloth.size() == count;
    const auto beside_rebuilt = [&](int x, int y) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (features.layer_share[i] != 0.0f || rgba.pixels[4 * i + 3] <= 0.0f || !has_cloth ||
            features.cloth[i] <= 0.5f || features.normal[i].squaredNorm() == 0.0f)
            return false;
        return (x > 0 && rebuilt(i - 1)) || (x + 1 < w && rebuilt(i + 1)) || (y > 0 && rebuilt(i - w)) ||
               (y + 1 < h && rebuilt(i + w));
    };
    // The light of `self` at (x, y) fitted over the window's candidates that match it.
    const auto fitted_light = [&](const Layer& self, int x, int y) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        PlaneFit fit;
        for (int qy = std::max(0, y - kMixedRadius); qy <= std::min(h - 1, y + kMixedRadius); ++qy)
            for (int qx = std::max(0, x - kMixedRadius); qx <= std::min(w - 1, x + kMixedRadius); ++qx) {
                const std::size_t q = static_cast<std::size_t>(qy) * w + qx;
                if (rgba.pixels[4 * q + 3] <= 0.0f) continue;
                const float r2 = static_cast<float>((qx - x) * (qx - x) + (qy - y) * (qy - y));
                const float spatial = std::exp(-r2 / (2.0f * kSpatialSigma * kSpatialSigma));
                if (q == i && features.layer_share[q] == 0.0f) {
                    fit.add(kOwnWeight, 0, 0, light[q]);
                } else if (features.layer_share[q] == 0.0f) {
                    const float m = match(self, features.depth[q], features.normal[q], features.albedo[q]);
                    fit.add(kPureWeight * spatial * m, qx - x, qy - y, light[q]);
                } else {
                    for (int k = 0; k < 2; ++k) {
                        const Layer other = layer(q, k);
                        if (other.share <= 0.0f) continue;
                        const float wt = other.share * spatial * match(self, other.depth, other.normal, other.albedo);
                        fit.add(wt, qx - x, qy - y, other.light);
                    }
                }
            }
        // The pixel itself is among the candidates, with weight > 0.
        return fit.at_pixel();
    };
    // The outputs are written after every pixel's is computed, from the inputs alone.
    std::vector<std::pair<std::size_t, V3>> out;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            if (rebuilt(i)) {
                V3 colour = V3::Zero();
                for (int l = 0; l < 2; ++l) {
                    const Layer self = layer(i, l);
                    colour += self.share * divisor(self.albedo).cwiseProduct(fitted_light(self, x, y));
                }
                out.emplace_back(i, colour);
            } else if (beside_rebuilt(x, y)) {
                Layer self;
                self.share = 1.0f, self.depth = features.depth[i];
                self.albedo = features.albedo[i], self.normal = features.normal[i];
                out.emplace_back(i, divisor(self.albedo).cwiseProduct(fitted_light(self, x, y)));
            }
        }
    for (const auto& [i, colour] : out)
        for (int k = 0; k < 3; ++k) rgba.pixels[4 * i + k] = colour[k];
}

}  // namespace foldcast::render
