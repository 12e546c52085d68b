#pragma once
// How the default profile turns a frame's quantised residuals into rANS symbols
// (docs/codec.md, docs/fca-format.md): one token per vertex classing its three residuals
// as 0, +1, -1 or "escape" (|q| >= 2), then per escaped coordinate a symbol for its sign
// and bit length, whose lower bits go raw.  A token's context is the frame's level class
// and the activity of two neighbours decoded at least kRansLanes tokens earlier (the
// previous row on a grid), so the four interleaved rANS states never wait for each other.
#include <array>
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "predictive_profile.hpp"
#include "rans_coder.hpp"

namespace foldcast::codec {

constexpr int kTokenLevels = 8;  // level classes 0..6, then 7 and above together
constexpr int kActivityBuckets = 5;
constexpr int kTokenTables = kTokenLevels * kActivityBuckets;
// Escapes take one table, or in files that code them in context (escapes_in_context) one
// per context (escape_context): kEscapeTable + context.
constexpr int kEscapeContexts = 8;
constexpr int kEscapeTable = kTokenTables;
constexpr int kTables = kTokenTables + kEscapeContexts;
constexpr int escape_tables(bool in_context) { return in_context ? kEscapeContexts : 1; }
constexpr int kMaxEscapeLength = 31;  // |q| < 2^31: more than any grid coordinate allows

constexpr int residual_class(std::int64_t q) { return q == 0 ? 0 : q == 1 ? 1 : q == -1 ? 2 : 3; }
constexpr int vertex_token(std::int64_t qx, std::int64_t qy, std::int64_t qz) {
    return residual_class(qx) | residual_class(qy) << 2 | residual_class(qz) << 4;
}
constexpr int token_class(int token, int coordinate) { return (token >> (2 * coordinate)) & 3; }

struct TokenTraits {
    std::array<std::uint8_t, kRansAlphabet> weight{};   // sum of 0, 1, 1, 2 per class
    std::array<std::uint8_t, kRansAlphabet> escapes{};  // escaped coordinates
    // q of the non-escaped coordinates (escaped ones 0), padded to 16 bytes so one copy
    // writes a vertex.
    std::array<std::array<std::int32_t, 4>, kRansAlphabet> value{};
    // The first `escapes` entries (padded to 16 bytes for the decoder's four-lane copy).
    std::array<std::array<std::uint32_t, 4>, kRansAlphabet> escaped_coordinates{};
    std::array<std::uint8_t, 13> bucket{};  // of two weights summed: 0, 1, 2-3, 4-7, 8-12
    // The bucket of two neighbours' tokens a and b at [a << 6 | b]: the decoder's one lookup.
    std::array<std::uint8_t, kRansAlphabet * kRansAlphabet> pair_bucket{};
    constexpr TokenTraits() {
        for (int t = 0; t < kRansAlphabet; ++t)
            for (int c = 0; c < 3; ++c) {
                const int k = token_class(t, c);
                weight[static_cast<std::size_t>(t)] =
                    static_cast<std::uint8_t>(weight[static_cast<std::size_t>(t)] + (k == 3 ? 2 : k != 0));
                if (k == 3)
                    escaped_coordinates[static_cast<std::size_t>(t)][escapes[static_cast<std::size_t>(t)]++] =
                        static_cast<std::uint32_t>(c);
                value[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)] = k == 1 ? 1 : k == 2 ? -1 : 0;
            }
        for (int a = 0; a < 13; ++a)
            bucket[static_cast<std::size_t>(a)] = static_cast<std::uint8_t>(
                std::min(static_cast<int>(std::bit_width(unsigned(a))), kActivityBuckets - 1));
        for (std::size_t a = 0; a < kRansAlphabet; ++a)
            for (std::size_t b = 0; b < kRansAlphabet; ++b) pair_bucket[a << 6 | b] = bucket[weight[a] + weight[b]];
    }
};
inline constexpr TokenTraits kTokens{};

constexpr int token_level(int level_class) { return level_class < kTokenLevels ? level_class : kTokenLevels - 1; }
constexpr int level_table_base(int level_class) { return token_level(level_class) * kActivityBuckets; }

// Escape symbol of |q| >= 2: (bit length - 2) * 2 + sign; the bits below the leading one go raw.
constexpr int escape_length(std::int64_t q) { return std::bit_width(static_cast<std::uint64_t>(q < 0 ? -q : q)); }
constexpr int escape_symbol(std::int64_t q) { return (escape_length(q) - 2) * 2 + (q < 0); }

// A vertex's two context neighbours (index `vertices` when there is none): the farther of
// the spatial prediction's two edge neighbours and the parallelogram's opposite corner.
struct ContextNeighbours {
    std::uint32_t far, opposite;
};
std::vector<ContextNeighbours> context_neighbours(const std::vector<SpatialReference>& refs);

// The context of vertex v's escaped coordinate c: the bit length of the larger |q| of the
// same coordinate at its two context neighbours, capped at kEscapeContexts - 1.  A
// residual's size follows its neighbours' (the motion's error is large where the cloth
// moves unpredictably, small where it rests), which the tokens' classes no longer tell
// once every neighbour escapes.  q holds the frame's residuals so far (the neighbours come
// earlier in the frame) and three zeros after the last vertex for a missing neighbour.
template <typename Int>
int escape_context(const Int* q, const ContextNeighbours& neighbours, std::size_t c) {
    const int larger = std::max(escape_length(q[3 * std::size_t(neighbours.far) + c]),
                                escape_length(q[3 * std::size_t(neighbours.opposite) + c]));
    return std::min(larger, kEscapeContexts - 1);
}

}  // namespace foldcast::codec
