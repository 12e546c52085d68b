
#include "foldcast/looks/looks.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::looks {

double default_load_constant() { return 23.9 * kPi * kPi / 12.0; }

double Mechanics::weight_n_per_m2() const {
    constexpr double kStandardGravity = 9.80665;  // m/s^2
    return gsm * 1e-3 * kStandardGravity;
}

}  // namespace foldcast::looks
