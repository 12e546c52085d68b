#pragma once
// What the streaming decoder needs from a profile: accept data packets in order, say which
// frames are final, and reconstruct all frames from what has arrived.
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
};

std::unique_ptr<ProfileDecoder> make_paper_decoder(const Header& header, const std::string& what);
std::unique_ptr<ProfileDecoder> make_predictive_decoder(const Header& header, const std::string& what);

}  // namespace foldcast::codec
