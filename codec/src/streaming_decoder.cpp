// Incremental decoding: bytes accumulate until a whole packet is there; each complete
// packet is checked (length bound, CRC, order) and handed to the profile's decoder.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "byte_io.hpp"
#include "container.hpp"
#include "crc32.hpp"
#include "foldcast/codec/codec.hpp"
#include "preview.hpp"
#include "profile_decoder.hpp"

namespace foldcast::codec {

struct StreamingDecoder::Impl {
    std::string what;
    std::optional<std::uint64_t> known_total;
    std::string pending;       // bytes not yet consumed
    std::size_t consumed = 0;  // bytes of accepted packets (and magic)
    bool magic_ok = false;
    bool complete = false;
    std::size_t packets = 0;
    std::size_t data_packets = 0;
    Header header;
    std::unique_ptr<ProfileDecoder> profile;
    std::vector<std::vector<Vec3f>> recycled;  // frame buffers for the profile, until it exists
    std::vector<Vec3f> preview;                // the coarse first frame, until data packet 0
    std::uint64_t first_frame_bytes = 0;       // 0: not known yet

    bool has_frame() const { return data_packets > 0 || !preview.empty(); }
    // Before data packet 0 and the preview: no frame can be made (making one would put every
    // vertex at one point).
    void require_frame() const {
        require();
        if (has_frame()) return;
        fail("no frame yet: the first " + std::to_string(consumed) + " bytes hold only the header; " +
             (first_frame_bytes ? "the first frame needs " + std::to_string(first_frame_bytes) + " bytes"
                                : std::string("the first frame needs data packet 0, which has not begun")));
    }

    void require() const {
        if (!profile) fail("no complete header yet (too short to be an .fca file)");
    }
    Animation without_frames() const {
        require();
        Animation anim;
        anim.topology = header.topology;
        anim.fps = header.fps;
        return anim;
    }
    [[noreturn]] void fail(const std::string& message) const { throw InputError(what + ": " + message); }

    void handle(PacketType type, std::string_view payload) {
        const std::string where = "packet " + std::to_string(packets) + " at byte " + std::to_string(consumed);
        if (complete) fail(where + " follows the end packet");
        if (!profile) {
            if (type != PacketType::header) fail(where + " is not a header, but the file must start with one");
            header = parse_header(payload, what, known_total);
            profile = header.profile == Profile::paper ? make_paper_decoder(header, what)
                                                       : make_predictive_decoder(header, what);
            profile->reuse(std::move(recycled));
            first_frame_bytes = header.first_frame_bytes;
            return;
        }
        ByteReader r(payload, what + ": " + where);
        switch (type) {
            case PacketType::header:
                r.fail("a second header");
            case PacketType::data: {
                const auto seq = r.get<std::uint32_t>("sequence number");
                if (seq != data_packets)
                    r.fail("data packet " + std::to_string(seq) + " out of order (expected " +
                           std::to_string(data_packets) + ")");
                profile->accept(seq, r.get_bytes(r.remaining(), "data"));
                ++data_packets;
                preview = {};
                return;
            }
            case PacketType::preview:
                if (header.version < 4 || packets != 1)
                    r.fail("a preview packet must directly follow the header (format version 4 and later)");
                preview = parse_preview(payload, header, r.what() + " (preview)");
                return;
            case PacketType::end: {
                const auto count = r.get<std::uint32_t>("packet count");
                r.expect_end("end packet");
                if (count != data_packets || data_packets != profile->expected_packets())
                    r.fail("end packet after " + std::to_string(data_packets) + " data packets (expected " +
                           std::to_string(profile->expected_packets()) + ")");
                complete = true;
                return;
            }
        }
        r.fail("unknown packet type " + std::to_string(static_cast<int>(type)));
    }

    // Decodes every complete packet of `input`; `used` says how many bytes it consumed,
    // also when it throws.
    void process(std::string_view input, std::size_t& used) {
        if (!magic_ok) {
            const std::size_t n = std::min(input.size(), sizeof(kMagic));
            if (std::memcmp(input.data(), kMagic, n) != 0) fail("not an .fca file (bad magic bytes)");
            if (input.size() < sizeof(kMagic)) return;
            magic_ok = true;
            used = sizeof(kMagic);
            consumed += sizeof(kMagic);
        }
        while (input.size() - used >= 5) {
            const char* at = input.data() + used;
            std::uint32_t length;
            std::memcpy(&length, at, 4);
            const auto type = static_cast<PacketType>(static_cast<std::uint8_t>(at[4]));
            if (length > kMaxPayloadBytes)
                fail("packet " + std::to_string(packets) + " claims " + std::to_string(length) + " bytes (limit 2^30)");
            if (profile && consumed + kPacketOverhead + length > header.total_bytes)
                fail("packet " + std::to_string(packets) + " runs past the size the header declares");
            if (profile && data_packets == 0 && type == PacketType::data && !first_frame_bytes)
                first_frame_bytes = consumed + kPacketOverhead + length;
            if (input.size() - used < kPacketOverhead + length) break;  // wait for the rest
            const std::string_view typed(at + 4, 1 + length);
            std::uint32_t stored;
            std::memcpy(&stored, at + 5 + length, 4);
            if (crc32(typed) != stored)
                fail("packet " + std::to_string(packets) + " at byte " + std::to_string(consumed) +
                     " is corrupt (CRC mismatch)");
            if (type != PacketType::header && type != PacketType::data && type != PacketType::end &&
                type != PacketType::preview)
                fail("packet " + std::to_string(packets) + " has unknown type " +
                     std::to_string(static_cast<int>(type)));
            handle(type, typed.substr(1));
            ++packets;
            used += kPacketOverhead + length;
            consumed += kPacketOverhead + length;
        }
    }
};

StreamingDecoder::StreamingDecoder(std::string what, std::optional<std::uint64_t> known_total_bytes)
    : impl_(std::make_unique<Impl>()) {
    impl_->what = std::move(what);
    impl_->known_total = known_total_bytes;
}
StreamingDecoder::~StreamingDecoder() = default;
StreamingDecoder::StreamingDecoder(StreamingDecoder&&) noexcept = default;
StreamingDecoder& StreamingDecoder::operator=(StreamingDecoder&&) noexcept = default;

void StreamingDecoder::feed(std::string_view bytes) {
    // Packets are read straight from the caller's bytes when nothing is pending (a whole
    // file: no copy); only an incomplete packet, or one that failed, waits in `pending`.
    std::string& pending = impl_->pending;
    const bool from_pending = !pending.empty();
    if (from_pending) pending.append(bytes);
    const std::string_view input = from_pending ? std::string_view(pending) : bytes;
    std::size_t used = 0;
    auto keep_rest = [&] {
        if (from_pending)
            pending.erase(0, used);
        else
            pending.assign(input.substr(used));
    };
    try {
        impl_->process(input, used);
    } catch (...) {
        keep_rest();
        throw;
    }
    keep_rest();
}

void StreamingDecoder::reuse(std::vector<std::vector<Vec3f>>&& frames) {
    if (!impl_->profile)
        impl_->recycled = std::move(frames);
    else if (impl_->data_packets == 0)
        impl_->profile->reuse(std::move(frames));
}

StreamStatus StreamingDecoder::status() const {
    StreamStatus s;
    s.header_ready = impl_->profile != nullptr;
    s.complete = impl_->complete;
    s.playable_frames = impl_->profile ? impl_->profile->playable_frames() : 0;
    s.packets = impl_->packets;
    s.bytes_used = impl_->consumed;
    s.frame_ready = impl_->has_frame();
    s.preview_only = impl_->data_packets == 0 && !impl_->preview.empty();
    s.first_frame_bytes = impl_->first_frame_bytes;
    return s;
}

std::size_t StreamingDecoder::vertex_count() const {
    impl_->require();
    return impl_->header.vertices;
}
std::size_t StreamingDecoder::frame_count() const {
    impl_->require();
    return impl_->header.frames;
}
double StreamingDecoder::fps() const {
    impl_->require();
    return impl_->header.fps;
}
Profile StreamingDecoder::profile() const {
    impl_->require();
    return impl_->header.profile;
}
const Topology& StreamingDecoder::topology() const {
    impl_->require();
    return impl_->header.topology;
}
std::optional<double> StreamingDecoder::max_error_m() const {
    impl_->require();
    const Header& h = impl_->header;
    if (h.profile == Profile::paper) return std::nullopt;
    // Per coordinate: the fine grid rounds by <= step/2, the residual quantiser (step m x
    // step) by <= m step / 2 (docs/codec.md; `cascade` quantises some frames finer, never
    // coarser); Euclidean over three coordinates.
    return std::sqrt(3.0) * h.step * (h.threshold + 1.0) / 2.0;
}

const Metadata& StreamingDecoder::metadata() const {
    impl_->require();
    return impl_->header.metadata;
}

std::optional<std::string> StreamingDecoder::metadata(const std::string& key) const {
    for (const auto& [k, value] : metadata())
        if (k == key) return value;
    return std::nullopt;
}

Animation StreamingDecoder::animation() const {
    Animation anim = impl_->without_frames();
    impl_->require_frame();
    if (impl_->data_packets == 0)
        anim.frames.assign(impl_->header.frames, impl_->preview);
    else
        impl_->profile->reconstruct(anim.frames);
    return anim;
}

Animation StreamingDecoder::take_animation() {
    Animation anim = impl_->without_frames();
    impl_->require_frame();
    if (impl_->data_packets == 0)
        anim.frames.assign(impl_->header.frames, impl_->preview);
    else
        impl_->profile->release(anim.frames);
    return anim;
}

void StreamingDecoder::frame(std::size_t t, std::vector<Vec3f>& out) const {
    impl_->require();
    if (t >= impl_->header.frames)
        throw InputError(impl_->what + ": frame " + std::to_string(t) + " out of range (" +
                         std::to_string(impl_->header.frames) + " frames)");
    impl_->require_frame();
    if (impl_->data_packets == 0)
        out = impl_->preview;
    else
        impl_->profile->reconstruct_frame(t, out);
}

std::vector<Vec3f> StreamingDecoder::frame(std::size_t t) const {
    std::vector<Vec3f> out;
    frame(t, out);
    return out;
}

Animation decode(std::string_view bytes, const std::string& what) {
    Animation anim;
    decode(bytes, anim, what);
    return anim;
}

void decode(std::string_view bytes, Animation& out, const std::string& what) {
    StreamingDecoder decoder(what, bytes.size());
    decoder.reuse(std::move(out.frames));
    out = Animation{};
    decoder.feed(bytes);
    out = decoder.take_animation();
}

}  // namespace foldcast::codec
