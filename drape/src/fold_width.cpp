// The width of a fold from bending against tension (docs/drape.md, "The fold width"): a fold
// whose depth varies as cos(pi x / l) between the supports, under a tension T per unit length
// along it, costs bending B k^4 and tension T (pi/l)^2 per unit depth^2 (k = 2 pi / lambda);
// for a fixed excess length taken up by the folds (depth^2 k^2 fixed) the sum
// B k^2 + T pi^2 / (l^2 k^2) is least at k^4 = pi^2 T / (B l^2), Cerda and Mahadevan's
// lambda = 2 sqrt(pi) (B l^2 / T)^(1/4).  T is the hanging stress's tension w h, as in S.
#include <cmath>

#include "foldcast/core/math.hpp"
#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {

double bending_stiffness_nm(const ClothParams& p) {
    const double t = p.thickness_m;
    return p.young_pa * t * t * t / (12.0 * (1.0 - p.poisson * p.poisson));
}

double fold_half_width_m(const ClothParams& params) {
    const ClothParams p = bay_params(params);
    const double l = p.support_span_m();
    const double tension_n_per_m = p.weight_n_per_m2 * p.height_m;
    return std::sqrt(kPi) * std::pow(bending_stiffness_nm(p) * l * l / tension_n_per_m, 0.25);
}

}  // namespace foldcast::drape
