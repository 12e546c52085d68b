#include "predictive_profile.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "bit_stream.hpp"
#include "byte_io.hpp"
#include "isometric_prediction.hpp"
#include "rans_coder.hpp"
#include "residual_tokens.hpp"
#include "spatial_weights.hpp"
#include "target_clones.hpp"

namespace foldcast::codec {
namespace {

// Floor division by a positive divisor fixed for a loop: an arithmetic shift when it is a
// power of two (the encoder's residual step, the hierarchy's spans), a division otherwise.
class FloorDivider {
public:
    explicit FloorDivider(std::int64_t divisor)
        : divisor_(divisor),
          shift_(std::has_single_bit(static_cast<std::uint64_t>(divisor))
                     ? std::countr_zero(static_cast<std::uint64_t>(divisor))
                     : -1) {}
    std::int64_t operator()(std::int64_t a) const {
        if (shift_ >= 0) return a >> shift_;
        const std::int64_t q = a / divisor_;
        return (a % divisor_ != 0 && a < 0) ? q - 1 : q;
    }

private:
    std::int64_t divisor_;
    int shift_;
};

// Temporal prediction of frame t (all 3N coordinates) by `ref` from decoded frames, into `out`.
// One loop per kind, so the compiler vectorises it; encoder and decoder share it, so they
// predict bit for bit alike.
FOLDCAST_AVX2_CLONES
void predict_row(const TemporalReference& ref, std::size_t t, const std::int32_t* const* frames, std::size_t row,
                 std::int64_t largest, std::int32_t* out) {
    switch (ref.kind) {
        case TemporalReference::Kind::none:
            std::fill(out, out + row, 0);
            return;
        case TemporalReference::Kind::copy: {
            const std::int32_t* a = frames[ref.frames[0]];
            for (std::size_t k = 0; k < row; ++k) out[k] = a[k];
            return;
        }
        case TemporalReference::Kind::linear: {
            const std::int32_t *a = frames[ref.frames[0]], *b = frames[ref.frames[1]];
            const auto span = static_cast<std::int64_t>(ref.frames[1] - ref.frames[0]);
            const auto offset = static_cast<std::int64_t>(t - ref.frames[0]);
            const FloorDivider divide(span);
            for (std::size_t k = 0; k < row; ++k)
                out[k] = static_cast<std::int32_t>(a[k] + divide(std::int64_t(b[k] - a[k]) * offset + span / 2));
            return;
        }
        case TemporalReference::Kind::cubic: {
            const std::int32_t *a = frames[ref.frames[0]], *b = frames[ref.frames[1]], *c = frames[ref.frames[2]],
                               *d = frames[ref.frames[3]];
            if (cubic_fits_int32(largest)) {
                for (std::size_t k = 0; k < row; ++k) out[k] = (-a[k] + 9 * b[k] + 9 * c[k] - d[k] + 8) >> 4;
                return;
            }
            for (std::size_t k = 0; k < row; ++k)
                out[k] = static_cast<std::int32_t>(
                    (-std::int64_t(a[k]) + 9 * std::int64_t(b[k]) + 9 * std::int64_t(c[k]) - std::int64_t(d[k]) + 8) >>
                    4);
            return;
        }
    }
}

}  // namespace

std::pair<std::size_t, std::size_t> bracket(const TemporalReference& ref) {
    if (ref.kind == TemporalReference::Kind::cubic) return {ref.frames[1], ref.frames[2]};
    if (ref.kind == TemporalReference::Kind::linear) return {ref.frames[0], ref.frames[1]};
    return {ref.frames[0], ref.frames[0]};
}

void predict_frame(const TemporalReference& ref, TemporalMode mode, std::size_t t, const std::int32_t* const* frames,
                   std::size_t row, std::int64_t largest, std::int32_t* out) {
    const auto [left, right] = bracket(ref);
    TemporalReference r = ref;
    switch (mode) {
        case TemporalMode::layout:
            break;
        case TemporalMode::linear:
            r = {TemporalReference::Kind::linear, {left, right, 0, 0}};
            break;
        case TemporalMode::copy_left:
            r = {TemporalReference::Kind::copy, {left, 0, 0, 0}};
            break;
        case TemporalMode::copy_right:
            r = {TemporalReference::Kind::copy, {right, 0, 0, 0}};
            break;
        case TemporalMode::none:
            r = {};
            break;
    }
    predict_row(r, t, frames, row, largest, out);
}

namespace {
// One frame through the closed loop in one mode: quantised residuals q (what is sent) and
// the decoded coordinates, plus an estimate of the bits q costs: the empirical entropy of
// the tokens given their activity bucket, of the escape symbols, and the raw bits.  It
// needs nothing from the entropy coder and tracks the real choice closely.
struct FrameTrial {
    std::vector<std::int64_t> q, decoded, temporal_residual;  // temporal_residual: decoded - temporal prediction
    std::vector<std::uint8_t> token, bucket;                  // per vertex: its token and the token's activity bucket
    double bits = 0.0;
};

double entropy_bits(const std::uint32_t* histogram, int symbols) {
    double total = 0.0, bits = 0.0;
    for (int s = 0; s < symbols; ++s) total += histogram[s];
    for (int s = 0; s < symbols; ++s)
        if (const double h = histogram[s]; h > 0) bits += h * std::log2(total / h);
    return bits;
}

// What every frame's spatial prediction reads: per vertex its two parallelograms and its
// context neighbours.
struct MeshTaps {
    const SpatialTaps& taps;
    const std::vector<ContextNeighbours>& neighbours;
};

// One trial of a frame: its target and temporal prediction (3 per vertex), how it is coded,
// and its own weights (own_weights()).
struct TrialFrame {
    const std::int32_t* target;
    const std::int32_t* temporal;
    const FrameCoding& coding;
    const SpatialWeights* own;

    std::int64_t spatial(const MeshTaps& mesh, std::size_t v, const std::int64_t* residual, int c) const {
        return frame_spatial_prediction(mesh.taps.first[v], mesh.taps.second[v], own, residual, c);
    }
};

// Grid-axis quantisation of vertex v's coordinates c in [c0, c1).
void quantise_grid_axes(const MeshTaps& mesh, const TrialFrame& frame, std::size_t v, int c0, int c1,
                        const FloorDivider& divide, FrameTrial& f) {
    const std::int64_t m = frame.coding.step;
    for (int c = c0; c < c1; ++c) {
        const std::size_t k = 3 * v + static_cast<std::size_t>(c);
        const std::int64_t p =
            frame.temporal[k] +
            (frame.coding.spatial == SpatialMode::none ? 0 : frame.spatial(mesh, v, f.temporal_residual.data(), c));
        const std::int64_t q = divide(frame.target[k] - p + m / 2);
        f.q[k] = q;
        f.decoded[k] = p + q * m;
        f.temporal_residual[k] = f.decoded[k] - frame.temporal[k];
    }
}

// Isometric quantisation (isometric_prediction.hpp) of vertex v; vertices without a
// parallelogram, or whose circle is undefined, along the grid's axes.  Vertex by vertex, as
// the decoder goes: the prediction reads the decoded corners.
void quantise_isometric(const MeshTaps& mesh, const TrialFrame& frame, std::size_t v, const FloorDivider& divide,
                        FrameTrial& f) {
    const SpatialReference& ref = mesh.taps.first[v];
    if (ref.c >= 0) {
        std::int64_t p0[3];
        for (int c = 0; c < 3; ++c)
            p0[c] = frame.temporal[3 * v + static_cast<std::size_t>(c)] +
                    frame.spatial(mesh, v, f.temporal_residual.data(), c);
        IsometricFrame circle;
        if (isometric_frame(
                isometric_inputs(v, std::size_t(ref.a), std::size_t(ref.b), p0, f.decoded.data(), frame.coding.lengths),
                circle)) {
            std::int64_t decoded[3];
            isometric_quantise(circle, frame.target + 3 * v, frame.coding.step, &f.q[3 * v]);
            isometric_reconstruct(circle, &f.q[3 * v], frame.coding.step, decoded);
            for (int c = 0; c < 3; ++c) {
                const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                f.decoded[k] = decoded[c];
                f.temporal_residual[k] = decoded[c] - frame.temporal[k];
            }
            return;
        }
    }
    quantise_grid_axes(mesh, frame, v, 0, 3, divide, f);
}

void run_frame(const MeshTaps& mesh, const std::int32_t* target, const std::int32_t* temporal,
               const FrameCoding& coding, FrameTrial& f) {
    const std::size_t n = mesh.taps.first.size();
    const FloorDivider divide(coding.step);
    const TrialFrame frame{target, temporal, coding, own_weights(coding.weights)};
    if (coding.spatial == SpatialMode::isometric) {
        for (std::size_t v = 0; v < n; ++v) quantise_isometric(mesh, frame, v, divide, f);
        // A residual the decoder would refuse (possible only far off the grid): not this mode.
        const std::int64_t limit = largest_residual(coding.step, coding.spatial);
        for (std::int64_t q : f.q)
            if (q > limit || q < -limit) {
                f.bits = std::numeric_limits<double>::infinity();
                return;
            }
    } else {
        // Coordinate-major: each pass reads one coordinate of earlier vertices.
        for (int c = 0; c < 3; ++c)
            for (std::size_t v = 0; v < n; ++v) quantise_grid_axes(mesh, frame, v, c, c + 1, divide, f);
    }
    const std::vector<ContextNeighbours>& neighbours = mesh.neighbours;
    std::array<std::uint32_t, kActivityBuckets * kRansAlphabet> tokens{};
    std::array<std::uint32_t, kRansAlphabet> escapes{};
    double raw_bits = 0.0;
    auto weight = [&](std::uint32_t u) { return u < n ? kTokens.weight[f.token[u]] : std::uint8_t(0); };
    for (std::size_t v = 0; v < n; ++v) {
        const std::int64_t* q = &f.q[3 * v];
        const auto token = static_cast<std::size_t>(vertex_token(q[0], q[1], q[2]));
        f.token[v] = static_cast<std::uint8_t>(token);
        f.bucket[v] = kTokens.bucket[weight(neighbours[v].far) + weight(neighbours[v].opposite)];
        ++tokens[f.bucket[v] * std::size_t(kRansAlphabet) + token];
        for (std::size_t j = 0; j < kTokens.escapes[token]; ++j) {
            const std::int64_t e = q[kTokens.escaped_coordinates[token][j]];
            ++escapes[static_cast<std::size_t>(escape_symbol(e))];
            raw_bits += escape_length(e) - 1;
        }
    }
    double bits = raw_bits + entropy_bits(escapes.data(), kRansAlphabet);
    for (int b = 0; b < kActivityBuckets; ++b) bits += entropy_bits(tokens.data() + b * kRansAlphabet, kRansAlphabet);
    f.bits = bits;
}
}  // namespace

bool frame_mode_allowed(const TemporalReference& reference, int mode, bool extended) {
    if (mode < 0 || mode >= (extended ? kFrameModes : kIsometricModes)) return false;
    const TemporalMode temporal = temporal_mode(mode);
    if (spatial_mode(mode) == SpatialMode::isometric && reference.kind == TemporalReference::Kind::none)
        return false;  // no decoded frame to keep the lengths of
    switch (reference.kind) {
        case TemporalReference::Kind::none:
            return temporal == TemporalMode::layout;  // frame 0: nothing to predict from
        case TemporalReference::Kind::copy:
            return temporal == TemporalMode::layout || temporal == TemporalMode::none;
        case TemporalReference::Kind::linear:
        case TemporalReference::Kind::cubic:
            return true;
    }
    return false;
}

int default_stride_log2(std::size_t frames, std::size_t vertices) {
    int l = 0;
    while (l < 4 && (std::size_t(2) << l) < frames) ++l;
    // Stride 2^l + 1 >= T: keyframes 0 and T - 1 only, one group; longer changes nothing.
    while ((std::size_t(1) << l) * vertices < kGroupVertexFrames && (std::size_t(1) << l) + 1 < frames) ++l;
    return l;
}

PredictiveLayout::PredictiveLayout(std::size_t t, int stride_log2) : frames(t), stride(std::size_t(1) << stride_log2) {
    references.resize(t);
    level_class.assign(t, 0);
    std::vector<std::size_t> keys;
    for (std::size_t f = 0; f < t; f += stride) keys.push_back(f);
    if (keys.back() != t - 1) keys.push_back(t - 1);
    for (std::size_t i = 1; i < keys.size(); ++i)
        references[keys[i]] = {TemporalReference::Kind::copy, {keys[i - 1], 0, 0, 0}};
    packets.push_back(keys);
    for (std::size_t start = 0; start + 1 < t; start += stride) {
        std::vector<std::size_t> group;
        for (std::size_t h = stride / 2; h >= 1; h /= 2) {
            for (std::size_t f = start + h; f < std::min(start + stride, t - 1); f += 2 * h) {
                group.push_back(f);
                level_class[f] = 1 + std::bit_width(h) - 1;
                TemporalReference& r = references[f];
                // The cubic's outer right frame must already be decoded: inside this
                // group's span, or a keyframe.
                const std::size_t far = f + 3 * h;
                const bool far_ok = far <= t - 1 && (far <= start + stride || far % stride == 0 || far == t - 1);
                if (f >= 3 * h && far_ok) {
                    r = {TemporalReference::Kind::cubic, {f - 3 * h, f - h, f + h, f + 3 * h}};
                } else {
                    r = {TemporalReference::Kind::linear, {f - h, std::min(f + h, t - 1), 0, 0}};
                }
            }
            if (h == 1) break;
        }
        if (!group.empty()) packets.push_back(group);
    }
    // After packet 0 only frame 0 is final (frame 1 is not a keyframe unless T <= 2); each
    // group packet completes frames up to the next keyframe.
    playable_after.assign(packets.size() + 1, 0);
    playable_after[1] = packets.size() == 1 ? t : 1;
    for (std::size_t k = 2; k <= packets.size(); ++k)
        playable_after[k] = k == packets.size() ? t : std::min(t, (k - 1) * stride + 1);
    std::vector<std::size_t> packet_of(t, 0);
    for (std::size_t k = 0; k < packets.size(); ++k)
        for (std::size_t f : packets[k]) packet_of[f] = k;
    referenced.assign(t, 0);
    referenced_later.assign(t, 0);
    for (std::size_t f = 0; f < t; ++f)
        for (std::size_t i = 0; i < references[f].count(); ++i) {
            const std::size_t r = references[f].frames[i];
            referenced[r] = 1;
            if (packet_of[r] < packet_of[f]) referenced_later[r] = 1;
        }
}

SpatialTaps spatial_taps(std::size_t n, const std::vector<Triangle>& triangles) {
    // Triangles around each vertex, in triangle order (compressed rows): the parallelogram's
    // fourth corner is the third vertex of another triangle on the same edge.
    std::vector<std::uint32_t> first(n + 1, 0), around(3 * triangles.size());
    for (const auto& tri : triangles)
        for (std::uint32_t v : tri) ++first[v + 1];
    for (std::size_t v = 0; v < n; ++v) first[v + 1] += first[v];
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < triangles.size(); ++i)
        for (std::uint32_t v : triangles[i]) around[fill[v]++] = static_cast<std::uint32_t>(i);
    // The first vertex other than `v` opposite edge (a, b), below v, or -1.
    auto opposite = [&](std::uint32_t a, std::uint32_t b, std::uint32_t v) -> std::int32_t {
        for (std::uint32_t k = first[a]; k < first[a + 1]; ++k) {
            const Triangle& t = triangles[around[k]];
            if (t[0] != b && t[1] != b && t[2] != b) continue;
            const std::uint32_t c = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
            if (c != v && c < v) return static_cast<std::int32_t>(c);
        }
        return -1;
    };
    // The first two parallelograms of each vertex's triangles in triangle order whose corners
    // all come before it, on different edges.
    SpatialTaps taps{std::vector<SpatialReference>(n), std::vector<SpatialReference>(n)};
    std::vector<std::int32_t> best_neighbour(n, -1);
    for (const auto& tri : triangles)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t v = tri[e];
            for (int o = 1; o < 3; ++o) {
                const std::uint32_t u = tri[(e + o) % 3];
                if (u < v) best_neighbour[v] = std::max(best_neighbour[v], static_cast<std::int32_t>(u));
            }
            const auto a = static_cast<std::int32_t>(tri[(e + 1) % 3]), b = static_cast<std::int32_t>(tri[(e + 2) % 3]);
            SpatialReference &one = taps.first[v], &two = taps.second[v];
            const bool same_edge = (one.a == a && one.b == b) || (one.a == b && one.b == a);
            if (a >= std::int32_t(v) || b >= std::int32_t(v) || two.c >= 0 || same_edge) continue;
            if (const std::int32_t c = opposite(std::uint32_t(a), std::uint32_t(b), v); c >= 0)
                (one.c < 0 ? one : two) = {a, b, c};
        }
    // Without a parallelogram: the highest earlier neighbour alone.
    for (std::size_t v = 0; v < n; ++v)
        if (taps.first[v].c < 0) taps.first[v] = {best_neighbour[v], -1, -1};
    return taps;
}

std::vector<SpatialReference> spatial_references(std::size_t n, const std::vector<Triangle>& triangles) {
    return spatial_taps(n, triangles).first;
}

std::vector<ContextNeighbours> context_neighbours(const std::vector<SpatialReference>& refs) {
    const std::size_t n = refs.size();
    const auto none = static_cast<std::uint32_t>(n);
    std::vector<ContextNeighbours> out(n, ContextNeighbours{none, none});
    // A neighbour counts only if decoded at least kRansLanes tokens earlier.
    auto usable = [](std::int32_t u, std::size_t v) { return u >= 0 && std::size_t(u) + kRansLanes <= v; };
    for (std::size_t v = 0; v < n; ++v) {
        const SpatialReference& r = refs[v];
        const std::int32_t far = r.b < 0 ? r.a : std::min(r.a, r.b);
        if (usable(far, v)) out[v].far = static_cast<std::uint32_t>(far);
        if (usable(r.c, v)) out[v].opposite = static_cast<std::uint32_t>(r.c);
    }
    return out;
}

namespace {
// Which frequency tables a packet sends: each table in use picks between the one it holds
// (from earlier packets, or uniform) and a new one, whichever codes its symbols in fewer bits.
struct TableChoice {
    bool send = false;
    QuantisedTable table;
    double bits = 1.0;  // the keep-or-replace flag, the new table if sent, and the symbols
};

TableChoice choose_table(const SymbolCounts& counts, const SymbolTable& current) {
    TableChoice choice;
    std::uint64_t total = 0;
    for (std::uint64_t c : counts) total += c;
    if (total == 0) return choice;
    choice.table = quantise_table(counts);
    const double fresh = table_bits(choice.table) + coded_bits(counts, make_table(choice.table));
    const double kept = coded_bits(counts, current);
    choice.send = kept < 0.0 || fresh < kept;
    choice.bits += choice.send ? fresh : kept;
    return choice;
}

// Whether a packet of an extended file codes its escapes in context: the frames' escapes
// in the tables of their contexts, counted in `counts`, against all in one table, with the
// tables each way's packet would send.  A small mesh's few escapes may not pay for eight
// tables.
bool escapes_pay_for_context(const std::vector<SymbolCounts>& counts, const std::vector<SymbolTable>& held) {
    double in_context = 0.0;
    SymbolCounts all{};
    for (int context = 0; context < kEscapeContexts; ++context) {
        const auto id = static_cast<std::size_t>(kEscapeTable + context);
        in_context += choose_table(counts[id], held[id]).bits;
        for (std::size_t s = 0; s < kRansAlphabet; ++s) all[s] += counts[id][s];
    }
    return in_context < choose_table(all, held[kEscapeTable]).bits;
}

// The level classes of a packet's frames, ascending: which table groups it may update.
std::vector<int> packet_levels(const PredictiveLayout& layout, const std::vector<std::size_t>& frames) {
    std::vector<int> levels;
    for (std::size_t t : frames) levels.push_back(token_level(layout.level_class[t]));
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    return levels;
}
}  // namespace

std::vector<int> packet_table_ids(const PredictiveLayout& layout, const std::vector<std::size_t>& frames,
                                  bool escapes_in_context) {
    std::vector<int> ids;
    for (int level : packet_levels(layout, frames))
        for (int b = 0; b < kActivityBuckets; ++b) ids.push_back(level * kActivityBuckets + b);
    for (int context = 0; context < escape_tables(escapes_in_context); ++context) ids.push_back(kEscapeTable + context);
    return ids;
}

namespace {
// A frame's mode and the weights it sends (the parallelogram's where it sends none).
struct FrameChoice {
    int mode = -1;
    SpatialWeights weights = kParallelogramWeights;
};

// Chooses how each frame is coded, through the closed loop over decoded frames.
struct FrameChooser {
    const PredictiveLayout& layout;
    MeshTaps mesh;
    const std::vector<const std::int32_t*>& decoded_frames;
    std::int64_t largest;  // bounds every decoded coordinate (predict_frame)
    std::int64_t m;
    bool cascade;
    bool extended;    // isometric modes and fitted weights allowed (extended_modes)
    int forced_mode;  // >= 0: that mode wherever allowed (tests)

    // The cheapest of the allowed modes for frame t (the forced one, else the layout's
    // reference with the parallelogram), spatial ones of an extended file both with the
    // parallelogram's weights and with weights fitted to the frame; `best` holds its trial.
    // `temporal`: room for a temporal prediction (3 per vertex).
    FrameChoice choose(std::size_t t, const std::int32_t* target, std::vector<std::int32_t>& temporal,
                       FrameTrial& trial, FrameTrial& best) const {
        const TemporalReference& ref = layout.references[t];
        const std::size_t row = temporal.size();
        const std::int64_t step = level_residual_step(m, layout.level_class[t], cascade);
        FrameChoice choice;
        // The fit depends only on the temporal prediction: once per temporal mode.
        std::array<std::optional<SpatialWeights>, kTemporalModes> fitted_for;
        for (int candidate = 0; candidate < kFrameModes; ++candidate) {
            if (!frame_mode_allowed(ref, candidate, extended) || (forced_mode >= 0 && candidate != forced_mode))
                continue;
            const TemporalMode temporal_kind = temporal_mode(candidate);
            if (temporal_kind == TemporalMode::linear && ref.kind == TemporalReference::Kind::linear) continue;
            FrameCoding coding;
            coding.spatial = spatial_mode(candidate);
            coding.step = coding.spatial == SpatialMode::isometric ? isometric_step(step, m) : step;
            coding.lengths = decoded_frames[bracket(ref).first];
            predict_frame(ref, temporal_kind, t, decoded_frames.data(), row, largest, temporal.data());
            const bool fit = extended && coding.spatial != SpatialMode::none;
            auto& fitted = fitted_for[static_cast<std::size_t>(temporal_kind)];
            if (fit && !fitted)
                fitted = fit_spatial_weights(mesh.taps.first, mesh.taps.second, target, temporal.data());
            for (int variant = 0; variant < (fit && *fitted != kParallelogramWeights ? 2 : 1); ++variant) {
                coding.weights = variant == 0 ? kParallelogramWeights : *fitted;
                run_frame(mesh, target, temporal.data(), coding, trial);
                if (variant == 1) trial.bits += kSpatialTaps * kWeightBits;  // the weights sent
                if (choice.mode < 0 || trial.bits < best.bits) {
                    std::swap(trial, best);
                    choice = {candidate, coding.weights};
                }
            }
        }
        if (choice.mode < 0) {  // forced mode not allowed here
            choice = {1, kParallelogramWeights};
            predict_frame(ref, TemporalMode::layout, t, decoded_frames.data(), row, largest, temporal.data());
            run_frame(mesh, target, temporal.data(),
                      FrameCoding{SpatialMode::parallelogram, kParallelogramWeights, step}, best);
        }
        return choice;
    }
};

// A rANS symbol of a packet: its table, value and state.
struct PacketSymbol {
    std::uint8_t table, symbol, lane;
};

// The escapes of a packet that does not code them in context, all in the first escape table.
void pool_escapes(std::vector<PacketSymbol>& symbols, std::vector<SymbolCounts>& counts) {
    for (PacketSymbol& s : symbols)
        if (s.table > kEscapeTable) s.table = static_cast<std::uint8_t>(kEscapeTable);
    for (int context = 1; context < kEscapeContexts; ++context) {
        auto& from = counts[static_cast<std::size_t>(kEscapeTable + context)];
        for (std::size_t s = 0; s < kRansAlphabet; ++s) counts[kEscapeTable][s] += from[s];
        from = SymbolCounts{};
    }
}
}  // namespace

std::vector<std::string> predictive_packets(const PredictiveLayout& layout, const std::vector<Triangle>& triangles,
                                            std::size_t n, const std::vector<std::int32_t>& grid,
                                            std::uint32_t residual_step, int forced_mode, bool cascade) {
    const std::size_t row = 3 * n;
    const auto m = static_cast<std::int64_t>(residual_step);
    const SpatialTaps taps = spatial_taps(n, triangles);
    const std::vector<ContextNeighbours> neighbours = context_neighbours(taps.first);
    // Decoded coordinates lie within m / 2 of the grid's.
    std::int64_t largest = 0;
    for (std::int32_t g : grid) largest = std::max<std::int64_t>(largest, g < 0 ? -std::int64_t(g) : g);
    largest += m;
    // Decoded frames (what the decoder will hold) are the references of later frames.
    std::vector<std::int32_t> decoded(grid.size(), 0);
    std::vector<const std::int32_t*> decoded_frames(layout.frames);
    for (std::size_t t = 0; t < layout.frames; ++t) decoded_frames[t] = decoded.data() + t * row;
    const bool extended = extended_modes(cascade, m);
    // Every file written now has the current version: extended ones code escapes in context.
    const bool escapes_in_context = extended;
    const FrameChooser chooser{layout,     MeshTaps{taps, neighbours}, decoded_frames, largest, m, cascade, extended,
                               forced_mode};
    std::vector<std::int32_t> temporal(row);
    FrameTrial trial, best;
    for (FrameTrial* f : {&trial, &best}) {
        f->decoded = f->temporal_residual = std::vector<std::int64_t>(row);
        f->q.assign(row + 3, 0);  // then a missing context neighbour's (escape_context)
        f->token.assign(n, 0);
        f->bucket.assign(n, 0);
    }
    std::vector<SymbolTable> tables(kTables, uniform_table());
    std::vector<std::string> out;
    for (const auto& frames : layout.packets) {
        std::vector<FrameChoice> choices;
        std::vector<PacketSymbol> symbols;               // an extended file's escapes in the tables of their contexts
        std::vector<std::pair<std::uint32_t, int>> raw;  // mantissas: value, bits
        std::vector<SymbolCounts> counts(kTables, SymbolCounts{});
        for (std::size_t t : frames) {
            const std::int32_t* target = grid.data() + t * row;
            choices.push_back(chooser.choose(t, target, temporal, trial, best));
            // Symbol k of a frame (tokens, then escapes) goes to rANS state k mod kRansLanes.
            std::size_t k = 0;
            const int base = level_table_base(layout.level_class[t]);
            for (std::size_t v = 0; v < n; ++v, ++k) {
                const int table = base + best.bucket[v];
                symbols.push_back(
                    {static_cast<std::uint8_t>(table), best.token[v], static_cast<std::uint8_t>(k % kRansLanes)});
                ++counts[static_cast<std::size_t>(table)][best.token[v]];
            }
            for (std::size_t v = 0; v < n; ++v)
                for (std::size_t j = 0; j < kTokens.escapes[best.token[v]]; ++j) {
                    const std::size_t c = kTokens.escaped_coordinates[best.token[v]][j];
                    const std::int64_t q = best.q[3 * v + c];
                    const int symbol = escape_symbol(q);
                    const int table =
                        kEscapeTable + (escapes_in_context ? escape_context(best.q.data(), neighbours[v], c) : 0);
                    symbols.push_back({static_cast<std::uint8_t>(table), static_cast<std::uint8_t>(symbol),
                                       static_cast<std::uint8_t>(k++ % kRansLanes)});
                    ++counts[static_cast<std::size_t>(table)][static_cast<std::size_t>(symbol)];
                    const int length = escape_length(q);
                    const std::uint64_t mag = static_cast<std::uint64_t>(q < 0 ? -q : q);
                    raw.push_back({static_cast<std::uint32_t>(mag - (std::uint64_t(1) << (length - 1))), length - 1});
                }
            for (std::size_t i = 0; i < row; ++i) decoded[t * row + i] = static_cast<std::int32_t>(best.decoded[i]);
        }
        // Side information first (modes, tables), then the raw mantissas in decoding order.
        BitWriter bits;
        for (const FrameChoice& choice : choices) {
            bits.put(static_cast<std::uint32_t>(choice.mode), kModeBits);
            if (extended) write_spatial_weights(bits, spatial_mode(choice.mode), choice.weights);
        }
        const bool in_context = escapes_in_context && escapes_pay_for_context(counts, tables);
        if (escapes_in_context) bits.put(in_context, 1);
        if (escapes_in_context && !in_context) pool_escapes(symbols, counts);
        for (int id : packet_table_ids(layout, frames, in_context)) {
            const TableChoice choice =
                choose_table(counts[static_cast<std::size_t>(id)], tables[static_cast<std::size_t>(id)]);
            bits.put(choice.send, 1);
            if (!choice.send) continue;
            write_table(bits, choice.table);
            tables[static_cast<std::size_t>(id)] = make_table(choice.table);
        }
        for (const auto& [value, count] : raw) bits.put(value, count);
        RansEncoder rans;
        for (const PacketSymbol& s : symbols) rans.push(tables[s.table], s.symbol, s.lane);
        ByteWriter payload;
        const std::string side = bits.finish();
        payload.put_varint(side.size());
        payload.put_bytes(side);
        payload.put_bytes(rans.finish());
        out.push_back(std::move(payload.bytes()));
    }
    return out;
}

}  // namespace foldcast::codec
