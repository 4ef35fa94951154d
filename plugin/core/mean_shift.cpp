#include "mean_shift.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

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

// The points bucketed into cells of side h along a few of their coordinates: the three of
// the translation, then the rotation entries that vary most (MeanShiftOptions::grid_axes
// in all).  Two points within h of each other are within h along each axis, so a point's
// neighbours lie in its own cell or the ones next to it (3^axes cells), the same for every
// point of the cell: a density is counted by scanning those, with no tree to descend.  In
// 13 dimensions a kd-tree's ball of radius h overlaps most cells it could prune, and where
// the votes crowd (a facade's 120 copies) it visits many leaves for each sparse point.
class CellGrid {
public:
    CellGrid(const KdTree::Points& points, double side, int axes) : points_(points), side_(side) {
        choose_axes(axes);
        const Eigen::Index n = points.rows();
        std::vector<int64_t> low(axes_.size(), INT64_MAX), high(axes_.size(), INT64_MIN);
        for (Eigen::Index i = 0; i < n; ++i)
            for (size_t a = 0; a < axes_.size(); ++a) {
                if (!std::isfinite(points(i, axes_[a]))) return;  // not usable(): no cell holds it
                low[a] = std::min(low[a], index_along(points.row(i).data(), a));
                high[a] = std::max(high[a], index_along(points.row(i).data(), a));
            }
        for (size_t a = 0; a < axes_.size(); ++a)
            if (high[a] - low[a] + 3 > kCellsPerAxis) return;  // not usable(): a key would wrap
        low_ = low;
        std::vector<std::pair<uint64_t, int>> keyed(static_cast<size_t>(n));
        for (Eigen::Index i = 0; i < n; ++i) keyed[size_t(i)] = {key_of(points.row(i).data()), int(i)};
        std::sort(keyed.begin(), keyed.end());
        members_.reserve(size_t(n));
        for (size_t k = 0; k < keyed.size(); ++k) {
            if (k == 0 || keyed[k].first != keyed[k - 1].first) {
                index_[keyed[k].first] = int(starts_.size());
                starts_.push_back(int(k));
                keys_.push_back(keyed[k].first);
            }
            members_.push_back(keyed[k].second);
        }
        starts_.push_back(int(members_.size()));
    }

    /// False when the points spread over too many cells for a key (a bandwidth far below
    /// the spread of Γ), or a coordinate is not finite: the caller counts with the tree.
    bool usable() const { return !low_.empty(); }
    int cell_count() const { return int(keys_.size()); }
    /// The points of cell c, as a range of member().
    std::pair<int, int> cell(int c) const { return {starts_[size_t(c)], starts_[size_t(c) + 1]}; }
    int member(int m) const { return members_[size_t(m)]; }

    /// The non-empty cells around cell c (its own first, where a dense neighbourhood reaches
    /// the cap soonest), as ranges of member(); returns how many points they hold.
    int neighbourhood(int c, std::vector<std::pair<int, int>>& ranges) const {
        ranges.clear();
        int total = 0;
        int around = 1;
        for (size_t a = 0; a < axes_.size(); ++a) around *= 3;
        const int middle = around / 2;  // every offset 0: the cell itself
        for (int k = 0; k < around; ++k) {
            const int n = k == 0 ? middle : (k <= middle ? k - 1 : k);
            uint64_t key = keys_[size_t(c)];
            int64_t shift = 0;
            // Offsets in -1..1 per axis; the construction keeps every neighbour's index in
            // range, so adding to the packed key is adding to each axis's field.
            for (int a = int(axes_.size()) - 1, rest = n; a >= 0; --a, rest /= 3)
                shift += int64_t(rest % 3 - 1) * (int64_t(1) << (kBitsPerAxis * (int(axes_.size()) - 1 - a)));
            key = uint64_t(int64_t(key) + shift);
            auto it = index_.find(key);
            if (it == index_.end()) continue;
            ranges.push_back(cell(it->second));
            total += ranges.back().second - ranges.back().first;
        }
        return total;
    }

    /// The points within h of `query` among those ranges, counted up to `cap`:
    /// KdTree::count_within, by scanning.  Only points numbered `first` or more count (the
    /// grid may hold two sets, one after the other).
    int count_within(const double* query, const std::vector<std::pair<int, int>>& ranges, int cap, int first = 0) const {
        const double h2 = side_ * side_;
        int count = 0;
        for (const auto& [begin, end] : ranges)
            for (int m = begin; m < end; ++m) {
                const int j = members_[size_t(m)];
                if (j >= first && squared_distance(query, points_.row(j).data()) < h2 && ++count >= cap) return cap;
            }
        return count;
    }

private:
    static constexpr int kTranslationAxes = 3;
    static constexpr int kMaxAxes = 6;
    static constexpr int kBitsPerAxis = 10;  // 6 axes in a 64-bit key
    static constexpr int64_t kCellsPerAxis = int64_t(1) << kBitsPerAxis;

    // The translation's axes, then the other coordinates of largest variance.
    void choose_axes(int axes) {
        const int dimension = int(points_.cols());
        axes = std::max(1, std::min({axes, dimension, kMaxAxes}));
        std::vector<std::pair<double, int>> spread;
        for (int d = kTranslationAxes; d < dimension; ++d) {
            const double mean = points_.col(d).mean();
            spread.push_back({-(points_.col(d).array() - mean).square().sum(), d});
        }
        std::sort(spread.begin(), spread.end());
        for (int d = 0; d < std::min(axes, kTranslationAxes); ++d) axes_.push_back(d);
        for (size_t k = 0; int(axes_.size()) < axes && k < spread.size(); ++k) axes_.push_back(spread[k].second);
    }
    // Summed as nanoflann's L2 metric sums it (four terms at a time), so that a count is
    // the tree's, comparison for comparison.  (a - b)^2 is (b - a)^2 exactly: the same
    // whichever of the two is the query.
    double squared_distance(const double* query, const double* p) const {
        const int dimension = int(points_.cols());
        double d2 = 0;
        int d = 0;
        for (; d + 3 < dimension; d += 4) {
            const double a = query[d] - p[d], b = query[d + 1] - p[d + 1], c = query[d + 2] - p[d + 2],
                         e = query[d + 3] - p[d + 3];
            d2 += a * a + b * b + c * c + e * e;
        }
        for (; d < dimension; ++d) d2 += (query[d] - p[d]) * (query[d] - p[d]);
        return d2;
    }
    int64_t index_along(const double* x, size_t a) const { return int64_t(std::floor(x[axes_[a]] / side_)); }
    // Each axis's cell index, counted from one below the lowest, in a field of its own.
    uint64_t key_of(const double* x) const {
        uint64_t key = 0;
        for (size_t a = 0; a < axes_.size(); ++a) key = key << kBitsPerAxis | uint64_t(index_along(x, a) - low_[a] + 1);
        return key;
    }

    const KdTree::Points& points_;
    double side_;
    std::vector<int> axes_;          // coordinates the cells divide
    std::vector<int64_t> low_;       // lowest cell index along each axis; empty: not usable()
    std::unordered_map<uint64_t, int> index_;  // key -> cell
    std::vector<uint64_t> keys_;     // per cell
    std::vector<int> starts_;        // per cell, its first entry of members_; one past the end last
    std::vector<int> members_;       // point indices, cell by cell
};

// The density of the points whose `stale` flag is set, counted again, cell by cell
// (CellGrid): a point with few points in the cells around it (the sparse background, most
// of Γ) is counted by scanning them; one in a crowded neighbourhood by the tree, whose
// search reaches the cap from the nearest points.  Both count the same.  Each point's
// count is its own entry: the same at any thread count.
void count_densities(const KdTree& tree, const MeanShiftOptions& options, const std::vector<char>& stale,
                     std::vector<int>& density) {
    const KdTree::Points& points = tree.points();
    auto count_by_tree = [&] {
#pragma omp parallel for schedule(dynamic, 256)
        for (int i = 0; i < tree.size(); ++i)
            if (stale[size_t(i)]) density[size_t(i)] = tree.count_within(points.row(i).data(), options.bandwidth, options.density_cap);
    };
    // The grid sorts every point: not worth it for a recount around a few removed votes.
    const double stale_count = double(std::count(stale.begin(), stale.end(), char(1)));
    if (stale_count < options.min_grid_share * double(tree.size())) return count_by_tree();
    const CellGrid grid(points, options.bandwidth, options.grid_axes);
    if (!grid.usable()) return count_by_tree();
#pragma omp parallel
    {
        std::vector<std::pair<int, int>> ranges;
#pragma omp for schedule(dynamic, 8)
        for (int c = 0; c < grid.cell_count(); ++c) {
            const auto [begin, end] = grid.cell(c);
            bool any = false;
            for (int m = begin; m < end && !any; ++m) any = stale[size_t(grid.member(m))];
            if (!any) continue;
            const bool scan = grid.neighbourhood(c, ranges) <= options.max_scanned_neighbours;
            for (int m = begin; m < end; ++m) {
                const int i = grid.member(m);
                if (!stale[size_t(i)]) continue;
                const double* x = points.row(i).data();
                density[size_t(i)] = scan ? grid.count_within(x, ranges, options.density_cap)
                                          : tree.count_within(x, options.bandwidth, options.density_cap);
            }
        }
    }
}

// Which points of the tree lie within h of one of `removed`.  One range query in the tree
// around each removed point finds them, but in 13 dimensions each costs as much as
// counting a density (a torus's family: 61,000 queries, 1.7 s).  So the kept and the removed
// points share one CellGrid: a kept point is scanned against the removed points in the
// cells around its own, stopping at the first within h; where those cells are crowded, a
// tree of the removed points answers (a count capped at one).  Distances are symmetric
// and summed as the tree sums them, so the answer is the range queries', point for point.
std::vector<char> near_removed(const KdTree& tree, const KdTree::Points& removed, const MeanShiftOptions& options) {
    const int n = tree.size();
    std::vector<char> near(size_t(n), 0);
    if (removed.rows() == 0 || n == 0) return near;
    KdTree::Points both(n + removed.rows(), tree.dimension());
    both.topRows(n) = tree.points();
    both.bottomRows(removed.rows()) = removed;
    const CellGrid grid(both, options.bandwidth, options.grid_axes);
    if (!grid.usable()) {
        for (Eigen::Index r = 0; r < removed.rows(); ++r)
            for (int i : tree.radius_search(removed.row(r).data(), options.bandwidth, false)) near[size_t(i)] = 1;
        return near;
    }
    const KdTree removed_tree(removed);
#pragma omp parallel
    {
        std::vector<std::pair<int, int>> ranges;
#pragma omp for schedule(dynamic, 8)
        for (int c = 0; c < grid.cell_count(); ++c) {
            const auto [begin, end] = grid.cell(c);
            bool any_kept = false;
            for (int m = begin; m < end && !any_kept; ++m) any_kept = grid.member(m) < n;
            if (!any_kept) continue;
            const bool scan = grid.neighbourhood(c, ranges) <= options.max_scanned_neighbours;
            for (int m = begin; m < end; ++m) {
                const int i = grid.member(m);
                if (i >= n) continue;
                const double* x = both.row(i).data();
                near[size_t(i)] = scan ? grid.count_within(x, ranges, 1, n) > 0
                                       : removed_tree.count_within(x, options.bandwidth, 1) > 0;
            }
        }
    }
    return near;
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
    // Only a point within h of a removed one lost a neighbour.
    count_densities(tree, options, near_removed(tree, removed, options), density);
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
