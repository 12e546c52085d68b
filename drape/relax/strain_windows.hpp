#pragma once
// Strain limiting in windows (docs/drape.md, "Relaxation"): the few warp and weft edges
// still beyond the stretch bound once the rest of the grid is within it are brought back by
// projecting every edge in a small window around them into a band inside the bound (or to
// its rest length), Gauss-Seidel, the window's rim and the pins held (Provot 1995's
// deformation constraints, applied locally).  An edge already within the band stays as it
// is: projecting the whole window to the rest lengths asked its rim for slack it did not
// have where a long run of edges is stretched (the top row between the supports).
// Why: the global iterations take such a local spike down by only a few per cent each (a
// warm-started animation frame spent half its iterations there), while a window of a few
// hundred edges settles in a few sweeps.
//
// Sequential in row-major order, so the result does not depend on the thread count.
#include <vector>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape::detail {

struct StrainWindows {
    GridSize grid;
    double rest_u = 0.0, rest_v = 0.0;             // edge rest lengths along a row and down a column
    const std::vector<char>* is_pinned = nullptr;  // per vertex: held where it is

    // Per-vertex work arrays, kept by the caller between calls (allocating and clearing them
    // for every call was a fifth of the call at 256x256).
    struct Scratch {
        std::vector<char> movable;   // in this round's windows and not pinned
        std::vector<int> window_of;  // the connected window of each movable vertex, else -1
    };

    // Moves the vertices near every edge whose |length / rest - 1| exceeds `bound` (x, y, z:
    // one array per coordinate, grid vertex order) until none does or the rounds run out:
    // each window's edges beyond `settle` (0 <= settle <= bound) are projected to the
    // nearest length within it (settle 0: to their rest lengths).  Returns whether every
    // edge ended within `bound`.
    template <typename T>
    bool limit(T* x, T* y, T* z, double bound, double settle, Scratch& scratch) const;
};

}  // namespace foldcast::drape::detail
