// Every whole-turn copy of IK solutions inside the joint limits, nearest to a reference first.
//
// A revolute joint whose (finite) limits span more than a whole turn holds an angle and its
// copies q + 2 pi t: distinct configurations with the same tool pose (a UR5 at +-360 degrees
// has 2^6 copies of each of its 8 solutions). Joints that span at most a whole turn, or are
// unbounded (continuous), hold one copy: the one the pipeline's wrap chose, nearest to the
// reference. A copy has its solution's tool pose, so it is listed with its solution's FK
// residuals, not put through FK again. Header-only: used by bind_solve.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "armkit/chain.hpp"
#include "armkit/tolerances.hpp"
#include "armkit/vec.hpp"

namespace armkit {

// Whether revolute joint j has finite limits spanning more than a whole turn.
inline bool spans_turns(const Chain& chain, int j) {
    return !chain.prismatic[j] && std::isfinite(chain.lower[j]) && std::isfinite(chain.upper[j]) &&
           chain.upper[j] - chain.lower[j] > kTwoPi + 2.0 * kLimitTolerance;
}

// The whole turns t with q + 2 pi t inside joint j's limits: [first, last] (empty if last < first).
inline void turn_range(const Chain& chain, int j, double q, double& first, double& last) {
    const double low = chain.lower[j] - kLimitTolerance, high = chain.upper[j] + kLimitTolerance;
    first = std::ceil((low - q) / kTwoPi);
    last = std::floor((high - q) / kTwoPi);
}

// How many values joint j of a solution at q (inside the limits) takes in its copies.
inline std::size_t joint_copy_count(const Chain& chain, int j, double q) {
    if (!spans_turns(chain, j)) return 1;
    double first, last;
    turn_range(chain, j, q, first, last);
    return last >= first ? std::size_t(last - first) + 1 : 1;
}

// How many copies rows q (k x n) make: of a row with expand[r] the product over the joints with
// free_joint[j] of their copy counts, of any other row one (a double: 2^n per row can be large).
inline double count_turn_copies(const Chain& chain, const double* q, const bool* expand, int k,
                                const bool* free_joint) {
    double total = 0.0;
    for (int r = 0; r < k; ++r) {
        double product = 1.0;
        if (expand[r])
            for (int j = 0; j < chain.n; ++j)
                if (free_joint[j]) product *= double(joint_copy_count(chain, j, q[std::size_t(r) * chain.n + j]));
        total += product;
    }
    return total;
}

// Lists whole-turn copies, nearest first, with scratch space kept from one call to the next (one
// lister per thread: nothing is allocated per copy, and after the first poses nothing at all).
//
// Best-first over the lattice of per-joint copy indices: a state's successors raise one index
// at or after its pivot (so each combination is reached once), and a successor is never
// nearer than its state, so states leave the heap nearest first (ties: by row, then as found).
class TurnCopyLister {
public:
    // The copies of rows q (k x n), those with expand[r] every copy inside the limits (of the
    // joints j with free_joint[j]; the others keep their value), the other rows as they are,
    // nearest to near (n) first by |w * (q - near)|, at most limit of them: their values into
    // out_q (limit x n) and the row each is a copy of into source (limit). Returns how many.
    std::size_t list(const Chain& chain, const double* q, const bool* expand, int k, const bool* free_joint,
                     const double* near, const double* weights, std::size_t limit, double* out_q,
                     std::int64_t* source) {
        const int n = chain.n;
        const std::size_t cells = std::size_t(k) * std::size_t(n);
        start_.resize(cells + 1);
        values_.clear();
        distances_.clear();
        for (int r = 0; r < k; ++r)
            for (int j = 0; j < n; ++j) {
                const std::size_t c = std::size_t(r) * n + j;
                start_[c] = values_.size();
                joint_copies(chain, j, q[c], near[j], weights[j], expand[r] && free_joint[j]);
            }
        start_[cells] = values_.size();
        heap_.clear();
        indices_.clear();
        for (int r = 0; r < k; ++r) {
            double distance = 0.0;
            for (int j = 0; j < n; ++j) distance += distances_[start_[std::size_t(r) * n + j]];
            push(distance, r, 0, nullptr, n);
        }
        std::size_t listed = 0;
        std::uint32_t index[kMaxJoints];
        while (!heap_.empty() && listed < limit) {
            std::pop_heap(heap_.begin(), heap_.end(), later);
            const State s = heap_.back();
            heap_.pop_back();
            const std::size_t row = std::size_t(s.row) * n;
            std::copy(indices_.data() + s.order * n, indices_.data() + (s.order + 1) * n, index);
            for (int j = 0; j < n; ++j) out_q[listed * n + j] = values_[start_[row + j] + index[j]];
            source[listed++] = s.row;
            for (int j = s.pivot; j < n; ++j) {
                if (start_[row + j] + index[j] + 1 >= start_[row + j + 1]) continue;
                ++index[j];
                double distance = 0.0;
                for (int i = 0; i < n; ++i) distance += distances_[start_[row + i] + index[i]];
                push(distance, s.row, j, index, n);
                --index[j];
            }
        }
        return listed;
    }

private:
    // A state of the search: its distance, row and pivot, and when it was found (order), which
    // is also where its per-joint copy indices are kept (the n at indices_[order n]).
    struct State {
        double distance;
        int row, pivot;
        std::int64_t order;
    };

    static bool later(const State& a, const State& b) {
        if (a.distance != b.distance) return a.distance > b.distance;
        if (a.row != b.row) return a.row > b.row;
        return a.order > b.order;
    }

    // A new state with copy indices index (n of them; nullptr: all zero).
    void push(double distance, int row, int pivot, const std::uint32_t* index, int n) {
        const std::int64_t order = std::int64_t(indices_.size() / std::size_t(n));
        if (index)
            indices_.insert(indices_.end(), index, index + n);
        else
            indices_.resize(indices_.size() + std::size_t(n), 0u);
        heap_.push_back(State{distance, row, pivot, order});
        std::push_heap(heap_.begin(), heap_.end(), later);
    }

    // Appends the values joint j of a solution at q takes in its copies (q alone unless copies),
    // with their squared weighted distances to reference, nearest first (q itself first among equals).
    void joint_copies(const Chain& chain, int j, double q, double reference, double weight, bool copies) {
        const std::size_t begin = values_.size();
        if (copies && spans_turns(chain, j)) {
            double first, last;
            turn_range(chain, j, q, first, last);
            for (double t = first; t <= last; t += 1.0) values_.push_back(t == 0.0 ? q : q + kTwoPi * t);
        }
        if (values_.size() == begin) values_.push_back(q);
        auto gap = [&](double v) { return weight * (v - reference) * weight * (v - reference); };
        auto before = [&](double a, double b) { return gap(a) < gap(b) || (gap(a) == gap(b) && a == q && b != q); };
        for (std::size_t a = begin + 1; a < values_.size(); ++a) {  // a stable insertion sort: no buffer
            const double v = values_[a];
            std::size_t b = a;
            for (; b > begin && before(v, values_[b - 1]); --b) values_[b] = values_[b - 1];
            values_[b] = v;
        }
        for (std::size_t c = begin; c < values_.size(); ++c) distances_.push_back(gap(values_[c]));
    }

    std::vector<double> values_, distances_;  // per (row, joint) cell: its values, from start_[cell]
    std::vector<std::size_t> start_;          // k n + 1 offsets into values_ and distances_
    std::vector<State> heap_;
    std::vector<std::uint32_t> indices_;      // n copy indices per state found, in the order found
};

}  // namespace armkit
