// Cloth parameters: conversion from a look's mechanics and validation.
#include <cmath>
#include <sstream>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {

ClothParams cloth_from_look(const looks::Mechanics& mechanics, double width_m, double height_m, double inset_m) {
    ClothParams p;
    p.width_m = width_m;
    p.height_m = height_m;
    p.inset_m = inset_m;
    p.thickness_m = mechanics.thickness_mm * 1e-3;
    p.young_pa = mechanics.young_mpa * 1e6;
    p.poisson = mechanics.poisson;
    p.weight_n_per_m2 = mechanics.weight_n_per_m2();
    p.load_constant = mechanics.load_constant;
    return p;
}

namespace {
constexpr int kMaxSupports = 65;  // 64 bays: beyond any rail a garment grid resolves
std::string number(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}
void require_positive(const char* name, double v) {
    if (!std::isfinite(v) || v <= 0.0)
        throw InputError(std::string(name) + " = " + number(v) + ": must be a finite number > 0");
}
}  // namespace

void validate(const ClothParams& p) {
    require_positive("width_m", p.width_m);
    require_positive("height_m", p.height_m);
    require_positive("thickness_m", p.thickness_m);
    require_positive("young_pa", p.young_pa);
    require_positive("weight_n_per_m2", p.weight_n_per_m2);
    require_positive("load_constant", p.load_constant);
    if (!std::isfinite(p.inset_m) || p.inset_m < 0.0 || p.inset_m >= 0.5 * p.width_m)
        throw InputError("inset_m = " + number(p.inset_m) +
                         ": must be >= 0 and < width/2 = " + number(0.5 * p.width_m));
    if (!std::isfinite(p.poisson) || p.poisson < 0.0 || p.poisson >= 0.5)
        throw InputError("poisson = " + number(p.poisson) + ": must be >= 0 and < 0.5");
    if (p.supports < 2 || p.supports > kMaxSupports)
        throw InputError("supports = " + std::to_string(p.supports) + ": must be 2.." + std::to_string(kMaxSupports));
    if (!std::isfinite(p.support_drop_m) || std::abs(p.support_drop_m) > p.support_span_m())
        throw InputError("support_drop_m = " + number(p.support_drop_m) +
                         ": must be a finite number with |drop| <= the support span " + number(p.support_span_m()) +
                         " m");
}

ClothParams bay_params(const ClothParams& p) {
    ClothParams bay = p;
    bay.width_m = p.width_m / p.bays();
    bay.inset_m = p.inset_m / p.bays();
    bay.supports = 2;
    bay.support_drop_m = 0.0;
    return bay;
}

double critical_stress_pa(const ClothParams& params) {
    const ClothParams p = bay_params(params);
    const double l = p.support_span_m();
    return p.load_constant * p.young_pa * p.thickness_m * p.thickness_m / (l * l * (1.0 - p.poisson * p.poisson));
}

double stress_ratio(const ClothParams& p) {
    return critical_stress_pa(p) * p.thickness_m / (p.weight_n_per_m2 * p.height_m);
}

double amplitude_ratio(double s) {
    if (!(s < 1.0)) return 0.0;
    if (s <= 0.0) return 1.0;
    // Larger root of (1-S) Q^2 - (2+S) Q + 1 = 0; its discriminant is S^2 + 8S.
    return ((2.0 + s) + std::sqrt(s * s + 8.0 * s)) / (2.0 * (1.0 - s));
}

}  // namespace foldcast::drape
