#include "predictive_profile.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>
#include <map>
#include <stdexcept>

#include "byte_io.hpp"
#include "profile_decoder.hpp"
#include "range_coder.hpp"

namespace foldcast::codec {
namespace {
constexpr int kNeighbourBuckets = 5;
constexpr int kMaxLevelClasses = 22;

// Floor division by a positive divisor fixed for a loop: an arithmetic shift when it is a
// power of two (the encoder's residual step, the hierarchy's spans), a division otherwise.
class FloorDivider {
public:
    explicit FloorDivider(std::int64_t divisor)
        : divisor_(divisor),
          shift_(std::has_single_bit(static_cast<std::uint64_t>(divisor)) ? std::countr_zero(static_cast<std::uint64_t>(divisor))
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
void predict_row(const TemporalReference& ref, std::size_t t, const std::int32_t* grid, std::size_t row,
                   std::int64_t* out) {
    auto frame = [&](std::size_t f) { return grid + f * row; };
    switch (ref.kind) {
    case TemporalReference::Kind::none: std::fill(out, out + row, 0); return;
    case TemporalReference::Kind::copy: {
        const std::int32_t* a = frame(ref.frames[0]);
        for (std::size_t k = 0; k < row; ++k) out[k] = a[k];
        return;
    }
    case TemporalReference::Kind::linear: {
        const std::int32_t *a = frame(ref.frames[0]), *b = frame(ref.frames[1]);
        const auto span = static_cast<std::int64_t>(ref.frames[1] - ref.frames[0]);
        const auto offset = static_cast<std::int64_t>(t - ref.frames[0]);
        const FloorDivider divide(span);
        for (std::size_t k = 0; k < row; ++k) out[k] = a[k] + divide(std::int64_t(b[k] - a[k]) * offset + span / 2);
        return;
    }
    case TemporalReference::Kind::cubic: {
        const std::int32_t *a = frame(ref.frames[0]), *b = frame(ref.frames[1]), *c = frame(ref.frames[2]),
                           *d = frame(ref.frames[3]);
        for (std::size_t k = 0; k < row; ++k)
            out[k] = (-std::int64_t(a[k]) + 9 * std::int64_t(b[k]) + 9 * std::int64_t(c[k]) - std::int64_t(d[k]) + 8) >> 4;
        return;
    }
    }
}

// The two decoded frames a midpoint lies between (left < t < right); keyframes: the
// previous keyframe twice.
inline std::pair<std::size_t, std::size_t> bracket(const TemporalReference& ref) {
    if (ref.kind == TemporalReference::Kind::cubic) return {ref.frames[1], ref.frames[2]};
    if (ref.kind == TemporalReference::Kind::linear) return {ref.frames[0], ref.frames[1]};
    return {ref.frames[0], ref.frames[0]};
}

// Temporal prediction of every coordinate of frame t in `mode` (frame_mode_allowed).
void predict_frame(const TemporalReference& ref, TemporalMode mode, std::size_t t, const std::int32_t* grid, std::size_t row,
                   std::int64_t* out) {
    const auto [left, right] = bracket(ref);
    TemporalReference r = ref;
    switch (mode) {
    case TemporalMode::layout: break;
    case TemporalMode::linear: r = {TemporalReference::Kind::linear, {left, right, 0, 0}}; break;
    case TemporalMode::copy_left: r = {TemporalReference::Kind::copy, {left, 0, 0, 0}}; break;
    case TemporalMode::copy_right: r = {TemporalReference::Kind::copy, {right, 0, 0, 0}}; break;
    case TemporalMode::none: r = {}; break;
    }
    predict_row(r, t, grid, row, out);
}

inline std::int64_t spatial(const SpatialReference& s, const std::int64_t* residual, int c) {
    if (s.a < 0) return 0;
    const std::int64_t ra = residual[3 * static_cast<std::size_t>(s.a) + static_cast<std::size_t>(c)];
    if (s.c < 0) return ra;
    return ra + residual[3 * static_cast<std::size_t>(s.b) + static_cast<std::size_t>(c)] -
           residual[3 * static_cast<std::size_t>(s.c) + static_cast<std::size_t>(c)];
}

// Context of a coded residual: |q| of the two earlier neighbours its spatial prediction
// uses (one where there is only one).  Both edges of the parallelogram see a fold front
// crossing the mesh; one alone misses it when the front runs along that edge.
inline std::int64_t neighbour_activity(const SpatialReference& s, const std::int64_t* q, int c) {
    auto at = [&](std::int32_t u) {
        const std::int64_t x = q[3 * static_cast<std::size_t>(u) + static_cast<std::size_t>(c)];
        return x < 0 ? -x : x;
    };
    if (s.a < 0) return 0;
    return s.b < 0 ? at(s.a) : at(s.a) + at(s.b);
}

inline int magnitude_bucket(std::int64_t value) {
    const std::uint64_t mag = value < 0 ? static_cast<std::uint64_t>(-value) : static_cast<std::uint64_t>(value);
    return std::min(static_cast<int>(std::bit_width(mag)), kNeighbourBuckets - 1);
}

// One frame through the closed loop in one mode: quantised residuals q (what is sent) and
// the decoded coordinates, plus an estimate of the bits q costs: the empirical entropy of
// (sign, bit length) given the neighbour's bucket (the coder's context), plus the mantissa
// bits.  It needs nothing from the entropy coder, and is within ~1 % of the real choice.
struct FrameTrial {
    std::vector<std::int64_t> q, decoded, temporal_residual, temporal;
    double bits = 0.0;
};

void run_frame(const std::vector<SpatialReference>& refs, std::size_t n, const std::int32_t* target, std::int64_t m, bool use_spatial,
               FrameTrial& f) {
    constexpr int kSymbols = 2 * 64;
    std::array<std::uint32_t, kNeighbourBuckets * kSymbols> histogram{};
    double mantissa_bits = 0.0;
    const FloorDivider divide(m);
    for (int c = 0; c < 3; ++c)
        for (std::size_t v = 0; v < n; ++v) {
            const std::size_t k = 3 * v + static_cast<std::size_t>(c);
            const std::int64_t p = f.temporal[k] + (use_spatial ? spatial(refs[v], f.temporal_residual.data(), c) : 0);
            const std::int64_t q = divide(target[k] - p + m / 2);
            f.q[k] = q;
            f.decoded[k] = p + q * m;
            f.temporal_residual[k] = f.decoded[k] - f.temporal[k];
            const std::int64_t neighbour = neighbour_activity(refs[v], f.q.data(), c);
            const std::uint64_t mag = q < 0 ? static_cast<std::uint64_t>(-q) : static_cast<std::uint64_t>(q);
            const int length = static_cast<int>(std::bit_width(mag));
            mantissa_bits += length > 1 ? length - 1 : 0;
            ++histogram[static_cast<std::size_t>(magnitude_bucket(neighbour) * kSymbols + (q < 0 ? 64 : 0) + length)];
        }
    double bits = mantissa_bits;
    for (int b = 0; b < kNeighbourBuckets; ++b) {
        double total = 0.0;
        for (int s = 0; s < kSymbols; ++s) total += histogram[static_cast<std::size_t>(b * kSymbols + s)];
        for (int s = 0; s < kSymbols; ++s)
            if (const double h = histogram[static_cast<std::size_t>(b * kSymbols + s)]; h > 0) bits += h * std::log2(total / h);
    }
    f.bits = bits;
}
}  // namespace

class ResidualContexts {
public:
    IntegerModel& model(int level_class, int coordinate, std::int64_t neighbour) {
        return models_[static_cast<std::size_t>((std::min(level_class, kMaxLevelClasses - 1) * 3 + coordinate) * kNeighbourBuckets +
                                                magnitude_bucket(neighbour))];
    }
    // The per-frame prediction mode (one context for all frames).
    IntegerModel& mode_model() { return mode_; }

private:
    std::vector<IntegerModel> models_ = std::vector<IntegerModel>(kMaxLevelClasses * 3 * kNeighbourBuckets);
    IntegerModel mode_;
};

bool frame_mode_allowed(const TemporalReference& reference, int mode) {
    if (mode < 0 || mode >= kFrameModes) return false;
    const auto temporal = static_cast<TemporalMode>(mode / 2);
    switch (reference.kind) {
    case TemporalReference::Kind::none: return temporal == TemporalMode::layout;  // frame 0: nothing to predict from
    case TemporalReference::Kind::copy: return temporal == TemporalMode::layout || temporal == TemporalMode::none;
    case TemporalReference::Kind::linear:
    case TemporalReference::Kind::cubic: return true;
    }
    return false;
}

int default_stride_log2(std::size_t frames) {
    int l = 0;
    while (l < 4 && (std::size_t(2) << l) < frames) ++l;
    return l;
}

PredictiveLayout::PredictiveLayout(std::size_t t, int stride_log2) : frames(t), stride(std::size_t(1) << stride_log2) {
    references.resize(t);
    level_class.assign(t, 0);
    std::vector<std::size_t> keys;
    for (std::size_t f = 0; f < t; f += stride) keys.push_back(f);
    if (keys.back() != t - 1) keys.push_back(t - 1);
    for (std::size_t i = 1; i < keys.size(); ++i) references[keys[i]] = {TemporalReference::Kind::copy, {keys[i - 1], 0, 0, 0}};
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
}

std::vector<SpatialReference> spatial_references(std::size_t n, const std::vector<Triangle>& triangles) {
    std::vector<SpatialReference> refs(n);
    // Opposite vertices of each edge, to find the parallelogram's fourth corner.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> opposite;
    auto key = [](std::uint32_t x, std::uint32_t y) { return std::pair(std::min(x, y), std::max(x, y)); };
    for (const auto& tri : triangles)
        for (int e = 0; e < 3; ++e) opposite[key(tri[e], tri[(e + 1) % 3])].push_back(tri[(e + 2) % 3]);
    std::vector<std::int32_t> best_neighbour(n, -1);
    for (const auto& tri : triangles)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t v = tri[e];
            for (int o = 1; o < 3; ++o) {
                const std::uint32_t u = tri[(e + o) % 3];
                if (u < v) best_neighbour[v] = std::max(best_neighbour[v], static_cast<std::int32_t>(u));
            }
            const std::uint32_t a = tri[(e + 1) % 3], b = tri[(e + 2) % 3];
            if (a < v && b < v && refs[v].c < 0)
                for (std::uint32_t c : opposite[key(a, b)])
                    if (c != v && c < v) {
                        refs[v] = {static_cast<std::int32_t>(a), static_cast<std::int32_t>(b), static_cast<std::int32_t>(c)};
                        break;
                    }
        }
    for (std::size_t v = 0; v < n; ++v)
        if (refs[v].c < 0) refs[v] = {best_neighbour[v], -1, -1};
    return refs;
}

std::vector<std::string> predictive_packets(const PredictiveLayout& layout, const std::vector<SpatialReference>& refs,
                                            std::size_t n, const std::vector<std::int32_t>& grid, std::uint32_t residual_step,
                                            int forced_mode) {
    const std::size_t row = 3 * n;
    const auto m = static_cast<std::int64_t>(residual_step);
    // Decoded frames (what the decoder will hold) are the references of later frames.
    std::vector<std::int32_t> decoded(grid.size(), 0);
    FrameTrial trial, best;
    for (FrameTrial* f : {&trial, &best}) f->q = f->decoded = f->temporal_residual = f->temporal = std::vector<std::int64_t>(row);
    std::vector<std::string> out;
    ResidualContexts contexts;
    for (const auto& frames : layout.packets) {
        RangeEncoder enc;
        for (std::size_t t : frames) {
            const TemporalReference& ref = layout.references[t];
            const std::int32_t* target = grid.data() + t * row;
            int mode = -1;
            best.bits = 0.0;
            for (int candidate = 0; candidate < kFrameModes; ++candidate) {
                if (!frame_mode_allowed(ref, candidate) || (forced_mode >= 0 && candidate != forced_mode)) continue;
                if (candidate / 2 == static_cast<int>(TemporalMode::linear) && ref.kind == TemporalReference::Kind::linear) continue;
                predict_frame(ref, static_cast<TemporalMode>(candidate / 2), t, decoded.data(), row, trial.temporal.data());
                run_frame(refs, n, target, m, candidate % 2 == 1, trial);
                if (mode < 0 || trial.bits < best.bits) {
                    std::swap(trial, best);
                    mode = candidate;
                }
            }
            if (mode < 0) {  // forced mode not allowed here: the layout's reference with spatial prediction
                mode = 1;
                predict_frame(ref, TemporalMode::layout, t, decoded.data(), row, best.temporal.data());
                run_frame(refs, n, target, m, true, best);
            }
            encode_integer(enc, contexts.mode_model(), mode);
            for (int c = 0; c < 3; ++c)  // planar: all x, then y, then z
                for (std::size_t v = 0; v < n; ++v) {
                    const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                    const std::int64_t neighbour = neighbour_activity(refs[v], best.q.data(), c);
                    encode_integer(enc, contexts.model(layout.level_class[t], c, neighbour), best.q[k]);
                }
            for (std::size_t k = 0; k < row; ++k) decoded[t * row + k] = static_cast<std::int32_t>(best.decoded[k]);
        }
        out.push_back(enc.finish());
    }
    return out;
}

namespace {
class PredictiveDecoder final : public ProfileDecoder {
public:
    PredictiveDecoder(const Header& h, std::string what)
        : header_(h), what_(std::move(what)), layout_(h.frames, static_cast<int>(h.profile_param)),
          refs_(spatial_references(h.vertices, h.topology.triangles)), residual_step_(static_cast<std::int64_t>(h.threshold)),
          grid_(std::size_t(h.frames) * 3 * h.vertices, 0), decoded_(h.frames, 0) {}

    void accept(std::size_t sequence, std::string_view payload) override {
        ByteReader r(payload, what_ + ": data packet " + std::to_string(sequence));
        if (sequence >= layout_.packets.size()) r.fail("more data packets than the header implies");
        const auto& frames = layout_.packets[sequence];
        const std::size_t n = header_.vertices, row = 3 * n;
        RangeDecoder dec(payload);
        std::vector<std::int64_t> temporal(row), temporal_residual(row), coded(row);
        const std::int64_t m = residual_step_;
        for (std::size_t t : frames) {
            std::int64_t mode = -1;
            if (!decode_integer(dec, contexts_.mode_model(), mode) || !frame_mode_allowed(layout_.references[t], static_cast<int>(std::clamp<std::int64_t>(mode, -1, kFrameModes))))
                r.fail("frame " + std::to_string(t) + ": prediction mode " + std::to_string(mode) + " is not allowed there (corrupt data)");
            predict_frame(layout_.references[t], static_cast<TemporalMode>(mode / 2), t, grid_.data(), row, temporal.data());
            const bool use_spatial = mode % 2 == 1;
            for (int c = 0; c < 3; ++c)
                for (std::size_t v = 0; v < n; ++v) {
                    const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                    const std::int64_t neighbour = neighbour_activity(refs_[v], coded.data(), c);
                    std::int64_t q = 0;
                    if (!decode_integer(dec, contexts_.model(layout_.level_class[t], c, neighbour), q) || q > 4 * kMaxGridValue ||
                        q < -4 * kMaxGridValue)
                        r.fail("residual out of range (corrupt data)");
                    coded[k] = q;
                    const std::int64_t g = temporal[k] + (use_spatial ? spatial(refs_[v], temporal_residual.data(), c) : 0) + q * m;
                    // Decoded coordinates stay within m / 2 of the encoder's grid [0, kMaxGridValue].
                    if (g < -static_cast<std::int64_t>(kMaxResidualStep) || g > kMaxGridValue + static_cast<std::int64_t>(kMaxResidualStep))
                        r.fail("position leaves the quantisation grid (corrupt data)");
                    temporal_residual[k] = g - temporal[k];
                    grid_[t * row + k] = static_cast<std::int32_t>(g);
                }
            if (dec.overrun()) r.fail("residual data is truncated");
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
            to_positions(t, out);
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
            to_positions(has_prev ? prev - 1 : next, out);
        } else {
            const float w = float(t - (prev - 1)) / float(next - (prev - 1));
            std::vector<Vec3f> b(out.size());
            to_positions(prev - 1, out);
            to_positions(next, b);
            for (std::size_t v = 0; v < out.size(); ++v) out[v] = (1.0f - w) * out[v] + w * b[v];
        }
    }

private:
    void to_positions(std::size_t t, std::vector<Vec3f>& out) const {
        const std::size_t n = header_.vertices;
        const std::int32_t* g = grid_.data() + t * 3 * n;
        const double step = header_.step;
        for (std::size_t v = 0; v < n; ++v)
            for (int c = 0; c < 3; ++c)
                out[v][c] = static_cast<float>(double(header_.bounds.min[c]) + step * double(g[3 * v + static_cast<std::size_t>(c)]));
    }

    Header header_;
    std::string what_;
    PredictiveLayout layout_;
    std::vector<SpatialReference> refs_;
    std::int64_t residual_step_;
    std::vector<std::int32_t> grid_;
    std::vector<char> decoded_;
    ResidualContexts contexts_;
    std::size_t received_ = 0;
};
}  // namespace

std::unique_ptr<ProfileDecoder> make_predictive_decoder(const Header& header, const std::string& what) {
    if (header.profile_param > 20) throw InputError(what + ": header: keyframe stride 2^" + std::to_string(header.profile_param) + " (allowed up to 2^20)");
    if (!(header.threshold >= 1.0 && header.threshold <= double(kMaxResidualStep) && header.threshold == std::floor(header.threshold)))
        throw InputError(what + ": header: residual step " + std::to_string(header.threshold) + " (allowed: an integer 1.." +
                         std::to_string(kMaxResidualStep) + ")");
    return std::make_unique<PredictiveDecoder>(header, what);
}

}  // namespace foldcast::codec
