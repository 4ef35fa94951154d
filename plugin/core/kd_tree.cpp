#include "kd_tree.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>

namespace symmetry {

namespace {
struct RowMajorAdaptor {
    const KdTree::Points* points;
    size_t kdtree_get_point_count() const { return size_t(points->rows()); }
    double kdtree_get_pt(size_t idx, size_t dim) const { return (*points)(Eigen::Index(idx), Eigen::Index(dim)); }
    template <class Box> bool kdtree_get_bbox(Box&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Adaptor<double, RowMajorAdaptor>,
                                                 RowMajorAdaptor, -1, size_t>;
}  // namespace

struct KdTree::Index {
    RowMajorAdaptor adaptor;
    Tree tree;
    Index(const Points* p)
        : adaptor{p}, tree(int(p->cols()), adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
        tree.buildIndex();
    }
};

KdTree::KdTree(Points points) : points_(std::move(points)) {
    index_ = std::make_unique<Index>(&points_);
}
KdTree::~KdTree() = default;

KdTree::Points KdTree::rows_of(const std::vector<Eigen::Vector3d>& points) {
    Points rows(Eigen::Index(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) rows.row(Eigen::Index(i)) = points[i].transpose();
    return rows;
}
// The index holds a pointer to points_, so a move must rebuild that link.
KdTree::KdTree(KdTree&& other) noexcept : points_(std::move(other.points_)), index_(std::move(other.index_)) {
    if (index_) index_->adaptor.points = &points_;
}
KdTree& KdTree::operator=(KdTree&& other) noexcept {
    points_ = std::move(other.points_);
    index_ = std::move(other.index_);
    if (index_) index_->adaptor.points = &points_;
    return *this;
}

std::vector<int> KdTree::radius_search(const double* query, double radius, bool sorted) const {
    std::vector<int> result;
    if (points_.rows() == 0) return result;
    std::vector<std::pair<size_t, double>> matches;
    // nanoflann's L2 metric works on squared distances.
    index_->tree.radiusSearch(query, radius * radius, matches, nanoflann::SearchParams(32, 0.0, false));
    result.reserve(matches.size());
    for (const auto& m : matches) result.push_back(int(m.first));
    if (sorted) std::sort(result.begin(), result.end());
    return result;
}

namespace {
// A nanoflann result set that only counts, and asks the search to stop at the cap.
struct CappedCounter {
    double radius2;
    int cap;
    int count = 0;
    size_t size() const { return size_t(count); }
    bool full() const { return true; }
    double worstDist() const { return radius2; }
    bool addPoint(double dist, size_t) {
        if (dist < radius2) ++count;
        return count < cap;
    }
};
}  // namespace

int KdTree::count_within(const double* query, double radius, int cap) const {
    if (points_.rows() == 0 || cap <= 0) return 0;
    CappedCounter counter{radius * radius, cap};
    index_->tree.radiusSearchCustomCallback(query, counter, nanoflann::SearchParams(32, 0.0, false));
    return std::min(counter.count, cap);
}

std::pair<int, double> KdTree::nearest(const double* query) const {
    if (points_.rows() == 0) return {-1, INFINITY};
    size_t index = 0;
    double squared = 0;
    nanoflann::KNNResultSet<double, size_t> result(1);
    result.init(&index, &squared);
    index_->tree.findNeighbors(result, query, nanoflann::SearchParams());
    return {int(index), std::sqrt(squared)};
}

std::vector<int> KdTree::nearest_k(const double* query, int k) const {
    const size_t count = size_t(std::max(0, std::min<int>(k, int(points_.rows()))));
    std::vector<size_t> indices(count);
    std::vector<double> squared(count);
    if (count == 0) return {};
    nanoflann::KNNResultSet<double, size_t> result(count);
    result.init(indices.data(), squared.data());
    index_->tree.findNeighbors(result, query, nanoflann::SearchParams());
    return std::vector<int>(indices.begin(), indices.begin() + long(result.size()));
}

}  // namespace symmetry
