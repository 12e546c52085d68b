#include "huffman.hpp"

#include <algorithm>
#include <queue>
#include <stdexcept>

namespace foldcast::codec {

namespace {
// Plain Huffman code lengths from counts (zero counts get length 0).
std::vector<std::uint8_t> huffman_lengths(const std::vector<std::uint64_t>& counts) {
    struct Node {
        std::uint64_t weight;
        int left, right;
    };
    std::vector<Node> nodes;
    using Item = std::pair<std::uint64_t, int>;  // weight, node; ties broken by node index
    std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
    for (std::size_t s = 0; s < counts.size(); ++s)
        if (counts[s] > 0) {
            nodes.push_back({counts[s], -1, static_cast<int>(s)});
            heap.push({counts[s], static_cast<int>(nodes.size() - 1)});
        }
    std::vector<std::uint8_t> lengths(counts.size(), 0);
    if (nodes.size() == 1) {
        lengths[static_cast<std::size_t>(nodes[0].right)] = 1;
        return lengths;
    }
    while (heap.size() > 1) {
        const auto a = heap.top();
        heap.pop();
        const auto b = heap.top();
        heap.pop();
        nodes.push_back({a.first + b.first, a.second, b.second});
        heap.push({a.first + b.first, static_cast<int>(nodes.size() - 1)});
    }
    // Depth-first walk from the root assigning depths to leaves.
    std::vector<std::pair<int, int>> stack{{heap.top().second, 0}};
    while (!stack.empty()) {
        const auto [node, depth] = stack.back();
        stack.pop_back();
        if (nodes[static_cast<std::size_t>(node)].left < 0) {
            lengths[static_cast<std::size_t>(nodes[static_cast<std::size_t>(node)].right)] =
                static_cast<std::uint8_t>(std::min(depth, 255));
        } else {
            stack.push_back({nodes[static_cast<std::size_t>(node)].left, depth + 1});
            stack.push_back({nodes[static_cast<std::size_t>(node)].right, depth + 1});
        }
    }
    return lengths;
}
}  // namespace

HuffmanTable HuffmanTable::from_counts(const std::vector<std::uint64_t>& counts, int max_length) {
    std::vector<std::uint64_t> c = counts;
    if (std::all_of(c.begin(), c.end(), [](std::uint64_t v) { return v == 0; }))
        throw std::logic_error("Huffman table from no symbols");
    HuffmanTable table;
    for (;;) {
        table.lengths_ = huffman_lengths(c);
        if (*std::max_element(table.lengths_.begin(), table.lengths_.end()) <= max_length) break;
        // Too deep: flatten the distribution (keeps every used symbol) and rebuild.
        for (auto& v : c)
            if (v > 0) v = std::max<std::uint64_t>(1, v / 2);
    }
    table.build_canonical();
    return table;
}

void HuffmanTable::write(ByteWriter& out) const {
    std::uint64_t used = 0;
    for (auto l : lengths_) used += l > 0;
    out.put_varint(used);
    for (std::size_t s = 0; s < lengths_.size(); ++s)
        if (lengths_[s] > 0) {
            out.put_varint(s);
            out.put<std::uint8_t>(lengths_[s]);
        }
}

HuffmanTable HuffmanTable::read(ByteReader& in, std::size_t alphabet_size) {
    HuffmanTable table;
    table.lengths_.assign(alphabet_size, 0);
    const std::uint64_t used = in.get_varint("Huffman symbol count");
    if (used == 0 || used > alphabet_size)
        in.fail("Huffman table lists " + std::to_string(used) + " symbols (allowed 1.." +
                std::to_string(alphabet_size) + ")");
    double kraft = 0.0;
    for (std::uint64_t i = 0; i < used; ++i) {
        const std::uint64_t symbol = in.get_varint("Huffman symbol");
        const auto length = in.get<std::uint8_t>("Huffman code length");
        if (symbol >= alphabet_size || table.lengths_[symbol] != 0)
            in.fail("Huffman table has symbol " + std::to_string(symbol) + " out of range or twice");
        if (length == 0 || length > kMaxHuffmanLength)
            in.fail("Huffman code length " + std::to_string(length) + " (allowed 1.." +
                    std::to_string(kMaxHuffmanLength) + ")");
        table.lengths_[symbol] = length;
        kraft += 1.0 / double(1u << length);
    }
    if (kraft > 1.0) in.fail("Huffman table is over-subscribed (Kraft sum > 1)");
    table.build_canonical();
    return table;
}

void HuffmanTable::build_canonical() {
    const int max_len = kMaxHuffmanLength;
    count_.assign(max_len + 1, 0);
    for (auto l : lengths_)
        if (l > 0) ++count_[l];
    first_code_.assign(max_len + 2, 0);
    first_index_.assign(max_len + 2, 0);
    std::uint32_t code = 0, index = 0;
    for (int len = 1; len <= max_len; ++len) {
        first_code_[len] = code;
        first_index_[len] = index;
        code = (code + count_[len]) << 1;
        index += count_[len];
    }
    sorted_symbols_.clear();
    for (int len = 1; len <= max_len; ++len)
        for (std::size_t s = 0; s < lengths_.size(); ++s)
            if (lengths_[s] == len) sorted_symbols_.push_back(static_cast<std::uint32_t>(s));
    codes_.assign(lengths_.size(), 0);
    std::vector<std::uint32_t> next = first_code_;
    for (std::uint32_t s : sorted_symbols_) codes_[s] = next[lengths_[s]]++;
}

void HuffmanTable::encode(BitWriter& out, std::uint32_t symbol) const {
    if (symbol >= lengths_.size() || lengths_[symbol] == 0) throw std::logic_error("Huffman symbol without a code");
    out.put(codes_[symbol], lengths_[symbol]);
}

std::uint32_t HuffmanTable::decode(BitReader& in, const ByteReader& in_what) const {
    std::uint32_t code = 0;
    for (int len = 1; len <= kMaxHuffmanLength; ++len) {
        code = (code << 1) | in.get(1);
        const std::uint32_t offset = code - first_code_[len];
        if (code >= first_code_[len] && offset < count_[len]) return sorted_symbols_[first_index_[len] + offset];
        if (in.overrun()) break;
    }
    in_what.fail("Huffman data is corrupt or truncated (no code matches)");
}

}  // namespace foldcast::codec
