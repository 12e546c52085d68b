// Fold lines y_i(x) = a_i cos(pi x / l), z_i(x) = s_i zmax cos(pi x / l), s_i = (-1)^i:
// the lowest (i = 0) bulges towards the viewer and the signs alternate upwards.
#include <cmath>

#include "foldcast/core/error.hpp"
#include "foldcast/drape.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::drape {

std::vector<FoldLine> fold_lines(const ClothParams& params, const FoldSolution& solution,
                                 int samples) {
    if (samples < 2) throw InputError("fold line samples = " + std::to_string(samples) + ": must be >= 2");
    const double l = params.support_span_m();
    std::vector<FoldLine> lines;
    if (solution.folds <= 0) return lines;
    for (int i = 0; i <= solution.folds; ++i) {
        FoldLine line;
        line.index = i;
        line.sign = i % 2 == 0 ? 1 : -1;
        const double a = solution.amplitudes_m.at(std::size_t(i));
        line.points.reserve(std::size_t(samples));
        for (int k = 0; k < samples; ++k) {
            const double x = -0.5 * l + l * k / (samples - 1);
            const double c = (k == 0 || k == samples - 1) ? 0.0 : std::cos(kPi * x / l);
            line.points.emplace_back(x, -a * c, line.sign * solution.zmax_m * c);
        }
        lines.push_back(std::move(line));
    }
    return lines;
}

}  // namespace foldcast::drape
