#include "pairing.h"

#include "kd_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace symmetry {

namespace {
double shape_index(double kappa1, double kappa2) {
    // A monotone function of κ1/κ2, finite wherever κ1 ≠ κ2 (umbilics are pruned before
    // pairing); 0 where both vanish.
    return (kappa1 == 0 && kappa2 == 0) ? 0.0 : (2.0 / M_PI) * std::atan2(kappa2 + kappa1, kappa2 - kappa1);
}
}  // namespace

Eigen::VectorXd signature(const SurfaceSignature& s, TransformationGroup group, double radius) {
    if (group == TransformationGroup::Similarity) {
        Eigen::VectorXd sigma(1);
        // Shape index: a monotone function of κ1/κ2, finite wherever κ1 ≠ κ2 (umbilics
        // are pruned before pairing).
        sigma(0) = (2.0 / M_PI) * std::atan2(s.kappa2 + s.kappa1, s.kappa2 - s.kappa1);
        return sigma;
    }
    Eigen::VectorXd sigma(2);
    sigma << s.kappa1 * radius, s.kappa2 * radius;
    return sigma;
}

Eigen::VectorXd ranking_signature(const SurfaceSignature& s, TransformationGroup group, double radius) {
    if (group == TransformationGroup::Similarity) {
        Eigen::VectorXd sigma(2);
        sigma << shape_index(s.kappa1, s.kappa2), shape_index(s.coarse_kappa1, s.coarse_kappa2);
        return sigma;
    }
    Eigen::VectorXd sigma(4);
    sigma << s.kappa1 * radius, s.kappa2 * radius, s.coarse_kappa1 * 2 * radius, s.coarse_kappa2 * 2 * radius;
    return sigma;
}

bool may_be_drawn(const Eigen::Vector3d& position, const PairingOptions& options) {
    return !options.first_pose_below_x || position.x() < *options.first_pose_below_x;
}

bool may_be_partner(const Eigen::Vector3d& position, const PairingOptions& options) {
    return !options.first_pose_below_x || position.x() >= *options.first_pose_below_x;
}

std::vector<SignaturePair> pair_drawn_samples(const std::vector<SurfaceSignature>& samples, TransformationGroup group,
                                              double radius, double tolerance, const std::vector<int>& drawn,
                                              double min_distance, const PairingOptions& options) {
    std::vector<SignaturePair> pairs;
    const int n = int(samples.size());
    if (n < 2) return pairs;

    const int dim = group == TransformationGroup::Similarity ? 1 : 2;
    KdTree::Points omega(n, dim);
    for (int i = 0; i < n; ++i) omega.row(i) = signature(samples[i], group, radius).transpose();
    KdTree tree(std::move(omega));

    std::vector<Eigen::VectorXd> ranking(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) ranking[size_t(i)] = ranking_signature(samples[size_t(i)], group, radius);
    const double min_distance2 = min_distance * min_distance;
    const int max_partners = std::max(1, options.max_partners);
    for (const int i : drawn) {
        std::vector<std::pair<double, int>> partners;
        for (int j : tree.radius_search(tree.points().row(i).data(), tolerance)) {
            if (j == i || !may_be_partner(samples[j].position, options)) continue;
            if ((samples[j].position - samples[i].position).squaredNorm() < min_distance2) continue;
            partners.push_back({(ranking[size_t(j)] - ranking[size_t(i)]).squaredNorm(), j});
        }
        if (int(partners.size()) > max_partners) {
            // Ties are broken by index, so the choice does not depend on the sort.
            std::nth_element(partners.begin(), partners.begin() + max_partners, partners.end());
            partners.resize(size_t(max_partners));
            std::sort(partners.begin(), partners.end(),
                      [](const auto& a, const auto& b) { return a.second < b.second; });
        }
        for (const auto& partner : partners) pairs.push_back({i, partner.second});
    }
    return pairs;
}

std::vector<SignaturePair> pair_in_signature_space(const std::vector<SurfaceSignature>& samples,
                                                   TransformationGroup group, double radius, double tolerance,
                                                   int subset_size, double min_distance, std::mt19937_64& rng,
                                                   const PairingOptions& options) {
    const int n = int(samples.size());
    if (n < 2) return {};
    // P' ⊂ P drawn without replacement (partial Fisher-Yates, own draws so the result does
    // not depend on the standard library's distributions), from the samples that may be
    // drawn (all of them, unless two poses are paired).
    std::vector<int> order;
    order.reserve(size_t(n));
    for (int i = 0; i < n; ++i)
        if (may_be_drawn(samples[size_t(i)].position, options)) order.push_back(i);
    const int drawable = int(order.size());
    const int m = std::min(subset_size, drawable);
    for (int k = 0; k < m; ++k) {
        int j = k + int(rng() % uint64_t(drawable - k));
        std::swap(order[k], order[j]);
    }
    order.resize(size_t(std::max(0, m)));
    std::sort(order.begin(), order.end());
    return pair_drawn_samples(samples, group, radius, tolerance, order, min_distance, options);
}

}  // namespace symmetry
