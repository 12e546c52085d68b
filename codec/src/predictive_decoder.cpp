// Decoder of the default profile (predictive_profile.hpp, docs/fca-format.md).  Per frame:
// the tokens of all vertices (four interleaved rANS states, contexts from vertices decoded
// at least four tokens earlier), the escaped residuals, then the closed-loop reconstruction
// in integers.  Corrupt data can only produce an error, never a read outside the packet.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "bit_stream.hpp"
#include "byte_io.hpp"
#include "isometric_prediction.hpp"
#include "spatial_weights.hpp"
#include "weighted_runs.hpp"
#include "predictive_profile.hpp"
#include "profile_decoder.hpp"
#include "rans_coder.hpp"
#include "residual_tokens.hpp"
#include "spatial_runs.hpp"
#include "target_clones.hpp"

namespace foldcast::codec {
namespace {

// one(i, x) for symbols i = 0 .. count-1, symbol i on states[i mod 4]: the states pass by
// value through locals, so they stay in registers (the callers' byte stores could alias
// anything in memory).
template <typename One>
void on_four_states(std::array<std::uint32_t, kRansLanes>& states, std::size_t count, One one) {
    std::uint32_t x0 = states[0], x1 = states[1], x2 = states[2], x3 = states[3];
    const std::size_t whole = count - count % kRansLanes;
    for (std::size_t i = 0; i < whole; i += kRansLanes) {
        x0 = one(i, x0);
        x1 = one(i + 1, x1);
        x2 = one(i + 2, x2);
        x3 = one(i + 3, x3);
    }
    if (whole + 0 < count) x0 = one(whole + 0, x0);
    if (whole + 1 < count) x1 = one(whole + 1, x1);
    if (whole + 2 < count) x2 = one(whole + 2, x2);
    states = {x0, x1, x2, x3};
}

// Tokens of vertices [0, n) into token[0, n), vertex v with state v mod 4; token[n] is 0,
// the context of a missing neighbour.  Only what the next tokens need happens here; their
// values come after (token_values).  Out of line, like decode_escapes: inlined into the
// packet loop, both measured 5-15 % slower.
template <RansDecoder::Renormalise R>
[[gnu::noinline]] void decode_tokens(RansDecoder& rans, const DecodeTable* const* level_tables,
                                     const ContextNeighbours* neighbours, std::uint8_t* token, std::size_t n) {
    // Pointers in locals too, not reloaded after every byte store.
    const DecodeTable* tables[kActivityBuckets];
    std::copy(level_tables, level_tables + kActivityBuckets, tables);
    const std::uint8_t* pos = rans.position();
    on_four_states(rans.state, n, [&](std::size_t v, std::uint32_t x) {
        const ContextNeighbours nb = neighbours[v];
        const std::size_t bucket = kTokens.pair_bucket[std::size_t(token[nb.far]) << 6 | token[nb.opposite]];
        token[v] = static_cast<std::uint8_t>(RansDecoder::decode<R>(*tables[bucket], x, pos));
        return x;
    });
    rans.set_position(pos);
}

// The values of the frame's escaped coordinates (indices into q in `escaped`, `count` of
// them): escape k is a symbol of table_of(index into q) from state (first_lane + k) mod 4,
// then its raw bits.  False if a magnitude exceeds `largest` (it cannot land on the grid; q
// gets the clamped value).
template <RansDecoder::Renormalise R, typename TableOf>
[[gnu::noinline]] bool decode_escapes(RansDecoder& rans, std::size_t first_lane, TableOf table_of, PaddedBitReader& raw,
                                      const std::uint32_t* escaped, std::size_t count, std::int64_t largest,
                                      std::int32_t* q) {
    PaddedBitReader bits = raw;
    const std::uint8_t* pos = rans.position();
    bool in_range = true;
    std::array<std::uint32_t, kRansLanes> states;  // from first_lane on
    for (std::size_t j = 0; j < kRansLanes; ++j) states[j] = rans.state[(first_lane + j) % kRansLanes];
    on_four_states(states, count, [&](std::size_t i, std::uint32_t x) {
        const int symbol = RansDecoder::decode<R>(table_of(escaped[i]), x, pos);
        const int length = symbol / 2 + 2;
        const std::int64_t magnitude =
            length > kMaxEscapeLength ? largest + 1 : (std::int64_t(1) << (length - 1)) | bits.get(length - 1);
        in_range &= magnitude <= largest;
        const auto bounded = static_cast<std::int32_t>(std::min(magnitude, largest));
        q[escaped[i]] = (symbol & 1) ? -bounded : bounded;
        return x;
    });
    for (std::size_t j = 0; j < kRansLanes; ++j) rans.state[(first_lane + j) % kRansLanes] = states[j];
    rans.set_position(pos);
    raw = bits;
    return in_range;
}

// The residuals the tokens stand for into q (3n + 1 values: each vertex writes 4), escaped
// coordinates 0 for now; returns how many coordinates are escaped, their indices in q listed
// in `escaped` (3n + 4 entries: each vertex writes 4, then moves on by its escape count).
FOLDCAST_AVX2_CLONES
std::size_t token_values(const std::uint8_t* token, std::size_t n, std::int32_t* q, std::uint32_t* escaped) {
    // Four lanes at once (a GNU vector: one add and one store on any target).
    using Lanes = std::uint32_t __attribute__((vector_size(16)));
    std::size_t count = 0;
    for (std::size_t v = 0; v < n; ++v) {
        const std::uint8_t t = token[v];
        std::memcpy(q + 3 * v, kTokens.value[t].data(), 4 * sizeof(std::int32_t));
        Lanes indices;
        std::memcpy(&indices, kTokens.escaped_coordinates[t].data(), sizeof indices);
        indices += static_cast<std::uint32_t>(3 * v);
        std::memcpy(escaped + count, &indices, sizeof indices);
        count += kTokens.escapes[t];
    }
    return count;
}

// The encoder's grid coordinates lie in [0, G] with G the bounds' extent in grid steps (the
// same double arithmetic as the encoder's rounding), decoded ones within m / 2 of them.
std::int32_t grid_high(const Header& h) {
    double extent = 0.0;
    for (int c = 0; c < 3; ++c)
        extent = std::max(extent, std::round((double(h.bounds.max[c]) - double(h.bounds.min[c])) / h.step));
    if (!(extent <= double(kMaxGridValue))) extent = double(kMaxGridValue);  // also NaN: the widest range
    return static_cast<std::int32_t>(extent) + std::int32_t(kMaxResidualStep);
}

// grid = temporal + residual, then position = origin + step * grid.  False if a coordinate
// leaves [low, high].
FOLDCAST_AVX2_CLONES
bool finish_row(const std::uint32_t* temporal, const std::uint32_t* residual, std::size_t row, std::int32_t low,
                std::int32_t high, const double* origin3, double step, std::int32_t* grid, float* out) {
    std::uint32_t outside = 0;
    for (std::size_t k = 0; k < row; ++k) {
        const auto g = static_cast<std::int32_t>(temporal[k] + residual[k]);
        outside |= std::uint32_t(g < low) | std::uint32_t(g > high);
        grid[k] = g;
    }
    if (outside) return false;
    // In double (grid values need up to 31 bits), four vertices at a time with the origin
    // repeated, so the loop vectorises.
    constexpr std::size_t kBlock = 12;
    double origin[kBlock];
    for (std::size_t j = 0; j < kBlock; ++j) origin[j] = origin3[j % 3];
    std::size_t k = 0;
    for (; k + kBlock <= row; k += kBlock)
        for (std::size_t j = 0; j < kBlock; ++j)
            out[k + j] = static_cast<float>(origin[j] + step * double(grid[k + j]));
    for (std::size_t j = 0; k < row; ++k, ++j) out[k] = static_cast<float>(origin[j] + step * double(grid[k]));
    return true;
}

const DecodeTable& uniform_decode_table() {
    static const DecodeTable table = [] {
        DecodeTable t;
        fill_decode_table(uniform_table(), t);
        return t;
    }();
    return table;
}

class PredictiveDecoder final : public ProfileDecoder {
public:
    PredictiveDecoder(const Header& h, std::string what)
        : header_(h),
          what_(std::move(what)),
          layout_(h.frames, static_cast<int>(h.profile_param)),
          taps_(spatial_taps(h.vertices, h.topology.triangles)),
          neighbours_(context_neighbours(taps_.first)),
          plan_(spatial_plan(taps_.first)),
          cascade_(h.profile == Profile::cascade),
          extended_(h.version >= kExtendedVersion && extended_modes(cascade_, std::int64_t(h.threshold))),
          escapes_in_context_(extended_ && h.version >= kEscapeContextVersion),
          weighted_plan_(extended_ ? weighted_plan(taps_) : WeightedPlan{}),
          residual_step_(static_cast<std::int64_t>(h.threshold)),
          grid_high_(grid_high(h)),
          positions_(h.frames),
          decoded_(h.frames, 0),
          grids_(h.frames),
          frame_grid_(h.frames, nullptr),
          table_of_() {
        table_of_.fill(&uniform_decode_table());
    }

    void reuse(std::vector<std::vector<Vec3f>>&& frames) override {
        positions_ = std::move(frames);
        positions_.resize(header_.frames);
    }

    // Hands the decoded frames over instead of copying them when every frame is decoded.
    void release(std::vector<std::vector<Vec3f>>& frames) override {
        if (std::find(decoded_.begin(), decoded_.end(), 0) != decoded_.end()) {
            reconstruct(frames);
            return;
        }
        frames = std::move(positions_);
        positions_.assign(header_.frames, {});
        std::fill(decoded_.begin(), decoded_.end(), 0);
        received_ = 0;
    }

    void accept(std::size_t sequence, std::string_view payload) override {
        ByteReader r(payload, what_ + ": data packet " + std::to_string(sequence));
        if (sequence >= layout_.packets.size()) r.fail("more data packets than the header implies");
        const auto& frames = layout_.packets[sequence];
        const std::size_t side_bytes = r.get_varint("side information length");
        BitReader bits(r.get_bytes(side_bytes, "side information"));
        // A frame decodes at most 4 symbols per vertex (a token and three escapes).
        RansDecoder rans(r.get_bytes(r.remaining(), "residual stream"), 4 * std::size_t(header_.vertices), stream_);

        std::vector<int> modes;
        std::vector<SpatialWeights> weights;
        for (std::size_t t : frames) {
            const int mode = static_cast<int>(bits.get(kModeBits));
            if (!frame_mode_allowed(layout_.references[t], mode, extended_))
                r.fail("frame " + std::to_string(t) + ": prediction mode " + std::to_string(mode) +
                       " is not allowed there (corrupt data)");
            modes.push_back(mode);
            weights.push_back(extended_ ? read_spatial_weights(bits, spatial_mode(mode)) : kParallelogramWeights);
        }
        const bool in_context = escapes_in_context_ && bits.get(1);
        for (int id : packet_table_ids(layout_, frames, in_context)) {
            if (!bits.get(1)) continue;
            const QuantisedTable table = read_table(bits);
            if (std::all_of(table.code.begin(), table.code.end(), [](std::uint8_t c) { return c == 0; }))
                r.fail("frequency table " + std::to_string(id) + " has no symbols (corrupt data)");
            auto& own = tables_[static_cast<std::size_t>(id)];
            if (!own) own = std::make_unique_for_overwrite<DecodeTable>();
            fill_decode_table(make_table(table), *own);
            table_of_[static_cast<std::size_t>(id)] = own.get();
        }
        if (bits.overrun()) r.fail("side information is truncated");
        // The rest of the side information: the escapes' raw bits, in decoding order.
        PaddedBitReader raw(bits.bytes(), bits.bit_position(), raw_bits_);

        const std::size_t n = header_.vertices, row = 3 * n;
        token_.assign(n + 1, 0);
        escaped_.resize(3 * n + 4);
        q_.assign(row + 3, 0);  // then a missing context neighbour's zeros (escape_context; token_values pads with 0)
        temporal_.resize(row);
        residual_.resize(row + 3);  // then the zeros that stand for a missing spatial reference
        // Integer frames: kept in grids_ if a later packet predicts from them, in scratch_
        // for this packet if only its frames do, else in one row (scratch_'s first) reused.
        std::size_t packet_references = 0;
        for (std::size_t t : frames) packet_references += layout_.referenced[t] && !layout_.referenced_later[t];
        if (const std::size_t needed = (1 + packet_references) * row; needed > scratch_size_) {
            scratch_ = std::make_unique_for_overwrite<std::int32_t[]>(
                needed);  // each row is written in full before it is read
            scratch_size_ = needed;
        }
        std::size_t next_scratch = 1;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const std::size_t t = frames[i];
            const SpatialMode spatial = spatial_mode(modes[i]);
            const std::int64_t level_step = level_residual_step(residual_step_, layout_.level_class[t], cascade_);
            const std::int64_t step =
                spatial == SpatialMode::isometric ? isometric_step(level_step, residual_step_) : level_step;
            // |q| above its bound cannot land on the grid; bounding it keeps the sums in int32.
            decode_residuals(rans, raw, layout_.level_class[t], largest_residual(step, spatial), in_context, r);
            predict_frame(layout_.references[t], temporal_mode(modes[i]), t, frame_grid_.data(), row, grid_high_,
                          temporal_.data());
            std::int32_t* grid = scratch_.get();
            if (layout_.referenced_later[t]) {
                if (!grids_[t])
                    grids_[t] = std::make_unique_for_overwrite<std::int32_t[]>(row);  // written in full below
                grid = grids_[t].get();
            } else if (layout_.referenced[t]) {
                grid = scratch_.get() + row * next_scratch++;
            }
            positions_[t].resize(n);
            const FrameCoding coding{spatial, weights[i], step, frame_grid_[bracket(layout_.references[t]).first]};
            if (!reconstruct_grid(coding, grid, positions_[t]))
                r.fail("frame " + std::to_string(t) + ": position leaves the quantisation grid (corrupt data)");
            frame_grid_[t] = layout_.referenced[t] ? grid : nullptr;
            decoded_[t] = 1;
        }
        received_ = sequence + 1;
    }

    std::size_t expected_packets() const override { return layout_.packets.size(); }
    std::size_t playable_frames() const override { return layout_.playable_after[received_]; }

    void reconstruct(std::vector<std::vector<Vec3f>>& frames) const override {
        frames.resize(header_.frames);
        for (std::size_t t = 0; t < frames.size(); ++t) reconstruct_frame(t, frames[t]);
    }

    // Decoded frames exactly; a frame not decoded yet is interpolated linearly between the
    // nearest decoded ones (held constant past the last), so a prefix gives a coarser
    // animation.  Costs one or two frames' conversion, whatever t.
    void reconstruct_frame(std::size_t t, std::vector<Vec3f>& out) const override {
        const std::size_t t_count = header_.frames;
        out.resize(header_.vertices);
        if (decoded_[t]) {
            out = positions_[t];
            return;
        }
        std::size_t prev = t;
        while (prev > 0 && !decoded_[prev - 1]) --prev;
        const bool has_prev = prev > 0;
        std::size_t next = t + 1;
        while (next < t_count && !decoded_[next]) ++next;
        const bool has_next = next < t_count;
        if (!has_prev && !has_next) {
            std::fill(out.begin(), out.end(), Vec3f(0.5f * (header_.bounds.min + header_.bounds.max)));
        } else if (!has_prev || !has_next) {
            out = positions_[has_prev ? prev - 1 : next];
        } else {
            const float w = float(t - (prev - 1)) / float(next - (prev - 1));
            const std::vector<Vec3f>&a = positions_[prev - 1], &b = positions_[next];
            for (std::size_t v = 0; v < out.size(); ++v) out[v] = (1.0f - w) * a[v] + w * b[v];
        }
    }

private:
    // One frame's quantised residuals into q_; |q| above `largest` cannot land on the grid.
    void decode_residuals(RansDecoder& rans, PaddedBitReader& bits, int level_class, std::int64_t largest,
                          bool in_context, const ByteReader& r) {
        // Frames of up to 512 vertices renormalise by a branch, longer ones branch-free
        // (RansDecoder::decode; measured in docs/codec.md: 16x16 grids gain, 32x32 lose).
        constexpr std::size_t kShortFrame = 512;
        using enum RansDecoder::Renormalise;
        const bool in_range = header_.vertices <= kShortFrame
                                  ? decode_symbols<branch>(rans, bits, level_class, largest, in_context)
                                  : decode_symbols<branch_free>(rans, bits, level_class, largest, in_context);
        if (!in_range) r.fail("residual out of range (corrupt data)");
        if (rans.overrun() || bits.overrun()) r.fail("residual data is truncated");
    }

    // The frame's tokens, their values and its escapes (`in_context`: with the tables of
    // their contexts) into q_; false if an escape is out of range.  Escape k of the frame
    // goes to state (n + k) mod 4.
    template <RansDecoder::Renormalise R>
    bool decode_symbols(RansDecoder& rans, PaddedBitReader& bits, int level_class, std::int64_t largest,
                        bool in_context) {
        const std::size_t n = header_.vertices;
        decode_tokens<R>(rans, table_of_.data() + level_table_base(level_class), neighbours_.data(), token_.data(), n);
        const std::size_t escaped = token_values(token_.data(), n, q_.data(), escaped_.data());
        std::int32_t* q = q_.data();
        if (!in_context) {
            const DecodeTable& table = *table_of_[kEscapeTable];
            const auto one_table = [&](std::uint32_t) -> const DecodeTable& { return table; };
            return decode_escapes<R>(rans, n % kRansLanes, one_table, bits, escaped_.data(), escaped, largest, q);
        }
        const DecodeTable* const* tables = table_of_.data() + kEscapeTable;
        const ContextNeighbours* neighbours = neighbours_.data();
        const auto table_of = [=](std::uint32_t k) -> const DecodeTable& {
            const std::uint32_t v = k / 3;
            return *tables[escape_context(q, neighbours[v], k - 3 * v)];
        };
        return decode_escapes<R>(rans, n % kRansLanes, table_of, bits, escaped_.data(), escaped, largest, q);
    }

    // grid = temporal prediction + (spatial prediction) + q m, checked against the grid's
    // range, and the positions it stands for.  The sums wrap modulo 2^32 (unsigned): for a
    // valid file every true value lies in int32, so wrapping changes nothing, and corrupt
    // data can only produce an out-of-range coordinate, caught below, never overflow.
    bool reconstruct_grid(const FrameCoding& coding, std::int32_t* grid, std::vector<Vec3f>& positions) {
        const std::size_t row = 3 * std::size_t(header_.vertices);
        const auto* q = reinterpret_cast<const std::uint32_t*>(q_.data());
        const auto m = static_cast<std::uint32_t>(coding.step);
        std::uint32_t* r = residual_.data();
        if (coding.spatial == SpatialMode::isometric) {
            if (!isometric_residuals(coding, grid)) return false;
        } else if (coding.spatial == SpatialMode::parallelogram && !own_weights(coding.weights)) {
            spatial_residuals(plan_, q, m, r);
        } else if (coding.spatial == SpatialMode::parallelogram) {
            weighted_residuals(coding);
        } else {
            for (std::size_t k = 0; k < row; ++k) r[k] = q[k] * m;
        }
        const double origin[3] = {header_.bounds.min.x(), header_.bounds.min.y(), header_.bounds.min.z()};
        return finish_row(reinterpret_cast<const std::uint32_t*>(temporal_.data()), r, row,
                          -std::int32_t(kMaxResidualStep), grid_high_, origin, header_.step, grid,
                          positions.data()->data());
    }

    // The residuals of an isometric frame into residual_, vertex by vertex (each prediction
    // reads decoded corners), its grid coordinates into `grid` as they are decoded; false if
    // a coordinate leaves the grid's range.  `lengths`: the decoded frame whose edge lengths
    // it keeps.
    bool isometric_residuals(const FrameCoding& coding, std::int32_t* grid) {
        const std::size_t n = header_.vertices;
        const std::int64_t low = -std::int64_t(kMaxResidualStep), high = grid_high_, s = coding.step;
        const SpatialWeights* own = own_weights(coding.weights);
        wide_residual_.resize(3 * n + 3);
        for (std::size_t v = 0; v < n; ++v) {
            const SpatialReference& ref = taps_.first[v];
            const std::int64_t q[3] = {q_[3 * v], q_[3 * v + 1], q_[3 * v + 2]};
            std::int64_t d[3];
            for (int c = 0; c < 3; ++c)
                d[c] = temporal_[3 * v + c] +
                       frame_spatial_prediction(ref, taps_.second[v], own, wide_residual_.data(), c);
            IsometricFrame frame;
            if (ref.c >= 0 &&
                isometric_frame(isometric_inputs(v, std::size_t(ref.a), std::size_t(ref.b), d, grid, coding.lengths),
                                frame)) {
                isometric_reconstruct(frame, q, s, d);
            } else {
                for (int c = 0; c < 3; ++c) d[c] += q[c] * s;
            }
            for (int c = 0; c < 3; ++c) {
                if (d[c] < low || d[c] > high) return false;
                const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                grid[k] = static_cast<std::int32_t>(d[c]);
                wide_residual_[k] = d[c] - temporal_[k];
                residual_[k] = static_cast<std::uint32_t>(wide_residual_[k]);
            }
        }
        return true;
    }

    // The residuals of a frame with its own weights into residual_ (wrapping, as
    // spatial_residuals does), exact in wide_residual_ (weighted_runs.hpp).
    void weighted_residuals(const FrameCoding& coding) {
        const std::size_t row = 3 * std::size_t(header_.vertices);
        wide_residual_.resize(row + 3);
        codec::weighted_residuals(weighted_plan_, taps_, coding.weights, q_.data(), coding.step, wide_residual_.data(),
                                  weighted_scratch_);
        for (std::size_t k = 0; k < row; ++k) residual_[k] = static_cast<std::uint32_t>(wide_residual_[k]);
    }

    Header header_;
    std::string what_;
    PredictiveLayout layout_;
    SpatialTaps taps_;  // the spatial references (first) and, for weighted frames, second parallelograms
    std::vector<ContextNeighbours> neighbours_;
    SpatialPlan plan_;
    bool cascade_;
    bool extended_;            // the file may use the isometric modes and its own weights
    bool escapes_in_context_;  // each packet says whether it codes its escapes in context
    WeightedPlan weighted_plan_;
    std::int64_t residual_step_;
    std::int32_t grid_high_;                     // decoded coordinates lie in [-kMaxResidualStep, grid_high_]
    std::vector<std::vector<Vec3f>> positions_;  // per decoded frame
    std::vector<char> decoded_;
    std::vector<std::unique_ptr<std::int32_t[]>> grids_;  // integer frames kept for later packets
    std::vector<const std::int32_t*> frame_grid_;         // each decoded frame's integers, while they are needed
    std::unique_ptr<std::int32_t[]> scratch_;
    std::size_t scratch_size_ = 0;
    std::vector<std::uint8_t> stream_;                          // the packet's rANS words, padded
    std::vector<std::uint8_t> raw_bits_;                        // the packet's side information, padded
    std::array<std::unique_ptr<DecodeTable>, kTables> tables_;  // each made when its first table arrives
    std::array<const DecodeTable*, kTables> table_of_;          // what each context decodes with now
    std::size_t received_ = 0;
    // Per-frame scratch.
    std::vector<std::uint8_t> token_;
    std::vector<std::uint32_t> escaped_;
    std::vector<std::int32_t> q_;
    std::vector<std::int32_t> temporal_;
    std::vector<std::uint32_t> residual_;
    std::vector<std::int64_t> wide_residual_;     // a weighted or isometric frame's residuals, exact
    std::vector<std::int64_t> weighted_scratch_;  // weighted_residuals' row sums
};
}  // namespace

std::unique_ptr<ProfileDecoder> make_predictive_decoder(const Header& header, const std::string& what) {
    if (header.profile_param > 20)
        throw InputError(what + ": header: keyframe stride 2^" + std::to_string(header.profile_param) +
                         " (allowed up to 2^20)");
    if (!(header.threshold >= 1.0 && header.threshold <= double(kMaxResidualStep) &&
          header.threshold == std::floor(header.threshold)))
        throw InputError(what + ": header: residual step " + std::to_string(header.threshold) +
                         " (allowed: an integer 1.." + std::to_string(kMaxResidualStep) + ")");
    return std::make_unique<PredictiveDecoder>(header, what);
}

}  // namespace foldcast::codec
