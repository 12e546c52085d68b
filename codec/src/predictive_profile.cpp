#include "predictive_profile.hpp"

#include <algorithm>
#include <bit>
#include <map>
#include <stdexcept>

#include "byte_io.hpp"
#include "profile_decoder.hpp"
#include "range_coder.hpp"

namespace foldcast::codec {
namespace {
constexpr int kNeighbourBuckets = 5;
constexpr int kMaxLevelClasses = 22;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {  // b > 0
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

// Temporal prediction of frame t (all 3N coordinates) from decoded frames, into `out`.
// One loop per kind, so the compiler vectorises it; encoder and decoder share it, so they
// predict bit for bit alike.
void predict_frame(const TemporalReference& ref, std::size_t t, const std::int32_t* grid, std::size_t row,
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
        if (std::has_single_bit(static_cast<std::uint64_t>(span))) {  // the usual case: a shift
            const int shift = std::countr_zero(static_cast<std::uint64_t>(span));
            for (std::size_t k = 0; k < row; ++k)
                out[k] = a[k] + ((std::int64_t(b[k] - a[k]) * offset + span / 2) >> shift);
        } else {
            for (std::size_t k = 0; k < row; ++k) out[k] = a[k] + floor_div(std::int64_t(b[k] - a[k]) * offset + span / 2, span);
        }
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

inline std::int64_t spatial(const SpatialReference& s, const std::int64_t* residual, int c) {
    if (s.a < 0) return 0;
    const std::int64_t ra = residual[3 * static_cast<std::size_t>(s.a) + static_cast<std::size_t>(c)];
    if (s.c < 0) return ra;
    return ra + residual[3 * static_cast<std::size_t>(s.b) + static_cast<std::size_t>(c)] -
           residual[3 * static_cast<std::size_t>(s.c) + static_cast<std::size_t>(c)];
}
}  // namespace

class ResidualContexts {
public:
    IntegerModel& model(int level_class, int coordinate, std::int64_t neighbour) {
        const std::uint64_t mag = neighbour < 0 ? static_cast<std::uint64_t>(-neighbour) : static_cast<std::uint64_t>(neighbour);
        const int bucket = std::min(static_cast<int>(std::bit_width(mag)), kNeighbourBuckets - 1);
        return models_[static_cast<std::size_t>((std::min(level_class, kMaxLevelClasses - 1) * 3 + coordinate) * kNeighbourBuckets + bucket)];
    }

private:
    std::vector<IntegerModel> models_ = std::vector<IntegerModel>(kMaxLevelClasses * 3 * kNeighbourBuckets);
};

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
                                            std::size_t n, const std::vector<std::int32_t>& grid) {
    const std::size_t row = 3 * n;
    std::vector<std::int64_t> residual(row), coded(row), prediction(row);
    std::vector<std::string> out;
    ResidualContexts contexts;
    for (const auto& frames : layout.packets) {
        RangeEncoder enc;
        for (std::size_t t : frames) {
            predict_frame(layout.references[t], t, grid.data(), row, prediction.data());
            for (std::size_t k = 0; k < row; ++k) residual[k] = grid[t * row + k] - prediction[k];
            for (int c = 0; c < 3; ++c)  // planar: all x, then y, then z
                for (std::size_t v = 0; v < n; ++v) {
                    const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                    coded[k] = residual[k] - spatial(refs[v], residual.data(), c);
                    const std::int64_t neighbour = refs[v].a < 0 ? 0 : coded[3 * static_cast<std::size_t>(refs[v].a) + static_cast<std::size_t>(c)];
                    encode_integer(enc, contexts.model(layout.level_class[t], c, neighbour), coded[k]);
                }
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
          refs_(spatial_references(h.vertices, h.topology.triangles)),
          grid_(std::size_t(h.frames) * 3 * h.vertices, 0), decoded_(h.frames, 0) {}

    void accept(std::size_t sequence, std::string_view payload) override {
        ByteReader r(payload, what_ + ": data packet " + std::to_string(sequence));
        if (sequence >= layout_.packets.size()) r.fail("more data packets than the header implies");
        const auto& frames = layout_.packets[sequence];
        const std::size_t n = header_.vertices, row = 3 * n;
        RangeDecoder dec(payload);
        std::vector<std::int64_t> residual(row), coded(row), prediction(row);
        for (std::size_t t : frames) {
            for (int c = 0; c < 3; ++c)
                for (std::size_t v = 0; v < n; ++v) {
                    const std::size_t k = 3 * v + static_cast<std::size_t>(c);
                    const std::int64_t neighbour = refs_[v].a < 0 ? 0 : coded[3 * static_cast<std::size_t>(refs_[v].a) + static_cast<std::size_t>(c)];
                    std::int64_t e = 0;
                    if (!decode_integer(dec, contexts_.model(layout_.level_class[t], c, neighbour), e) ||
                        e > 4 * kMaxGridValue || e < -4 * kMaxGridValue)
                        r.fail("residual out of range (corrupt data)");
                    coded[k] = e;
                    residual[k] = e + spatial(refs_[v], residual.data(), c);
                }
            if (dec.overrun()) r.fail("residual data is truncated");
            predict_frame(layout_.references[t], t, grid_.data(), row, prediction.data());
            std::int32_t* out = grid_.data() + t * row;
            bool off_grid = false;
            for (std::size_t k = 0; k < row; ++k) {
                const std::int64_t g = residual[k] + prediction[k];
                off_grid |= g < 0 || g > kMaxGridValue;
                out[k] = static_cast<std::int32_t>(g);
            }
            if (off_grid) r.fail("position leaves the quantisation grid");
            decoded_[t] = 1;
        }
        received_ = sequence + 1;
    }

    std::size_t expected_packets() const override { return layout_.packets.size(); }
    std::size_t playable_frames() const override { return layout_.playable_after[received_]; }

    void reconstruct(std::vector<std::vector<Vec3f>>& frames) const override {
        const std::size_t n = header_.vertices, row = 3 * n, t_count = header_.frames;
        frames.assign(t_count, std::vector<Vec3f>(n));
        const Vec3f centre = 0.5f * (header_.bounds.min + header_.bounds.max);
        // Frames not decoded yet: linear interpolation between the nearest decoded ones
        // (held constant past the last), so a prefix gives a coarser animation.
        std::size_t prev = t_count;
        for (std::size_t t = 0; t < t_count; ++t) {
            if (decoded_[t]) {
                to_positions(t, frames[t]);
                prev = t;
                continue;
            }
            std::size_t next = t + 1;
            while (next < t_count && !decoded_[next]) ++next;
            if (prev == t_count && next == t_count) {
                std::fill(frames[t].begin(), frames[t].end(), centre);
            } else if (prev == t_count || next == t_count) {
                to_positions(prev == t_count ? next : prev, frames[t]);
            } else {
                const float w = float(t - prev) / float(next - prev);
                std::vector<Vec3f> b(n);
                to_positions(next, b);
                for (std::size_t v = 0; v < n; ++v) frames[t][v] = (1.0f - w) * frames[prev][v] + w * b[v];
            }
        }
        (void)row;
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
    std::vector<std::int32_t> grid_;
    std::vector<char> decoded_;
    ResidualContexts contexts_;
    std::size_t received_ = 0;
};
}  // namespace

std::unique_ptr<ProfileDecoder> make_predictive_decoder(const Header& header, const std::string& what) {
    if (header.profile_param > 20) throw InputError(what + ": header: keyframe stride 2^" + std::to_string(header.profile_param) + " (allowed up to 2^20)");
    return std::make_unique<PredictiveDecoder>(header, what);
}

}  // namespace foldcast::codec
