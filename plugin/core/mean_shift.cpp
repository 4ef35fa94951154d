#include "mean_shift.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace symmetry {

std::vector<Cluster> mean_shift(const KdTree& tree, const MeanShiftOptions& options) {
    const KdTree::Points& points = tree.points();
    const int n = tree.size();
    const int dim = tree.dimension();
    const double h = options.bandwidth;
    std::vector<Cluster> clusters;
    if (n == 0) return clusters;

    // Density at every point, to start the ascent from the densest points first.
    std::vector<int> density(n);
#pragma omp parallel for schedule(dynamic, 256)
    for (int i = 0; i < n; ++i) density[i] = tree.count_within(points.row(i).data(), h, options.density_cap);
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return density[a] > density[b]; });

    std::vector<Eigen::VectorXd> modes;
    std::vector<int> heights;
    // Comaniciu and Meer's basin-of-attraction shortcut: points within h/2 of a
    // trajectory would climb to the same mode, so no ascent starts from them.
    std::vector<char> covered(n, 0);
    Eigen::VectorXd x(dim), mean(dim);
    for (int start : order) {
        // A point whose neighbourhood is too thin cannot reach a mode of sufficient
        // height on its own; the ones that could are reached from denser starts.
        if (density[start] < options.min_support) break;
        if (options.max_modes > 0 && int(modes.size()) >= options.max_modes) break;
        if (covered[start]) continue;
        x = points.row(start).transpose();

        // An ascent that comes within h/2 of a mode already found would end there (the
        // merge below): it stops at once.  On a ridge of the density, as a continuous
        // family makes, most ascents are such.
        auto near_known_mode = [&](const Eigen::VectorXd& y) {
            for (const auto& m : modes)
                if ((m - y).squaredNorm() < 0.25 * h * h) return true;
            return false;
        };
        std::vector<int> neighbours;
        bool joined = false;
        for (int it = 0; it < options.max_iterations && !joined; ++it) {
            neighbours = tree.radius_search(x.data(), h, false);
            if (neighbours.empty()) break;
            mean.setZero();
            for (int j : neighbours) {
                mean += points.row(j).transpose();
                if ((points.row(j).transpose() - x).squaredNorm() < 0.25 * h * h) covered[size_t(j)] = 1;
            }
            mean /= double(neighbours.size());
            if (options.project) options.project(mean);
            double step = (mean - x).norm();
            x = mean;
            if (step < 1e-4 * h) break;
            joined = near_known_mode(x);
        }
        if (joined) continue;
        int height = tree.count_within(x.data(), h, n);
        if (height < options.min_support) continue;

        // Merge with an existing mode closer than h/2, keeping the higher one.
        bool merged = false;
        for (size_t k = 0; k < modes.size(); ++k)
            if ((modes[k] - x).norm() < 0.5 * h) {
                if (height > heights[k]) { modes[k] = x; heights[k] = height; }
                merged = true;
                break;
            }
        if (!merged) { modes.push_back(x); heights.push_back(height); }
    }

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
