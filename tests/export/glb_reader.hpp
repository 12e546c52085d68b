#pragma once
// A .glb read back for tests: the JSON document, the BIN chunk, and accessors decoded to
// floats (meshoptimizer's decoders for EXT_meshopt_compression views, dequantized).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace foldcast::test {

struct Glb {
    nlohmann::json json;
    std::string bin;
    // Accessor `index` as floats, `components` per element (normalized integers mapped to
    // [-1, 1] / [0, 1], other integers as they are).
    std::vector<float> floats(int index) const;
    // The bytes of buffer view `index`, decompressed if it is.
    std::string view_bytes(int index) const;
    std::vector<std::uint32_t> indices(int accessor) const;
};

// Throws std::runtime_error on a malformed container.
Glb parse_glb(const std::string& bytes);
std::string read_file(const std::string& path);

}  // namespace foldcast::test
