// Strain limiting in windows (drape/relax/strain_windows.hpp): the edges beyond the bound are
// brought back, nothing outside the windows and no pinned vertex moves, and the result does
// not depend on the thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "strain_windows.hpp"

namespace foldcast::drape::detail {
namespace {

constexpr double kRest = 0.01;

// A flat nu x nv sheet at its rest lengths, one array per coordinate.
struct Sheet {
    GridSize grid;
    std::vector<float> x, y, z;
    StrainWindows::Scratch scratch;
    explicit Sheet(GridSize g) : grid(g) {
        for (int j = 0; j < g.nv; ++j)
            for (int i = 0; i < g.nu; ++i)
                x.push_back(float(i * kRest)), y.push_back(float(-j * kRest)), z.push_back(0.0f);
    }
    std::size_t at(int i, int j) const { return std::size_t(j) * std::size_t(grid.nu) + std::size_t(i); }
    double worst() const {
        double out = 0.0;
        const auto edge = [&](std::size_t a, std::size_t b) {
            const double dx = x[b] - x[a], dy = y[b] - y[a], dz = z[b] - z[a];
            out = std::max(out, std::abs(std::sqrt(dx * dx + dy * dy + dz * dz) / kRest - 1.0));
        };
        for (int j = 0; j < grid.nv; ++j)
            for (int i = 0; i < grid.nu; ++i) {
                if (i + 1 < grid.nu) edge(at(i, j), at(i + 1, j));
                if (j + 1 < grid.nv) edge(at(i, j), at(i, j + 1));
            }
        return out;
    }
    // settle: by default the share of the bound the relaxation settles its windows within.
    bool limit(const std::vector<char>& pinned, double bound, double settle_share = 0.8) {
        const StrainWindows windows{grid, kRest, kRest, &pinned};
        return windows.limit(x.data(), y.data(), z.data(), bound, settle_share * bound, scratch);
    }
};

// A vertex pulled a fifth of an edge out of the sheet stretches its four edges by ~2 %, and
// one pushed along the row stretches one edge by 20 % and squeezes the other.
TEST(StrainWindows, SpikesComeBackWithinTheBound) {
    Sheet sheet({40, 30});
    sheet.z[sheet.at(10, 10)] = float(0.2 * kRest);
    sheet.x[sheet.at(30, 20)] += float(0.2 * kRest);
    ASSERT_GT(sheet.worst(), 0.19);
    const std::vector<char> pinned(sheet.x.size(), 0);
    EXPECT_TRUE(sheet.limit(pinned, 0.01));
    EXPECT_LE(sheet.worst(), 0.01);
}

TEST(StrainWindows, OnlyTheWindowsMoveAndPinsStay) {
    Sheet sheet({40, 30});
    const std::size_t spike = sheet.at(12, 15), pin = sheet.at(13, 15);
    sheet.z[spike] = float(0.3 * kRest);
    std::vector<char> pinned(sheet.x.size(), 0);
    pinned[pin] = 1;
    const Sheet before = sheet;
    EXPECT_TRUE(sheet.limit(pinned, 0.01));
    EXPECT_LE(sheet.worst(), 0.01);
    EXPECT_EQ(sheet.x[pin], before.x[pin]);
    EXPECT_EQ(sheet.y[pin], before.y[pin]);
    EXPECT_EQ(sheet.z[pin], before.z[pin]);
    EXPECT_NE(sheet.z[spike], before.z[spike]);
    // Far from the spike (beyond the windows of two rounds) nothing moved.
    for (int j = 0; j < 30; ++j)
        for (int i = 0; i < 40; ++i) {
            if (std::abs(i - 12) <= 16 && std::abs(j - 15) <= 16) continue;
            const std::size_t k = sheet.at(i, j);
            EXPECT_EQ(sheet.x[k], before.x[k]);
            EXPECT_EQ(sheet.y[k], before.y[k]);
            EXPECT_EQ(sheet.z[k], before.z[k]);
        }
}

TEST(StrainWindows, WithinTheBoundNothingMoves) {
    Sheet sheet({20, 20});
    sheet.z[sheet.at(5, 5)] = float(0.05 * kRest);  // ~0.1 % on its edges
    const Sheet before = sheet;
    EXPECT_TRUE(sheet.limit(std::vector<char>(sheet.x.size(), 0), 0.01));
    EXPECT_EQ(sheet.x, before.x);
    EXPECT_EQ(sheet.y, before.y);
    EXPECT_EQ(sheet.z, before.z);
}

// The relaxed top row between two supports: a run of edges stretched a little (2 %, within
// the 3 % bound) with one edge pushed beyond it.  Settled into a band (within 2.4 %), the
// spike's neighbours take its excess and nothing else moves; projected to their rest lengths,
// every edge of the window gives up its 2 % and the window's rim has to make room (in the
// animation's top row, a run of such edges that the window could not settle).
TEST(StrainWindows, AStretchedRunSettlesIntoTheBand) {
    const auto stretched_row = [] {
        Sheet sheet({48, 12});
        for (float& v : sheet.x) v *= 1.02f;
        sheet.x[sheet.at(24, 0)] += float(0.02 * kRest);  // its left edge 4 %, its right one 0 %
        return sheet;
    };
    const auto moved = [](const Sheet& a, const Sheet& b) {
        int count = 0;
        for (std::size_t k = 0; k < a.x.size(); ++k) count += a.x[k] != b.x[k] || a.y[k] != b.y[k] || a.z[k] != b.z[k];
        return count;
    };
    std::vector<char> pinned(48 * 12, 0);
    pinned[0] = pinned[47] = 1;
    Sheet band = stretched_row(), to_rest = stretched_row();
    ASSERT_GT(band.worst(), 0.035);
    EXPECT_TRUE(band.limit(pinned, 0.03));
    EXPECT_LE(band.worst(), 0.03);
    EXPECT_TRUE(to_rest.limit(pinned, 0.03, 0.0));
    EXPECT_LE(to_rest.worst(), 0.03);
    EXPECT_LE(moved(band, stretched_row()), 5);
    EXPECT_GT(moved(to_rest, stretched_row()), 50);
}

// An edge between two pinned vertices cannot be brought back: the call says so instead of
// claiming success, and still leaves both pins where they are.
TEST(StrainWindows, AnEdgeBetweenPinsIsReportedNotFixed) {
    Sheet sheet({12, 12});
    const std::size_t a = sheet.at(0, 0), b = sheet.at(1, 0);
    sheet.x[b] += float(0.1 * kRest);
    std::vector<char> pinned(sheet.x.size(), 0);
    pinned[a] = pinned[b] = 1;
    EXPECT_FALSE(sheet.limit(pinned, 0.01));
    EXPECT_EQ(sheet.x[b], float(kRest) + float(0.1 * kRest));
}

// The scratch a call leaves behind (even one that gave up) serves the next call as a new one.
TEST(StrainWindows, AReusedScratchChangesNothing) {
    Sheet gave_up({12, 12});
    gave_up.x[gave_up.at(1, 0)] += float(0.1 * kRest);
    std::vector<char> pinned(gave_up.x.size(), 0);
    pinned[gave_up.at(0, 0)] = pinned[gave_up.at(1, 0)] = 1;
    ASSERT_FALSE(gave_up.limit(pinned, 0.01));
    Sheet fresh({12, 12}), reused({12, 12});
    for (Sheet* s : {&fresh, &reused}) s->z[s->at(6, 6)] = float(0.25 * kRest);
    reused.scratch = gave_up.scratch;
    const std::vector<char> none(fresh.x.size(), 0);
    EXPECT_TRUE(fresh.limit(none, 0.01));
    EXPECT_TRUE(reused.limit(none, 0.01));
    EXPECT_EQ(fresh.x, reused.x);
    EXPECT_EQ(fresh.y, reused.y);
    EXPECT_EQ(fresh.z, reused.z);
}

// Many separate windows (settled in parallel): the same bytes on one thread and on several.
TEST(StrainWindows, SameBytesWhateverTheThreadCount) {
    const auto run = [](int threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        Sheet sheet({64, 64});
        for (int s = 0; s < 24; ++s) sheet.z[sheet.at(4 + (s * 11) % 56, 4 + (s * 7) % 56)] = float(0.25 * kRest);
        EXPECT_TRUE(sheet.limit(std::vector<char>(sheet.x.size(), 0), 0.01));
        return sheet;
    };
    const Sheet one = run(1), many = run(4);
    EXPECT_EQ(std::memcmp(one.x.data(), many.x.data(), one.x.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(one.y.data(), many.y.data(), one.y.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(one.z.data(), many.z.data(), one.z.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace foldcast::drape::detail
