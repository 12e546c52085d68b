#pragma once
// The container side of a .glb: one binary buffer (the GLB's BIN chunk) that buffer views
// are appended to, 4-byte aligned, optionally through meshoptimizer's codecs
// (EXT_meshopt_compression: the compressed bytes in the BIN chunk, the view itself in a
// fallback buffer that holds no data), and the JSON document around it.
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace foldcast::gltf {

constexpr int kArrayBuffer = 34962;         // bufferView.target of vertex attributes
constexpr int kElementArrayBuffer = 34963;  // ... of indices
constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125,
              kFloat = 5126;

class GlbBuilder {
public:
    GlbBuilder();
    nlohmann::json& document() { return document_; }

    // A buffer view of `bytes` as they are; `stride` 0 = tightly packed (no byteStride).
    int add_view(std::string_view bytes, int target, int stride = 0);
    // A vertex stream of `count` elements of `stride` bytes (a multiple of 4, <= 256) or a
    // triangle list of 16- or 32-bit indices (`indices` true, stride 2 or 4), compressed.
    int add_compressed_view(std::string_view bytes, std::size_t count, int stride, int target, bool indices);
    // Appends to "accessors" (or any other top-level array) and returns the index.
    int add(const char* array, nlohmann::json object);
    // Marks an extension used (and required when `required`).
    void use_extension(const std::string& name, bool required);

    // The finished file: header, JSON chunk, BIN chunk.
    std::string finish();

private:
    std::size_t append(std::string& buffer, std::string_view bytes);
    nlohmann::json document_;
    std::string bin_;
    std::size_t fallback_bytes_ = 0;
};

}  // namespace foldcast::gltf
