#include "mean_shift.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace symmetry {

namespace {

// One ascent from a starting point, recorded step by step so that it can be replayed
// against modes it did not know of when it climbed (see mean_shift()).
struct Ascent {
    int start = -1;
    std::vector<Eigen::VectorXd> after;      // the estimate after each step
    std::vector<std::vector<int>> covered;   // per step: the points within h/2 of the estimate before it
    bool joined = false;                     // stopped within h/2 of one of the modes it knew
    bool converged = false;                  // stopped because its last step was too small
    int height = 0;                          // points within h of the last estimate (unless joined)
};

// Whether y lies within `radius` of one of the first `count` modes (see
// MeanShiftOptions::join_radius): the ascent stops there.
bool near_mode(const std::vector<Eigen::VectorXd>& modes, size_t count, const Eigen::VectorXd& y, double radius) {
    for (size_t k = 0; k < count; ++k)
        if ((modes[k] - y).squaredNorm() < radius * radius) return true;
    return false;
}

// The mean-shift ascent from `start` that knows the first `known` modes.  For the
// Epanechnikov kernel the step is the plain mean of the points within h (its shadow is
// the flat kernel, Comaniciu and Meer 2002), so every step is one range query.
Ascent climb(const KdTree& tree, int start, const std::vector<Eigen::VectorXd>& modes, size_t known,
             const MeanShiftOptions& options) {
    const KdTree::Points& points = tree.points();
    const double h = options.bandwidth;
    Ascent a;
    a.start = start;
    Eigen::VectorXd x = points.row(start).transpose(), mean(tree.dimension());
    for (int it = 0; it < options.max_iterations; ++it) {
        const std::vector<int> neighbours = tree.radius_search(x.data(), h, false);
        if (neighbours.empty()) break;
        mean.setZero();
        std::vector<int> close;
        for (int j : neighbours) {
            mean += points.row(j).transpose();
            if ((points.row(j).transpose() - x).squaredNorm() < 0.25 * h * h) close.push_back(j);
        }
        mean /= double(neighbours.size());
        if (options.project) options.project(mean);
        const double step = (mean - x).norm();
        x = mean;
        a.after.push_back(x);
        a.covered.push_back(std::move(close));
        if (step < 1e-4 * h) {
            a.converged = true;
            break;
        }
        if (near_mode(modes, known, x, options.join_radius * h)) {
            a.joined = true;
            break;
        }
    }
    if (!a.joined) a.height = tree.count_within(x.data(), h, tree.size());
    return a;
}

// The ascent as the sequential loop would have climbed it knowing every mode found so
// far, not only the first `known`: it stops at the first step that comes within the join
// radius of one (the join test follows every step but one that converged).  Sets `joined`; returns
// the steps taken.
size_t replay(Ascent& a, const std::vector<Eigen::VectorXd>& modes, size_t known, double radius) {
    if (modes.size() == known) return a.after.size();
    for (size_t k = 0; k < a.after.size(); ++k) {
        const bool tested = k + 1 < a.after.size() || !a.converged;
        if (tested && near_mode(modes, modes.size(), a.after[k], radius)) {
            a.joined = true;
            return k + 1;
        }
    }
    return a.after.size();
}

// A new mode, or merged with an existing one closer than h/2, keeping the higher one.
// Returns whether an existing mode moved.
bool add_mode(const Eigen::VectorXd& x, int height, double h, std::vector<Eigen::VectorXd>& modes,
              std::vector<int>& heights) {
    for (size_t k = 0; k < modes.size(); ++k)
        if ((modes[k] - x).norm() < 0.5 * h) {
            if (height <= heights[k]) return false;
            modes[k] = x;
            heights[k] = height;
            return true;
        }
    modes.push_back(x);
    heights.push_back(height);
    return false;
}

// The modes, climbed from the starts in `order` (decreasing density), skipping points
// within h/2 of an earlier ascent path, which they would follow anyway (Comaniciu and
// Meer's basin of attraction); modes closer than h/2 are merged.  A point whose
// neighbourhood is too thin cannot reach a mode of sufficient height on its own; the ones
// that could are reached from denser starts.
//
// That is a sequence, but its ascents are climbed a batch at a time on every core: each
// ascent of a batch knows the modes found before the batch, and is then committed in
// order as if it had been climbed alone: skipped if a path committed before it covers
// its start, cut at the first step that comes within the join radius of a mode committed before it
// (climbed again if a merge moved a mode it knew).  An ascent only stops earlier for
// knowing more modes, never takes another path, so the result is the sequential one at
// any thread count.
void find_modes(const KdTree& tree, const std::vector<int>& density, const std::vector<int>& order,
                const MeanShiftOptions& options, std::vector<Eigen::VectorXd>& modes, std::vector<int>& heights) {
    const double h = options.bandwidth;
    std::vector<char> covered(size_t(tree.size()), 0);
    const int batch_size = std::max(1, options.batch_size);
    size_t next = 0;
    bool last = false;
    while (next < order.size() && !last) {
        std::vector<int> batch;
        for (; next < order.size() && int(batch.size()) < batch_size; ++next) {
            const int start = order[next];
            if (density[size_t(start)] < options.min_support) {  // and so are all after it
                last = true;
                break;
            }
            if (!covered[size_t(start)]) batch.push_back(start);
        }
        const size_t known = modes.size();
        std::vector<Ascent> ascents(batch.size());
#pragma omp parallel for schedule(dynamic, 1)
        for (int b = 0; b < int(batch.size()); ++b) ascents[size_t(b)] = climb(tree, batch[size_t(b)], modes, known, options);

        bool moved_a_mode = false;  // a merge moved a mode the later ascents knew
        for (Ascent& a : ascents) {
            if (options.max_modes > 0 && int(modes.size()) >= options.max_modes) return;
            if (covered[size_t(a.start)]) continue;
            if (moved_a_mode) a = climb(tree, a.start, modes, modes.size(), options);
            const size_t steps = replay(a, modes, known, options.join_radius * h);
            for (size_t k = 0; k < steps; ++k)
                for (int j : a.covered[k]) covered[size_t(j)] = 1;
            if (a.joined || a.height < options.min_support) continue;
            moved_a_mode |= add_mode(a.after.back(), a.height, h, modes, heights);
        }
    }
}

// The density of the points whose `stale` flag is set, counted again.  Each point's count
// is its own entry: the same at any thread count.
void count_densities(const KdTree& tree, const MeanShiftOptions& options, const std::vector<char>& stale,
                     std::vector<int>& density) {
    const KdTree::Points& points = tree.points();
#pragma omp parallel for schedule(dynamic, 256)
    for (int i = 0; i < tree.size(); ++i)
        if (stale[size_t(i)])
            density[size_t(i)] = tree.count_within(points.row(i).data(), options.bandwidth, options.density_cap);
}

}  // namespace

std::vector<int> densities(const KdTree& tree, const MeanShiftOptions& options) {
    std::vector<int> density(size_t(tree.size()), 0);
    count_densities(tree, options, std::vector<char>(size_t(tree.size()), 1), density);
    return density;
}

std::vector<int> densities_after_removal(const KdTree& tree, const std::vector<int>& before,
                                         const std::vector<int>& earlier_index, const KdTree::Points& removed,
                                         const MeanShiftOptions& options) {
    std::vector<int> density(size_t(tree.size()));
    for (int i = 0; i < tree.size(); ++i) density[size_t(i)] = before[size_t(earlier_index[size_t(i)])];
    // Only a point within h of a removed one lost a neighbour; the distance is symmetric,
    // so the range query around the removed point finds exactly those.
    std::vector<char> stale(size_t(tree.size()), 0);
    for (Eigen::Index r = 0; r < removed.rows(); ++r)
        for (int i : tree.radius_search(removed.row(r).data(), options.bandwidth, false)) stale[size_t(i)] = 1;
    count_densities(tree, options, stale, density);
    return density;
}

std::vector<Cluster> mean_shift(const KdTree& tree, const MeanShiftOptions& options) {
    return mean_shift(tree, densities(tree, options), options);
}

std::vector<Cluster> mean_shift(const KdTree& tree, const std::vector<int>& density, const MeanShiftOptions& options) {
    const int n = tree.size();
    const double h = options.bandwidth;
    std::vector<Cluster> clusters;
    if (n == 0) return clusters;
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return density[a] > density[b]; });
    std::vector<Eigen::VectorXd> modes;
    std::vector<int> heights;
    find_modes(tree, density, order, options, modes, heights);

    // The members of a cluster are the points within h of its mode, the ones its height
    // counts.  (Assigning each point to its nearest mode only would leave a mode on a
    // ridge of the density, as a continuous family makes, with no members at all.)
    for (size_t k = 0; k < modes.size(); ++k) {
        Cluster c;
        c.mode = modes[k];
        c.members = tree.radius_search(modes[k].data(), h);
        c.height = heights[k];
        clusters.push_back(std::move(c));
    }
    std::stable_sort(clusters.begin(), clusters.end(),
                     [](const Cluster& a, const Cluster& b) { return a.height > b.height; });
    return clusters;
}

}  // namespace symmetry
