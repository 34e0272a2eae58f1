// Every whole-turn copy of IK solutions inside the joint limits, nearest to a reference first.
//
// A revolute joint whose (finite) limits span more than a whole turn holds an angle and its
// copies q + 2 pi t: distinct configurations with the same tool pose (a UR5 at +-360 degrees
// has 2^6 copies of each of its 8 solutions). Joints that span at most a whole turn, or are
// unbounded (continuous), hold one copy: the one the pipeline's wrap chose, nearest to the
// reference. Header-only: used by bind_solve.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <queue>
#include <vector>

#include "armkit/chain.hpp"
#include "armkit/fk.hpp"
#include "armkit/linalg.hpp"

namespace armkit {

// Whether revolute joint j has finite limits spanning more than a whole turn.
inline bool spans_turns(const Chain& chain, int j) {
    return !chain.prismatic[j] && std::isfinite(chain.lower[j]) && std::isfinite(chain.upper[j]) &&
           chain.upper[j] - chain.lower[j] > kTwoPi + 2.0 * kLimitTolerance;
}

// The values joint j of a solution takes in its copies, with their squared weighted distances
// to reference, nearest first (q itself first among equals). q inside the limits is assumed.
inline void joint_copies(const Chain& chain, int j, double q, double reference, double weight,
                         std::vector<double>& values, std::vector<double>& distances) {
    values.clear();
    if (spans_turns(chain, j)) {
        const double low = chain.lower[j] - kLimitTolerance, high = chain.upper[j] + kLimitTolerance;
        for (double t = std::ceil((low - q) / kTwoPi); t <= std::floor((high - q) / kTwoPi); t += 1.0)
            values.push_back(t == 0.0 ? q : q + kTwoPi * t);
    }
    if (values.empty()) values.push_back(q);
    auto gap = [&](double v) { return weight * (v - reference) * weight * (v - reference); };
    std::stable_sort(values.begin(), values.end(), [&](double a, double b) {
        return gap(a) < gap(b) || (gap(a) == gap(b) && a == q && b != q);
    });
    distances.resize(values.size());
    for (std::size_t c = 0; c < values.size(); ++c) distances[c] = gap(values[c]);
}

struct TurnCopies {
    std::vector<std::int64_t> source;  // m: the row each copy is of
    std::vector<double> q;             // m x n
    std::vector<double> errors;        // m x 2: FK residual [m, rad] of each copy to the target
    double total = 0.0;                // how many copies exist (m is at most the limit)
};

// The copies of rows q (k x n), those with expand[r] every copy inside the limits (of the
// joints j with free_joint[j]; the others keep their value), the other rows as they are, nearest to near (n) first by |w * (q - near)| (ties: by row, then as found),
// at most limit of them; each FK-verified against T.
//
// Best-first over the lattice of per-joint copy indices: a state's successors raise one index
// at or after its pivot (so each combination is reached once), and a successor is never
// nearer than its state, so states leave the queue nearest first.
inline TurnCopies turn_copies(const Chain& chain, const Pose& T, const double* q, const bool* expand, int k,
                              const bool* free_joint, const double* near, const double* weights,
                              std::size_t limit) {
    const int n = chain.n;
    std::vector<std::vector<double>> values(std::size_t(k) * n), distances(std::size_t(k) * n);
    TurnCopies out;
    for (int r = 0; r < k; ++r) {
        double product = 1.0;
        for (int j = 0; j < n; ++j) {
            const std::size_t c = std::size_t(r) * n + j;
            const double v = q[c];
            if (expand[r] && free_joint[j]) {
                joint_copies(chain, j, v, near[j], weights[j], values[c], distances[c]);
            } else {
                values[c] = {v};
                distances[c] = {weights[j] * (v - near[j]) * weights[j] * (v - near[j])};
            }
            product *= double(values[c].size());
        }
        out.total += product;
    }
    struct State {
        double distance;
        int row, pivot;
        std::int64_t order;
        std::vector<std::uint32_t> index;
    };
    auto later = [](const State& a, const State& b) {
        if (a.distance != b.distance) return a.distance > b.distance;
        if (a.row != b.row) return a.row > b.row;
        return a.order > b.order;
    };
    std::priority_queue<State, std::vector<State>, decltype(later)> queue(later);
    std::int64_t pushed = 0;
    for (int r = 0; r < k; ++r) {
        State s{0.0, r, 0, pushed++, std::vector<std::uint32_t>(std::size_t(n), 0u)};
        for (int j = 0; j < n; ++j) s.distance += distances[std::size_t(r) * n + j][0];
        queue.push(std::move(s));
    }
    double copy[kMaxJoints];
    while (!queue.empty() && out.source.size() < limit) {
        const State s = queue.top();
        queue.pop();
        const std::size_t row = std::size_t(s.row) * n;
        for (int j = 0; j < n; ++j) copy[j] = values[row + j][s.index[j]];
        out.source.push_back(s.row);
        out.q.insert(out.q.end(), copy, copy + n);
        double position = 0.0, angle = 0.0;
        pose_residual(T, tool_pose(chain, copy), position, angle);
        out.errors.push_back(position);
        out.errors.push_back(angle);
        for (int j = s.pivot; j < n; ++j) {
            const std::vector<double>& d = distances[row + j];
            if (s.index[j] + 1 >= d.size()) continue;
            State next{0.0, s.row, j, pushed++, s.index};
            ++next.index[j];
            for (int i = 0; i < n; ++i) next.distance += distances[row + i][next.index[i]];
            queue.push(std::move(next));
        }
    }
    return out;
}

}  // namespace armkit
