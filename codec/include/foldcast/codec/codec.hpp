#pragma once
// codec: the progressive wavelet animation format .fca (docs/fca-format.md, docs/codec.md).
// Compresses any fixed-topology foldcast::Animation; knows nothing about drape.
//
//   std::string bytes = codec::encode(anim, {});          // default profile
//   codec::write_fca("anim.fca", bytes);
//   Animation back = codec::decode(codec::read_fca("anim.fca"));
//
// Streaming: feed a StreamingDecoder bytes as they arrive; it reports which frames are
// final and reconstructs every frame from what it has (coarser where data is missing).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "foldcast/core/mesh.hpp"
#include "foldcast/core/progress.hpp"

namespace foldcast::codec {

enum class Profile : std::uint8_t {
    paper = 0,       // reference method: velocity + cubic B-spline wavelets + Huffman
    predictive = 1,  // the `default` profile (docs/codec.md): error-bounded hierarchical prediction
    cascade = 2,     // `default` with the frames others predict from quantised finer
};
std::string profile_name(Profile p);             // "paper" / "default" / "cascade"
Profile parse_profile(const std::string& name);  // throws InputError

// Key-value pairs stored in the header (format version 4), in order: e.g. {"look", "denim"}
// for the look an animation was draped with.  Keys 1..64 characters [a-z0-9_], values at
// most 1,024 bytes without control characters (the encoder throws InputError otherwise).
using Metadata = std::vector<std::pair<std::string, std::string>>;

struct EncodeOptions {
    Profile profile = Profile::predictive;
    // Largest allowed per-vertex position error in metres (Euclidean).  The default profile
    // guarantees it; paper searches its threshold until the measured max error meets it.
    std::optional<double> max_error_m;
    // paper only: fraction (0, 1] of wavelet coefficients kept (the threshold eps is the
    // matching quantile of |c|).  Mutually exclusive with max_error_m.
    std::optional<double> keep_fraction;
    Metadata metadata;
};

// Default error bound when neither max_error_m nor keep_fraction is given, as a fraction
// of the animation's bounding-box diagonal.
constexpr double kDefaultMaxErrorRel = 2e-4;

// Throws InputError for an invalid animation or options.
std::string encode(const Animation& anim, const EncodeOptions& options, const ProgressFn& progress = {});

// Whole-buffer decode.  A truncated buffer (a prefix of a valid file) decodes to the best
// animation it allows; corrupted or hostile bytes throw InputError naming `what`.
Animation decode(std::string_view bytes, const std::string& what = "fca data");
// The same into `out`, overwriting its frame buffers where they have the size instead of
// allocating new ones (a player or converter decoding clip after clip).  On InputError,
// `out` is left empty.
void decode(std::string_view bytes, Animation& out, const std::string& what = "fca data");

struct StreamStatus {
    bool header_ready = false;
    bool complete = false;            // the end packet arrived: every frame is final
    std::size_t playable_frames = 0;  // frames [0, playable_frames) are final
    std::size_t packets = 0;          // packets accepted so far
    std::size_t bytes_used = 0;       // bytes of accepted packets (a partial packet waits)
    // A frame can be made: data packet 0 arrived, or (version 4) the coarse preview of frame
    // 0, which every frame shows until data packet 0 arrives (preview_only).
    bool frame_ready = false;
    bool preview_only = false;
    // Bytes from the file's start that make frame 0 final (up to the end of data packet 0):
    // from the header (version 4), or once data packet 0's length has arrived; 0 unknown.
    std::uint64_t first_frame_bytes = 0;
};

class StreamingDecoder {
public:
    // `known_total_bytes`: the size of the whole input when known (a file); it bounds
    // allocations together with the size the header declares (docs/fca-format.md).
    explicit StreamingDecoder(std::string what = "fca stream", std::optional<std::uint64_t> known_total_bytes = {});
    ~StreamingDecoder();
    StreamingDecoder(StreamingDecoder&&) noexcept;
    StreamingDecoder& operator=(StreamingDecoder&&) noexcept;

    // Appends bytes and decodes every packet that is now complete.  Throws InputError on
    // corrupt data; after a throw the decoder keeps what it had accepted before.
    void feed(std::string_view bytes);
    // Frame buffers to decode into (those of an earlier animation), given before the first
    // data packet: frames of the right size are overwritten instead of allocated.  Ignored
    // once data has been decoded.
    void reuse(std::vector<std::vector<Vec3f>>&& frames);
    StreamStatus status() const;

    // Valid once status().header_ready.
    std::size_t vertex_count() const;
    std::size_t frame_count() const;
    double fps() const;
    Profile profile() const;
    const Topology& topology() const;
    // Largest per-vertex position error (metres, Euclidean) of a final frame, from the
    // header: the default profile's quantiser guarantees it; `paper` states none (nullopt).
    std::optional<double> max_error_m() const;
    // The header's metadata (version 4; empty for older files) and one value by key.
    const Metadata& metadata() const;
    std::optional<std::string> metadata(const std::string& key) const;

    // Best reconstruction of one frame / all frames from the packets accepted so far.
    // Throws InputError before any frame can be made (!status().frame_ready), naming the
    // bytes the first frame needs.
    std::vector<Vec3f> frame(std::size_t t) const;
    // The same into a caller's buffer: no allocation once it has the size (playback).
    void frame(std::size_t t, std::vector<Vec3f>& out) const;
    Animation animation() const;
    // animation(), handing the decoded frames over where the profile can instead of copying
    // them; the decoder holds no frames afterwards.
    Animation take_animation();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

struct Metrics {
    std::size_t frames = 0, vertices = 0, bytes = 0;
    double bpvf = 0.0;           // bits per vertex per frame
    double rms_error_rel = 0.0;  // RMS vertex error / bounding-box diagonal
    double max_error_rel = 0.0;  // max vertex error / bounding-box diagonal
    double max_error_m = 0.0;
    double kg_error = 0.0;  // Karni-Gotsman, percent
};
// Throws InputError if the animations differ in shape.
Metrics measure(const Animation& original, const Animation& decoded, std::size_t bytes);

// .fca files: read (size-checked) and written atomically.
std::string read_fca(const std::filesystem::path& path);
void write_fca(const std::filesystem::path& path, std::string_view bytes);

}  // namespace foldcast::codec
