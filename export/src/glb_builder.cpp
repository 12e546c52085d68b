#include "glb_builder.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace foldcast::gltf {

namespace {
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;
constexpr std::uint32_t kBinChunk = 0x004E4942;

void put_u32(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
}  // namespace

GlbBuilder::GlbBuilder() { document_ = {{"asset", {{"version", "2.0"}, {"generator", "foldcast"}}}}; }

std::size_t GlbBuilder::append(std::string& buffer, std::string_view bytes) {
    buffer.resize((buffer.size() + 3) & ~std::size_t(3), '\0');
    const std::size_t offset = buffer.size();
    buffer.append(bytes);
    return offset;
}

int GlbBuilder::add_view(std::string_view bytes, int target, int stride) {
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", append(bin_, bytes)}, {"byteLength", bytes.size()}};
    if (target) view["target"] = target;
    if (stride) view["byteStride"] = stride;
    return add("bufferViews", std::move(view));
}

int GlbBuilder::add_compressed_view(std::string_view bytes, std::size_t count, int stride, int target, bool indices) {
    if (bytes.size() != count * static_cast<std::size_t>(stride))
        throw std::logic_error("compressed buffer view: size is not count x stride");
    std::vector<unsigned char> encoded;
    if (indices) {
        // The extension's TRIANGLES mode decodes index codec version 1.
        meshopt_encodeIndexVersion(1);
        std::vector<unsigned int> wide(count);
        for (std::size_t i = 0; i < count; ++i) {
            std::uint16_t narrow = 0;
            if (stride == 2)
                std::memcpy(&narrow, bytes.data() + 2 * i, 2), wide[i] = narrow;
            else
                std::memcpy(&wide[i], bytes.data() + 4 * i, 4);
        }
        const std::size_t vertices = count ? *std::max_element(wide.begin(), wide.end()) + 1 : 0;
        encoded.resize(meshopt_encodeIndexBufferBound(count, vertices));
        encoded.resize(meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), wide.data(), count));
    } else {
        meshopt_encodeVertexVersion(0);  // the extension's ATTRIBUTES mode is version 0
        encoded.resize(meshopt_encodeVertexBufferBound(count, static_cast<std::size_t>(stride)));
        encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), bytes.data(), count,
                                                  static_cast<std::size_t>(stride)));
    }
    if (encoded.empty()) throw std::logic_error("meshoptimizer could not encode a buffer view");
    const std::size_t offset = append(bin_, {reinterpret_cast<const char*>(encoded.data()), encoded.size()});
    fallback_bytes_ = (fallback_bytes_ + 3) & ~std::size_t(3);
    nlohmann::json view = {{"buffer", 1},
                           {"byteOffset", fallback_bytes_},
                           {"byteLength", bytes.size()},
                           {"extensions",
                            {{"EXT_meshopt_compression",
                              {{"buffer", 0},
                               {"byteOffset", offset},
                               {"byteLength", encoded.size()},
                               {"byteStride", stride},
                               {"count", count},
                               {"mode", indices ? "TRIANGLES" : "ATTRIBUTES"}}}}}};
    if (!indices && target) view["byteStride"] = stride;
    if (target) view["target"] = target;
    fallback_bytes_ += bytes.size();
    use_extension("EXT_meshopt_compression", true);
    return add("bufferViews", std::move(view));
}

int GlbBuilder::add(const char* array, nlohmann::json object) {
    nlohmann::json& list = document_[array];
    if (list.is_null()) list = nlohmann::json::array();
    list.push_back(std::move(object));
    return static_cast<int>(list.size()) - 1;
}

void GlbBuilder::use_extension(const std::string& name, bool required) {
    const auto add_to = [&](const char* key) {
        nlohmann::json& list = document_[key];
        if (list.is_null()) list = nlohmann::json::array();
        if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
    };
    add_to("extensionsUsed");
    if (required) add_to("extensionsRequired");
}

std::string GlbBuilder::finish() {
    bin_.resize((bin_.size() + 3) & ~std::size_t(3), '\0');
    nlohmann::json buffers = nlohmann::json::array({{{"byteLength", bin_.size()}}});
    if (fallback_bytes_)
        buffers.push_back(
            {{"byteLength", fallback_bytes_}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    document_["buffers"] = buffers;
    std::string json = document_.dump();
    json.resize((json.size() + 3) & ~std::size_t(3), ' ');

    std::string out;
    out.reserve(12 + 8 + json.size() + 8 + bin_.size());
    put_u32(out, kGlbMagic);
    put_u32(out, 2);
    put_u32(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin_.size()));
    put_u32(out, static_cast<std::uint32_t>(json.size()));
    put_u32(out, kJsonChunk);
    out += json;
    put_u32(out, static_cast<std::uint32_t>(bin_.size()));
    put_u32(out, kBinChunk);
    out += bin_;
    return out;
}

}  // namespace foldcast::gltf
