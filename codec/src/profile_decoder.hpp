#pragma once
// What the streaming decoder needs from a profile: accept data packets in order, say which
// frames are final, and reconstruct frames from what has arrived.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "container.hpp"

namespace foldcast::codec {

class ProfileDecoder {
public:
    virtual ~ProfileDecoder() = default;
    // Data packet number `sequence` (0, 1, ...).  Throws InputError on malformed payloads.
    virtual void accept(std::size_t sequence, std::string_view payload) = 0;
    virtual std::size_t expected_packets() const = 0;
    virtual std::size_t playable_frames() const = 0;
    // frames is resized to T frames of N vertices.
    virtual void reconstruct(std::vector<std::vector<Vec3f>>& frames) const = 0;
    // Buffers of an earlier animation to decode into, given before the first data packet:
    // profiles that can overwrite frames of the right size instead of allocating them.
    virtual void reuse(std::vector<std::vector<Vec3f>>&& frames) { frames.clear(); }
    // reconstruct(), but a profile may hand over its own frames instead of copying them,
    // after which it is empty.
    virtual void release(std::vector<std::vector<Vec3f>>& frames) { reconstruct(frames); }
    // Frame t alone, the same values as reconstruct() gives it; profiles that can, do it
    // without reconstructing the others.
    virtual void reconstruct_frame(std::size_t t, std::vector<Vec3f>& out) const {
        std::vector<std::vector<Vec3f>> frames;
        reconstruct(frames);
        out = std::move(frames[t]);
    }
};

std::unique_ptr<ProfileDecoder> make_paper_decoder(const Header& header, const std::string& what);
std::unique_ptr<ProfileDecoder> make_predictive_decoder(const Header& header, const std::string& what);

}  // namespace foldcast::codec
