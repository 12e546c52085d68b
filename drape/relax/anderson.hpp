#pragma once
// Anderson acceleration of a fixed-point map x -> G(x) (Peng et al. 2018, "Anderson
// acceleration for geometry optimization and physics simulation"): from the last few steps'
// differences, the combination of the recent G values whose residual G(x) - x is least.
// The relaxation (relax.cpp) runs it on its local/global map.
//
// The vectors are long (three coordinates of every free vertex) and the work is a few passes
// over memory per step, so every pass runs over TBB in fixed chunks, its dot products summed
// per chunk and then in chunk order: the result does not depend on the thread count.  The
// history is a ring of preallocated slots with the dot products of its differences kept beside
// it (one new row per step instead of the whole normal matrix), read oldest first.  A step is
// two sweeps over memory: the residual, the new differences and their dot products in one (each
// array read once), the accelerated point in the other, both a SIMD packet at a time.
//
// T: the vectors' type.  In double, the dot products are summed in the order Eigen's dot()
// uses (the bits are dot()'s).  In float (the history alone is 10 vectors) the step moves half
// the memory: the products are float's, summed in float over short blocks and those sums in
// double (anderson.cpp), so the small least-squares system's entries do not lose precision
// with the vectors' length; the system and its solve are double either way.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace foldcast::drape::detail {

template <typename T>
class Anderson {
public:
    static constexpr int kHistory = 5;

    explicit Anderson(Eigen::Index size);
    Eigen::Index size() const { return size_; }

    // A new fixed point problem: no history, no previous step.
    void restart() { stored_ = 0, steps_ = 0; }
    // The same problem but a changed map (or a rejected step): no history; the next step's
    // differences are taken against the last one.
    void forget() { stored_ = 0; }

    // Where the caller writes g = G(current) before step(); size() values.
    T* g() { return g_.data(); }
    // One step from current and g.  Writes the accelerated point to next and returns true, or
    // returns false (next untouched) when there is no history yet or the combination is not
    // finite: the caller then takes last_g().  current and next: size() values each.
    bool step(const T* current, T* next);
    // The g of the last step (valid until the next g() is written).
    const T* last_g() const { return g_prev_.data(); }

private:
    using Slots = std::array<std::vector<T>, kHistory>;
    std::size_t slot_of(int a) const { return std::size_t((oldest_ + a) % kHistory); }  // a-th oldest

    Eigen::Index size_;
    int stored_ = 0, oldest_ = 0, steps_ = 0;
    std::vector<T> f_, g_prev_, f_prev_, g_;               // residual G(x) - x, G and residual before, G now
    Slots dg_, df_;                                        // differences of G and of the residual
    std::vector<double> partial_;                          // per chunk: df_new . df_a, then df_a . f
    Eigen::Matrix<double, kHistory, kHistory> slot_dots_;  // df[s] . df[t] by slot
};

}  // namespace foldcast::drape::detail
