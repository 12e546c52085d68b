// More supports (docs/drape.md): the cloth on `supports` equally spaced supports is
// supports - 1 bays side by side, each a two-support cloth with its share of the width and
// span that folds by the model; neighbouring bays share the support column between them.
// A support drop shears the level pattern, y -= drop * (x - x_first) / l, so the last
// support hangs `drop` lower than the first and every fold line runs support to support.
#include <string>

#include "foldcast/core/error.hpp"
#include "fold_surface.hpp"

namespace foldcast::drape::detail {

void validate_bay_grid(const ClothParams& params, GridSize grid) {
    const int bays = params.bays();
    if ((grid.nu - 1) % bays != 0) {
        const int below = 1 + (grid.nu - 1) / bays * bays;
        throw InputError("grid " + std::to_string(grid.nu) + "x" + std::to_string(grid.nv) + ": with " +
                         std::to_string(params.supports) +
                         " supports the vertices across minus one must be a "
                         "multiple of the " +
                         std::to_string(bays) +
                         " bays, so that every support is a "
                         "vertex (e.g. " +
                         std::to_string(below) + " or " + std::to_string(below + bays) + ")");
    }
}

std::vector<int> support_columns(const ClothParams& params, GridSize grid) {
    validate_bay_grid(params, grid);
    const int per_bay = (grid.nu - 1) / params.bays();
    std::vector<int> columns;
    for (int k = 0; k <= params.bays(); ++k) columns.push_back(k * per_bay);
    return columns;
}

void garment_positions(const ClothParams& params, const FoldSolution& solution, GridSize grid,
                       std::vector<Vec3f>& positions, std::vector<float>* fold_sign) {
    validate_bay_grid(params, grid);
    const int bays = params.bays();
    const ClothParams bay = bay_params(params);
    const FoldSurface surface(bay, solution);
    if (bays == 1 && params.support_drop_m == 0.0) {
        grid_positions(surface, bay, grid, positions, fold_sign);
        return;
    }
    const GridSize bay_grid{(grid.nu - 1) / bays + 1, grid.nv};
    std::vector<Vec3f> bay_positions;
    std::vector<float> bay_sign;
    grid_positions(surface, bay, bay_grid, bay_positions, fold_sign ? &bay_sign : nullptr);

    const auto nu = static_cast<std::size_t>(grid.nu);
    const auto nb = static_cast<std::size_t>(bay_grid.nu);
    positions.resize(nu * std::size_t(grid.nv));
    if (fold_sign) fold_sign->resize(positions.size());
    const double span = params.support_span_m(), bay_span = bay.support_span_m();
    const double shear = params.support_drop_m / span;
    for (std::size_t j = 0; j < std::size_t(grid.nv); ++j)
        for (int k = 0; k < bays; ++k)
            for (std::size_t i = k == 0 ? 0 : 1; i < nb; ++i) {  // the shared column once
                const Vec3f& p = bay_positions[j * nb + i];
                // Support columns hang straight below their support: x exact there.
                const bool support = i == 0 || i == nb - 1;
                const double x = support ? -0.5 * span + (k + (i == 0 ? 0 : 1)) * bay_span
                                         : -0.5 * span + (k + 0.5) * bay_span + double(p.x());
                const double y = double(p.y()) - shear * (x + 0.5 * span);
                const std::size_t out = j * nu + std::size_t(k) * (nb - 1) + i;
                positions[out] = Vec3f(float(x), float(y), p.z());
                if (fold_sign) (*fold_sign)[out] = bay_sign[j * nb + i];
            }
}

}  // namespace foldcast::drape::detail
