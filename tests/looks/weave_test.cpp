// Procedural weaves: deterministic, the right period at the look's physical scale, the right
// structure (twill diagonal, scattered satin), and filtered to the mean at large footprints.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/weave.hpp"

using namespace foldcast::looks;

namespace {

Appearance appearance_of(Weave weave, double repeat_mm = 0.45, int twill_float = 3) {
    Appearance a;
    a.weave = weave;
    a.repeat_mm = repeat_mm;
    a.twill_float = twill_float;
    return a;
}

// Deterministic points inside yarn cells (away from cell edges, where shifting by whole
// periods in floating point could land on the other side of an edge).
std::vector<Eigen::Vector2d> cell_points(double pitch_m, int count) {
    std::vector<Eigen::Vector2d> points;
    std::uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) / 9007199254740992.0;  // [0, 1)
    };
    for (int k = 0; k < count; ++k) {
        const double cell_u = std::floor(next() * 40.0) - 20.0, cell_v = std::floor(next() * 40.0) - 20.0;
        points.emplace_back((cell_u + 0.05 + 0.9 * next()) * pitch_m, (cell_v + 0.05 + 0.9 * next()) * pitch_m);
    }
    return points;
}

bool same(const WeaveSample& a, const WeaveSample& b) {
    return std::abs(a.albedo_scale - b.albedo_scale) < 1e-4f && (a.normal - b.normal).norm() < 1e-4f &&
           a.yarn == b.yarn && std::abs(a.weft_cover - b.weft_cover) < 1e-4f;
}

// Share of points whose sample differs after shifting by (du, dv) yarns.
double share_changed(const Appearance& a, double du, double dv) {
    const double pitch = a.repeat_mm * 1e-3;
    int changed = 0;
    const auto points = cell_points(pitch, 400);
    for (const auto& p : points)
        if (!same(sample_weave(a, p, 0.0), sample_weave(a, p + Eigen::Vector2d(du, dv) * pitch, 0.0))) ++changed;
    return static_cast<double>(changed) / static_cast<double>(points.size());
}

struct Case {
    Weave weave;
    int twill_float;
    int period_yarns;
};
const Case kCases[] = {
    {Weave::plain, 3, 2}, {Weave::twill, 2, 3}, {Weave::twill, 3, 4}, {Weave::satin, 3, 5}, {Weave::knit, 3, 1}};

double std_dev_of_albedo(const Appearance& a, double footprint_yarns) {
    const double pitch = a.repeat_mm * 1e-3;
    double sum = 0.0, sum2 = 0.0;
    const int n = 2000;
    for (int k = 0; k < n; ++k) {
        // An irrational stride scatters the points over many periods.
        const Eigen::Vector2d uv(k * 0.6180339887 * pitch, k * 0.4142135623 * pitch);
        const double v = sample_weave(a, uv, footprint_yarns * pitch).albedo_scale;
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

}  // namespace

TEST(Weave, PeriodIsTheRightMultipleOfRepeat) {
    for (const Case& c : kCases) {
        const Appearance a = appearance_of(c.weave, 0.45, c.twill_float);
        SCOPED_TRACE(std::string(weave_name(c.weave)) + " " + std::to_string(c.twill_float));
        EXPECT_EQ(weave_period_yarns(a), Eigen::Vector2i(c.period_yarns, c.period_yarns));
        EXPECT_EQ(share_changed(a, c.period_yarns, 0), 0.0);
        EXPECT_EQ(share_changed(a, 0, c.period_yarns), 0.0);
        // ... and no shorter shift along u or v repeats it.
        for (int k = 1; k < c.period_yarns; ++k) {
            EXPECT_GT(share_changed(a, k, 0), 0.2) << "shift " << k << " along u";
            EXPECT_GT(share_changed(a, 0, k), 0.2) << "shift " << k << " along v";
        }
        // Within one yarn cell the surface varies (the yarn profile), so a repeat shorter
        // than a yarn is impossible too.
        EXPECT_GT(share_changed(a, 0.5, 0), 0.2);
    }
}

TEST(Weave, ScaleIsPhysical) {
    // Doubling repeat_mm doubles every length of the pattern.
    for (const Case& c : kCases) {
        const Appearance fine = appearance_of(c.weave, 0.3, c.twill_float);
        const Appearance coarse = appearance_of(c.weave, 0.6, c.twill_float);
        for (const auto& p : cell_points(0.3e-3, 200))
            EXPECT_TRUE(same(sample_weave(fine, p, 0.0), sample_weave(coarse, 2.0 * p, 0.0)));
    }
}

TEST(Weave, TwillLinesRunDiagonally) {
    for (int twill_float : {2, 3}) {
        const Appearance twill = appearance_of(Weave::twill, 0.45, twill_float);
        EXPECT_EQ(share_changed(twill, 1, 1), 0.0) << twill_float << "/1";
        EXPECT_GT(share_changed(twill, 1, -1), 0.2) << twill_float << "/1";
    }
}

TEST(Weave, TwillAndSatinShowTheRightShareOfWeft) {
    // Far away every look shows the period average: 1/2 weft for plain, 1/(k+1) for k/1
    // twill (warp-faced), 1/5 for warp-faced 5-harness satin.
    const double expected[] = {0.5, 1.0 / 3.0, 0.25, 0.2};
    for (int c = 0; c < 4; ++c) {
        const Appearance a = appearance_of(kCases[c].weave, 0.45, kCases[c].twill_float);
        EXPECT_NEAR(sample_weave(a, {0.01, 0.02}, 1e-3).weft_cover, expected[c], 1e-3) << c;
    }
}

TEST(Weave, SatinBindingPointsAreScattered) {
    // A satin never puts two binding points (weft on top) next to each other, not even
    // diagonally: that is what hides the twill line.
    const Appearance satin = appearance_of(Weave::satin, 1.0);
    const double pitch = 1e-3;
    auto weft_on_top = [&](int i, int j) {
        return sample_weave(satin, {(i + 0.5) * pitch, (j + 0.5) * pitch}, 0.0).yarn == 2;
    };
    int binding_points = 0;
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
            if (!weft_on_top(i, j)) continue;
            ++binding_points;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                    if (di != 0 || dj != 0) {
                        EXPECT_FALSE(weft_on_top(i + di, j + dj)) << i << "," << j;
                    }
        }
    EXPECT_EQ(binding_points, 20);  // one per warp yarn per 5 picks
}

TEST(Weave, DeterministicAcrossCallsAndThreads) {
    const Appearance denim = appearance_of(Weave::twill, 0.45, 3);
    const auto points = cell_points(0.45e-3, 1000);
    std::vector<WeaveSample> serial;
    for (const auto& p : points) serial.push_back(sample_weave(denim, p, 0.3e-3));
    std::vector<WeaveSample> threaded(points.size());
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (size_t k = static_cast<size_t>(t); k < points.size(); k += 4)
                threaded[k] = sample_weave(denim, points[k], 0.3e-3);
        });
    for (auto& thread : threads) thread.join();
    for (size_t k = 0; k < points.size(); ++k) {
        EXPECT_EQ(serial[k].albedo_scale, threaded[k].albedo_scale);
        EXPECT_EQ(serial[k].normal, threaded[k].normal);
        EXPECT_EQ(serial[k].weft_cover, threaded[k].weft_cover);
    }
}

TEST(Weave, UnfilteredSamplesCarryYarnStructure) {
    for (const Case& c : kCases) {
        const Appearance a = appearance_of(c.weave, 0.45, c.twill_float);
        float max_tilt = 0.0f, min_albedo = 10.0f, max_albedo = 0.0f;
        for (const auto& p : cell_points(0.45e-3, 500)) {
            const WeaveSample s = sample_weave(a, p, 0.0);
            EXPECT_NEAR(s.normal.norm(), 1.0f, 1e-5f);
            EXPECT_GT(s.normal.z(), 0.0f);
            max_tilt = std::max(max_tilt, s.normal.head<2>().norm());
            min_albedo = std::min(min_albedo, s.albedo_scale);
            max_albedo = std::max(max_albedo, s.albedo_scale);
        }
        EXPECT_GT(max_tilt, 0.3f) << weave_name(c.weave);
        EXPECT_GT(max_albedo - min_albedo, 0.3f) << weave_name(c.weave);
    }
    Appearance flat = appearance_of(Weave::plain);
    flat.bump_strength = 0.0;
    EXPECT_EQ(sample_weave(flat, {1e-4, 2e-4}, 0.0).normal, Eigen::Vector3f(0, 0, 1));
    const WeaveSample none = sample_weave(appearance_of(Weave::none), {1e-4, 2e-4}, 0.0);
    EXPECT_EQ(none.albedo_scale, 1.0f);
    EXPECT_EQ(none.normal, Eigen::Vector3f(0, 0, 1));
}

TEST(Weave, LargeFootprintGivesTheMeanAndNoShimmer) {
    for (const Case& c : kCases) {
        const Appearance a = appearance_of(c.weave, 0.45, c.twill_float);
        SCOPED_TRACE(weave_name(c.weave));
        // The fine structure averages to what is shown far away: no brightness jump with
        // distance.
        // (Points of a 2-D Kronecker sequence cover each period evenly, cell edges included.)
        double sum = 0.0;
        const int n = 20000;
        for (int k = 0; k < n; ++k) {
            const Eigen::Vector2d uv(std::fmod(k * 0.7548776662, 1.0), std::fmod(k * 0.5698402910, 1.0));
            sum += sample_weave(a, uv * 20 * 0.45e-3, 0.0).albedo_scale;
        }
        EXPECT_NEAR(sum / n, 1.0, 0.01);
        // Far away: exactly the mean everywhere, flat normal, the filtered slope kept as variance.
        for (const auto& p : cell_points(0.45e-3, 50)) {
            const WeaveSample s = sample_weave(a, p, 2 * 0.45e-3);
            EXPECT_FLOAT_EQ(s.albedo_scale, 1.0f);
            EXPECT_EQ(s.normal, Eigen::Vector3f(0, 0, 1));
            EXPECT_EQ(s.yarn, 0);
            EXPECT_GT(s.slope_variance, 0.0f);
        }
        // Variation across the cloth falls steadily as the footprint grows: what a pixel can't
        // resolve does not flicker from frame to frame.
        const double sd0 = std_dev_of_albedo(a, 0.0), sd_quarter = std_dev_of_albedo(a, 0.3),
                     sd_half = std_dev_of_albedo(a, 0.6), sd_one = std_dev_of_albedo(a, 1.0);
        EXPECT_GT(sd0, 0.05);
        EXPECT_LT(sd_quarter, sd0);
        EXPECT_LT(sd_half, 0.5 * sd0);
        EXPECT_LT(sd_one, 1e-6);
    }
}

TEST(Weave, AlbedoMixesWarpAndWeftColours) {
    Appearance denim = appearance_of(Weave::twill, 1.0, 3);
    denim.base_colour = {0.0f, 0.0f, 0.5f};
    denim.weft_colour = Eigen::Vector3f(0.8f, 0.8f, 0.8f);
    // Cell (3, 0) of a 3/1 twill has the weft on top (i - j = 3 mod 4).
    const WeaveSample weft = sample_weave(denim, {3.5e-3, 0.5e-3}, 0.0);
    ASSERT_EQ(weft.yarn, 2);
    EXPECT_TRUE(weave_albedo(denim, weft).isApprox(Eigen::Vector3f(0.8f, 0.8f, 0.8f) * weft.albedo_scale));
    const WeaveSample far = sample_weave(denim, {3.5e-3, 0.5e-3}, 5e-3);
    EXPECT_TRUE(weave_albedo(denim, far).isApprox(Eigen::Vector3f(0.2f, 0.2f, 0.575f), 1e-3f));
}
