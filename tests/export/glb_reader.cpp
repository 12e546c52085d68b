#include "glb_reader.hpp"

#include <meshoptimizer.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace foldcast::test {

namespace {
std::uint32_t u32(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}
int components(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    return 4;
}
int component_bytes(int type) { return type == 5120 || type == 5121 ? 1 : type == 5122 || type == 5123 ? 2 : 4; }
}  // namespace

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Glb parse_glb(const std::string& bytes) {
    if (bytes.size() < 28 || u32(bytes, 0) != 0x46546C67 || u32(bytes, 4) != 2 || u32(bytes, 8) != bytes.size())
        throw std::runtime_error("not a glTF 2.0 binary");
    const std::uint32_t json_length = u32(bytes, 12);
    if (u32(bytes, 16) != 0x4E4F534A || 20 + json_length + 8 > bytes.size()) throw std::runtime_error("bad JSON chunk");
    Glb glb;
    glb.json = nlohmann::json::parse(bytes.substr(20, json_length));
    const std::size_t bin_at = 20 + json_length;
    if (u32(bytes, bin_at + 4) != 0x004E4942) throw std::runtime_error("bad BIN chunk");
    glb.bin = bytes.substr(bin_at + 8, u32(bytes, bin_at));
    return glb;
}

std::string Glb::view_bytes(int index) const {
    const nlohmann::json& view = json["bufferViews"][index];
    if (view.contains("extensions") && view["extensions"].contains("EXT_meshopt_compression")) {
        const nlohmann::json& ext = view["extensions"]["EXT_meshopt_compression"];
        const std::size_t count = ext["count"], stride = ext["byteStride"];
        const std::string packed =
            bin.substr(ext["byteOffset"].get<std::size_t>(), ext["byteLength"].get<std::size_t>());
        std::string out(count * stride, '\0');
        const auto* src = reinterpret_cast<const unsigned char*>(packed.data());
        const int rc = ext["mode"] == "TRIANGLES"
                           ? meshopt_decodeIndexBuffer(out.data(), count, stride, src, packed.size())
                           : meshopt_decodeVertexBuffer(out.data(), count, stride, src, packed.size());
        if (rc != 0) throw std::runtime_error("meshopt could not decode buffer view " + std::to_string(index));
        return out;
    }
    if (view["buffer"] != 0) throw std::runtime_error("buffer view without data");
    return bin.substr(view.value("byteOffset", std::size_t(0)), view["byteLength"].get<std::size_t>());
}

std::vector<float> Glb::floats(int index) const {
    const nlohmann::json& a = json["accessors"][index];
    const int type = a["componentType"], n = components(a["type"]);
    const bool normalized = a.value("normalized", false);
    const nlohmann::json& view = json["bufferViews"][a["bufferView"].get<int>()];
    const std::string data = view_bytes(a["bufferView"]);
    const std::size_t size = component_bytes(type);
    const std::size_t stride = view.value("byteStride", n * size);
    const std::size_t count = a["count"], offset = a.value("byteOffset", std::size_t(0));
    std::vector<float> out;
    out.reserve(count * n);
    for (std::size_t i = 0; i < count; ++i)
        for (int c = 0; c < n; ++c) {
            const char* p = data.data() + offset + i * stride + c * size;
            float v = 0.0f;
            switch (type) {
                case 5120:
                    v = normalized ? std::max(*reinterpret_cast<const std::int8_t*>(p) / 127.0f, -1.0f)
                                   : *reinterpret_cast<const std::int8_t*>(p);
                    break;
                case 5121:
                    v = normalized ? *reinterpret_cast<const std::uint8_t*>(p) / 255.0f
                                   : *reinterpret_cast<const std::uint8_t*>(p);
                    break;
                case 5122: {
                    std::int16_t s;
                    std::memcpy(&s, p, 2);
                    v = normalized ? std::max(s / 32767.0f, -1.0f) : s;
                    break;
                }
                case 5123: {
                    std::uint16_t s;
                    std::memcpy(&s, p, 2);
                    v = normalized ? s / 65535.0f : s;
                    break;
                }
                case 5125: {
                    std::uint32_t s;
                    std::memcpy(&s, p, 4);
                    v = static_cast<float>(s);
                    break;
                }
                default:
                    std::memcpy(&v, p, 4);
            }
            out.push_back(v);
        }
    return out;
}

std::vector<std::uint32_t> Glb::indices(int accessor) const {
    const std::vector<float> f = floats(accessor);
    return {f.begin(), f.end()};
}

}  // namespace foldcast::test
