#include "paper_profile.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "byte_io.hpp"
#include "profile_decoder.hpp"
#include "run_length_coder.hpp"

namespace foldcast::codec {
namespace {
constexpr std::size_t kCoarseRows = (std::size_t(1) << kCoarsestLevel) + 3;

// Values of coefficient rows `rows` for every trajectory, row-major (row, then vertex xyz).
std::vector<std::int32_t> gather(const IntMatrix& q, std::span<const std::size_t> rows) {
    std::vector<std::int32_t> values;
    values.reserve(rows.size() * static_cast<std::size_t>(q.cols()));
    for (std::size_t r : rows)
        for (Eigen::Index k = 0; k < q.cols(); ++k) values.push_back(q(static_cast<Eigen::Index>(r), k));
    return values;
}

std::vector<std::size_t> coarse_rows() {
    std::vector<std::size_t> rows(kCoarseRows);
    for (std::size_t r = 0; r < kCoarseRows; ++r) rows[r] = r;
    return rows;
}
}  // namespace

PaperEncoder::PaperEncoder(const Animation& anim) : anim_(anim), layout_(anim.vertex_count(), anim.frame_count()) {
    const std::size_t n = layout_.vertices, t = layout_.frames;
    coefficients_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(layout_.wavelet->length()),
                                          static_cast<Eigen::Index>(layout_.trajectories));
    for (std::size_t k = 1; k < t; ++k)
        for (std::size_t v = 0; v < n; ++v)
            for (int c = 0; c < 3; ++c)
                coefficients_(static_cast<Eigen::Index>(k - 1),
                              static_cast<Eigen::Index>(3 * v + static_cast<std::size_t>(c))) =
                    double(anim.frames[k][v][c]) - double(anim.frames[k - 1][v][c]);
    layout_.wavelet->analyse(coefficients_);
}

double PaperEncoder::min_step() const {
    return std::max(coefficients_.cwiseAbs().maxCoeff() / double(kMaxCodedMagnitude / 2), 1e-12);
}

double PaperEncoder::threshold_for_keep(double fraction) const {
    const Eigen::Index rows = coefficients_.rows() - static_cast<Eigen::Index>(kCoarseRows);
    std::vector<double> magnitudes;
    magnitudes.reserve(static_cast<std::size_t>(rows * coefficients_.cols()));
    for (Eigen::Index k = 0; k < coefficients_.cols(); ++k)
        for (Eigen::Index r = static_cast<Eigen::Index>(kCoarseRows); r < coefficients_.rows(); ++r)
            magnitudes.push_back(std::abs(coefficients_(r, k)));
    if (magnitudes.empty() || fraction >= 1.0) return 0.0;
    const auto keep = static_cast<std::size_t>(std::llround(fraction * double(magnitudes.size())));
    if (keep == 0) return std::numeric_limits<double>::infinity();
    std::nth_element(magnitudes.begin(), magnitudes.begin() + static_cast<std::ptrdiff_t>(keep - 1), magnitudes.end(),
                     std::greater<>());
    return magnitudes[keep - 1];
}

IntMatrix PaperEncoder::quantise(double step, double threshold) const {
    IntMatrix q(coefficients_.rows(), coefficients_.cols());
    for (Eigen::Index k = 0; k < coefficients_.cols(); ++k)
        for (Eigen::Index r = 0; r < coefficients_.rows(); ++r) {
            const double c = coefficients_(r, k);
            const bool dropped = r >= static_cast<Eigen::Index>(kCoarseRows) && std::abs(c) < threshold;
            q(r, k) = dropped ? 0 : static_cast<std::int32_t>(std::lround(c / step));
        }
    return q;
}

double PaperEncoder::max_error_m(double step, double threshold) const {
    std::vector<std::vector<Vec3f>> frames;
    paper_reconstruct(layout_, anim_.frames.front(), quantise(step, threshold), step, frames);
    double worst = 0.0;
    for (std::size_t t = 0; t < frames.size(); ++t)
        for (std::size_t v = 0; v < frames[t].size(); ++v)
            worst = std::max(worst, double((frames[t][v] - anim_.frames[t][v]).norm()));
    return worst;
}

std::vector<std::string> PaperEncoder::packets(double step, double threshold) const {
    const IntMatrix q = quantise(step, threshold);
    const auto coarse = coarse_rows();
    std::vector<std::vector<std::int32_t>> blocks{gather(q, coarse)};
    for (std::size_t p = 0; p < layout_.packet_first.size(); ++p)
        blocks.push_back(
            gather(q, std::span(layout_.node_rows).subspan(layout_.packet_first[p], layout_.packet_count[p])));
    std::vector<std::uint64_t> counts(kRunLengthAlphabet, 0);
    for (const auto& b : blocks) count_run_length_symbols(b, counts);
    if (std::all_of(counts.begin(), counts.end(), [](auto c) { return c == 0; })) counts[0] = 1;
    const HuffmanTable table = HuffmanTable::from_counts(counts);

    std::vector<std::string> out;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        ByteWriter w;
        if (b == 0) {
            table.write(w);
            for (const Vec3f& p : anim_.frames.front())
                for (int c = 0; c < 3; ++c) w.put<float>(p[c]);
        }
        BitWriter bits;
        encode_run_length(blocks[b], table, bits);
        w.put_bytes(bits.finish());
        out.push_back(std::move(w.bytes()));
    }
    return out;
}

void paper_reconstruct(const PaperLayout& layout, const std::vector<Vec3f>& first_frame, const IntMatrix& quantised,
                       double step, std::vector<std::vector<Vec3f>>& frames) {
    Eigen::MatrixXd x = quantised.cast<double>() * step;
    layout.wavelet->synthesise(x);
    frames.assign(layout.frames, std::vector<Vec3f>(layout.vertices));
    std::vector<double> p(layout.trajectories);
    for (std::size_t v = 0; v < layout.vertices; ++v)
        for (int c = 0; c < 3; ++c) p[3 * v + static_cast<std::size_t>(c)] = first_frame[v][c];
    for (std::size_t t = 0; t < layout.frames; ++t) {
        for (std::size_t k = 0; k < layout.trajectories; ++k) {
            if (t > 0) p[k] += x(static_cast<Eigen::Index>(t - 1), static_cast<Eigen::Index>(k));
            frames[t][k / 3][static_cast<Eigen::Index>(k % 3)] = static_cast<float>(p[k]);
        }
    }
}

namespace {
class PaperDecoder final : public ProfileDecoder {
public:
    PaperDecoder(const Header& h, std::string what)
        : header_(h),
          what_(std::move(what)),
          layout_(h.vertices, h.frames),
          quantised_(IntMatrix::Zero(static_cast<Eigen::Index>(layout_.wavelet->length()),
                                     static_cast<Eigen::Index>(layout_.trajectories))) {}

    void accept(std::size_t sequence, std::string_view payload) override {
        ByteReader r(payload, what_ + ": data packet " + std::to_string(sequence));
        if (sequence >= layout_.data_packets()) r.fail("more data packets than the header implies");
        std::vector<std::size_t> rows;
        if (sequence == 0) {
            table_ = HuffmanTable::read(r, kRunLengthAlphabet);
            first_frame_.resize(layout_.vertices);
            for (auto& p : first_frame_)
                for (int c = 0; c < 3; ++c) {
                    p[c] = r.get<float>("first frame");
                    if (!std::isfinite(p[c])) r.fail("first frame has a non-finite position");
                }
            rows = coarse_rows();
        } else {
            const auto first = layout_.packet_first[sequence - 1];
            rows.assign(
                layout_.node_rows.begin() + static_cast<std::ptrdiff_t>(first),
                layout_.node_rows.begin() + static_cast<std::ptrdiff_t>(first + layout_.packet_count[sequence - 1]));
        }
        std::vector<std::int32_t> values(rows.size() * layout_.trajectories);
        const std::string_view rest = r.get_bytes(r.remaining(), "coefficients");
        BitReader bits(rest);
        decode_run_length(bits, table_, values, r);
        std::size_t i = 0;
        for (std::size_t row : rows)
            for (std::size_t k = 0; k < layout_.trajectories; ++k)
                quantised_(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(k)) = values[i++];
        received_ = sequence + 1;
    }

    std::size_t expected_packets() const override { return layout_.data_packets(); }

    std::size_t playable_frames() const override {
        if (received_ == 0) return 0;
        const std::size_t nodes =
            received_ == 1 ? 0 : layout_.packet_first[received_ - 2] + layout_.packet_count[received_ - 2];
        return layout_.playable_after[nodes];
    }

    void reconstruct(std::vector<std::vector<Vec3f>>& frames) const override {
        if (received_ == 0) {
            // Nothing but the header: every vertex at the centre of the bounds.
            const Vec3f centre = 0.5f * (header_.bounds.min + header_.bounds.max);
            frames.assign(header_.frames, std::vector<Vec3f>(header_.vertices, centre));
            return;
        }
        paper_reconstruct(layout_, first_frame_, quantised_, header_.step, frames);
    }

private:
    Header header_;
    std::string what_;
    PaperLayout layout_;
    IntMatrix quantised_;
    HuffmanTable table_;
    std::vector<Vec3f> first_frame_;
    std::size_t received_ = 0;
};
}  // namespace

std::unique_ptr<ProfileDecoder> make_paper_decoder(const Header& header, const std::string& what) {
    // Work policy: building the layout costs O(T) (about 8 us a frame) before any data
    // arrives, so T is capped (kMaxPaperLevel) and must be one the declared size can hold: a
    // complete stream has one packet per kCoefficientsPerPacket coefficients of the 2^J - 8
    // detail rows (plus the base packet), each at least 4 + 1 + 4 bytes of framing and one
    // byte of Huffman data.  From N and T alone, before the layout.  (Against the declared
    // size, not the bytes at hand: a short prefix of a long file still decodes.)
    const std::uint64_t bytes = header.total_bytes;
    const std::uint64_t trajectories = 3 * std::uint64_t(header.vertices);
    int level = kCoarsestLevel;
    while (level_size(level) < header.frames - 1 && level < 40) ++level;
    const std::uint64_t detail_rows = level == kCoarsestLevel ? 0 : (std::uint64_t(1) << level) - 8;
    const std::uint64_t per_packet = std::max<std::uint64_t>(1, PaperLayout::kCoefficientsPerPacket / trajectories);
    const std::uint64_t packets = 1 + (detail_rows + per_packet - 1) / per_packet;
    constexpr std::uint64_t kMinPacketBytes = 10;
    if (level > kMaxPaperLevel || packets * kMinPacketBytes > bytes)
        throw InputError(
            what + ": header: " + std::to_string(header.frames) + " frames of " + std::to_string(header.vertices) +
            " vertices need " + std::to_string(packets) + " packets (at least " +
            std::to_string(packets * kMinPacketBytes) + " bytes) in the paper profile: more than the " +
            std::to_string(bytes) + " bytes the file declares" +
            (level > kMaxPaperLevel ? " or the profile's limit of " + std::to_string(kMaxPaperFrames) + " frames"
                                    : ""));
    return std::make_unique<PaperDecoder>(header, what);
}

}  // namespace foldcast::codec
