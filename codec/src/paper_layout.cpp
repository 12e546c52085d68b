#include "paper_layout.hpp"

#include <algorithm>

namespace foldcast::codec {

PaperLayout::PaperLayout(std::size_t n, std::size_t t) : vertices(n), frames(t), trajectories(3 * n) {
    level = kCoarsestLevel;
    while (level_size(level) < t - 1) ++level;
    wavelet = std::make_shared<const CubicBSplineWavelet>(level);

    // Depth-first over the trees rooted at level j0 + 1: node (j, i) has children (j+1, 2i)
    // and (j+1, 2i+1); its coefficient row is 2^(j-1) + 3 + i.
    struct Node {
        int j;
        std::size_t i;
    };
    std::vector<Node> stack;
    for (std::size_t root = std::size_t(1) << kCoarsestLevel; root-- > 0;) stack.push_back({kCoarsestLevel + 1, root});
    while (!stack.empty()) {
        const Node node = stack.back();
        stack.pop_back();
        node_rows.push_back((std::size_t(1) << (node.j - 1)) + 3 + node.i);
        if (node.j < level) {
            stack.push_back({node.j + 1, 2 * node.i + 1});
            stack.push_back({node.j + 1, 2 * node.i});
        }
    }
    if (level == kCoarsestLevel) node_rows.clear();

    const std::size_t per_packet = std::max<std::size_t>(1, kCoefficientsPerPacket / trajectories);
    for (std::size_t first = 0; first < node_rows.size(); first += per_packet) {
        packet_first.push_back(first);
        packet_count.push_back(std::min(per_packet, node_rows.size() - first));
    }

    // Frame t needs velocity samples 0..t-1: every coefficient whose support starts at or
    // before t-1.  With k nodes in hand, the earliest missing support start bounds it.
    playable_after.assign(node_rows.size() + 1, frames);
    std::size_t earliest_missing = frames;  // sample index
    for (std::size_t k = node_rows.size(); k-- > 0;) {
        playable_after[k + 1] = std::min(frames, earliest_missing + 1);
        earliest_missing = std::min(earliest_missing, wavelet->support(node_rows[k]).first);
    }
    playable_after[0] = std::min(frames, earliest_missing + 1);
}

}  // namespace foldcast::codec
