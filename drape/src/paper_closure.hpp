#pragma once
// The original paper's closure (docs/drape.md, "The paper's closure"), kept so that a reader
// can reproduce the published tables.
#include "foldcast/drape/drape.hpp"

namespace foldcast::drape::detail {

// Solves one bay (two supports, level) that buckles (S < 1) and has slack (inset > 0).
// `s` arrives with stress_ratio, critical_Q and slack_amplitude_m set; the rest is filled in.
FoldSolution solve_paper_closure(const ClothParams& bay, FoldSolution s);

// Composite Simpson's rule for the length of (x, A cos(pi x / l)) over [-l/2, l/2], as the
// paper measures the top edge.
double top_edge_length_simpson_m(double span_m, double amplitude_m, int intervals);

}  // namespace foldcast::drape::detail
