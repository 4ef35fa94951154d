// A thin wrapper around nanoflann for the three neighbourhood queries of the
// pipeline: edges near a sample (curvature tensor, §2), partners in signature
// space (§2.2) and neighbours in transformation space (§3.1).  Wrapping it keeps
// the nanoflann API version (Debian ships 1.4, newer releases changed the result
// type) in one place.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace symmetry {

/// Points are the rows of a dense matrix; the tree keeps its own copy.
class KdTree {
public:
    using Points = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    explicit KdTree(Points points);
    /// 3-D points as the rows a tree is built from.
    static Points rows_of(const std::vector<Eigen::Vector3d>& points);
    ~KdTree();
    KdTree(KdTree&&) noexcept;
    KdTree& operator=(KdTree&&) noexcept;

    int size() const { return int(points_.rows()); }
    int dimension() const { return int(points_.cols()); }
    const Points& points() const { return points_; }

    /// Indices of all points within Euclidean distance `radius` of `query`
    /// (dimension() values), in increasing index order so results are deterministic
    /// (unless `sorted` is false, for callers that filter and sort themselves).
    std::vector<int> radius_search(const double* query, double radius, bool sorted = true) const;

    /// How many points lie within `radius` of `query`, counting no further than `cap`: the
    /// search stops there, so a count in a dense region costs no more than in a sparse one.
    int count_within(const double* query, double radius, int cap) const;

    /// Index of the nearest point and its Euclidean distance.
    std::pair<int, double> nearest(const double* query) const;

    /// Indices of the `k` nearest points (fewer if the tree holds fewer), nearest first.
    std::vector<int> nearest_k(const double* query, int k) const;

private:
    struct Index;
    Points points_;
    std::unique_ptr<Index> index_;
};

}  // namespace symmetry
