// Fold lines y_i(x) = a_i cos(pi x / l), z_i(x) = s_i zmax cos(pi x / l), s_i = (-1)^i:
// the lowest (i = 0) bulges towards the viewer and the signs alternate upwards; repeated
// over the bays and sheared by the support drop.
#include <cmath>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::drape {

std::vector<FoldLine> fold_lines(const ClothParams& params, const FoldSolution& solution, int samples) {
    if (samples < 2) throw InputError("fold line samples = " + std::to_string(samples) + ": must be >= 2");
    validate(params);
    const double span = params.support_span_m();
    const double l = bay_params(params).support_span_m();
    const double shear = params.support_drop_m / span;  // the drop shears the level pattern
    std::vector<FoldLine> lines;
    if (solution.folds <= 0) return lines;
    for (int bay = 0; bay < params.bays(); ++bay)
        for (int i = 0; i <= solution.folds; ++i) {
            FoldLine line;
            line.index = i;
            line.sign = i % 2 == 0 ? 1 : -1;
            line.bay = bay;
            const double a = solution.amplitudes_m.at(std::size_t(i));
            line.points.reserve(std::size_t(samples));
            for (int k = 0; k < samples; ++k) {
                const double x = -0.5 * l + l * k / (samples - 1);
                const double c = (k == 0 || k == samples - 1) ? 0.0 : std::cos(kPi * x / l);
                const double x_cloth = -0.5 * span + (bay + 0.5) * l + x;
                line.points.emplace_back(x_cloth, -a * c - shear * (x_cloth + 0.5 * span),
                                         line.sign * solution.zmax_m * c);
            }
            lines.push_back(std::move(line));
        }
    return lines;
}

}  // namespace foldcast::drape
