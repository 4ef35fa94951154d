#include "surface_query.h"

#include "kd_tree.h"

#include <vcg/complex/algorithms/closest.h>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vcg/space/index/grid_static_ptr.h>

namespace symmetry {

namespace {
// The faces one grid search has tested, for vcg's grid search in place of the mesh's own
// marks (which queries from several threads would share).  The grid holds a face in every
// cell it overlaps, and a search unmarked tests a face once per cell it meets (measured on
// the 160k-vertex scan of the speed benchmark: 95 million face tests unmarked, 42 million
// marked, and verification from 7.5 s to 4.5 s, with the same answers).  Each thread keeps
// a stamp per face for the last two surfaces it searched; a search marks with a stamp one
// above the last.
class QueryMarks {
public:
    QueryMarks(const Mesh& mesh, std::uint64_t surface) : first_(mesh.face.empty() ? nullptr : &mesh.face[0]) {
        thread_local std::array<Stamps, 2> recent;
        Stamps* slot = &recent[0];
        for (Stamps& s : recent)
            if (s.surface == surface) slot = &s;
        if (slot->surface != surface) {  // reuse the one searched less recently
            slot = recent[0].last_use <= recent[1].last_use ? &recent[0] : &recent[1];
            slot->surface = surface;
            slot->stamp.assign(mesh.face.size(), 0);
            slot->current = 0;
        }
        slot->last_use = ++uses();
        stamps_ = slot;
    }
    void UnMarkAll() {
        if (++stamps_->current == 0) {  // the stamps wrapped around: start them again
            std::fill(stamps_->stamp.begin(), stamps_->stamp.end(), 0u);
            stamps_->current = 1;
        }
    }
    bool IsMarked(const Face* f) const { return stamps_->stamp[size_t(f - first_)] == stamps_->current; }
    void Mark(const Face* f) { stamps_->stamp[size_t(f - first_)] = stamps_->current; }

private:
    struct Stamps {
        std::uint64_t surface = 0;
        std::uint64_t last_use = 0;
        std::vector<std::uint32_t> stamp;
        std::uint32_t current = 0;
    };
    static std::uint64_t& uses() {
        thread_local std::uint64_t count = 0;
        return count;
    }
    const Face* first_;
    Stamps* stamps_;
};

std::uint64_t next_surface_id() {
    static std::atomic<std::uint64_t> next{1};
    return next++;
}

}  // namespace

// The faces in vcg's grid, and a sphere around each (its centroid and the distance to its
// farthest corner), so that a search skips at the cost of one distance a face that lies
// farther than its bound, before vcg's exact point-triangle distance.
struct SurfaceQuery::Grid {
    vcg::GridStaticPtr<Face, double> grid;
    const Face* first = nullptr;
    std::vector<Eigen::Vector4d> spheres;  // centre, radius

    explicit Grid(const Mesh& mesh) : first(mesh.face.empty() ? nullptr : &mesh.face[0]) {
        spheres.resize(mesh.face.size());
        for (size_t f = 0; f < mesh.face.size(); ++f) {
            Eigen::Vector3d corner[3];
            for (int k = 0; k < 3; ++k) {
                const auto& p = mesh.face[f].cP(k);
                corner[k] = Eigen::Vector3d(p[0], p[1], p[2]);
            }
            const Eigen::Vector3d centre = (corner[0] + corner[1] + corner[2]) / 3;
            double radius = 0;
            for (const Eigen::Vector3d& c : corner) radius = std::max(radius, (c - centre).norm());
            spheres[f] << centre, radius;
        }
    }
    // Whether face f may lie within `bound` of q.  The sphere's radius is widened a little:
    // a face exactly at the bound counts, as in vcg's test, whatever the rounding.
    bool may_reach(const Face& f, const vcg::Point3d& q, double bound) const {
        const Eigen::Vector4d& s = spheres[size_t(&f - first)];
        const double dx = q[0] - s[0], dy = q[1] - s[1], dz = q[2] - s[2];
        const double reach = (s[3] + bound) * (1 + 1e-9);
        return dx * dx + dy * dy + dz * dz <= reach * reach;
    }
};

SurfaceQuery::SurfaceQuery(const Mesh& mesh, double cells_per_face)
    : mesh_(&mesh), id_(next_surface_id()), grid_(std::make_unique<Grid>(mesh)) {
    Mesh& m = const_cast<Mesh&>(mesh);  // vcg's grid stores non-const face pointers; it never writes
    const int cells = int(std::max(1.0, std::min(cells_per_face * double(m.face.size()), 1e8)));
    grid_->grid.Set(m.face.begin(), m.face.end(), cells);
}

// A cloud's discs: a kd-tree over their centres, searched for the `candidates` nearest.
struct SurfaceQuery::Discs {
    std::vector<Eigen::Vector3d> centres, normals;
    std::vector<double> radii;
    KdTree tree;
    int candidates;

    Discs(const std::vector<Eigen::Vector3d>& p, const std::vector<Eigen::Vector3d>& n, const std::vector<double>& r,
          int k)
        : centres(p), normals(n), radii(r), tree(KdTree::rows_of(p)), candidates(k) {}

    // The point of disc i nearest to q: q's projection on its plane, pulled in to the rim.
    ClosestPoint on_disc(int i, const Eigen::Vector3d& q) const {
        ClosestPoint c;
        const Eigen::Vector3d& n = normals[size_t(i)];
        const double height = (q - centres[size_t(i)]).dot(n);
        Eigen::Vector3d tangential = q - height * n - centres[size_t(i)];
        const double reach = tangential.norm();
        if (reach > radii[size_t(i)]) tangential *= radii[size_t(i)] / reach;
        c.found = true;
        c.face = i;
        c.point = centres[size_t(i)] + tangential;
        c.normal = n;
        c.distance = (q - c.point).norm();
        c.signed_distance = height >= 0 ? c.distance : -c.distance;
        return c;
    }
};

SurfaceQuery::SurfaceQuery(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                           const std::vector<double>& radii, int candidate_discs) {
    if (normals.size() != points.size() || radii.size() != points.size() || candidate_discs < 1)
        throw InputError("A surface of discs needs one normal and one radius per point, and at least one disc per query.");
    discs_ = std::make_unique<Discs>(points, normals, radii, candidate_discs);
}

SurfaceQuery::~SurfaceQuery() = default;

namespace {
// What landing() records while vcg's grid search runs (see LandingDistance).
struct LandingSearch {
    struct Best {
        const Face* face = nullptr;
        double distance = std::numeric_limits<double>::max();
        vcg::Point3d point;
        void offer(const Face& f, double d, const vcg::Point3d& p) {
            if (d > distance) return;
            face = &f;
            distance = d;
            point = p;
        }
    };
    const std::vector<Eigen::Vector3d>* normals;
    double min_cosine;
    double tie;
    Best nearest, facing, facing_either_sign;
};

// The distance vcg's grid search sees while landing(): each face's true distance, but
// the search bound it keeps is the nearest distance so far plus the tie, so that every face
// within that margin of the nearest is tested; the facing ones are recorded on the side.
// (vcg copies the functor: what it records goes to the LandingSearch it points to.)
struct LandingDistance {
    typedef double ScalarType;
    typedef vcg::Point3d QueryType;
    static const vcg::Point3d& Pos(const vcg::Point3d& q) { return q; }
    LandingSearch* search;
    const SurfaceQuery::Grid* grid;
    bool operator()(const Face& f, const vcg::Point3d& p, double& bound, vcg::Point3d& q) const {
        if (!grid->may_reach(f, p, bound)) return false;
        double d = bound;
        vcg::Point3d c;
        if (!vcg::face::PointDistanceBase(f, p, d, c)) return false;
        const Eigen::Vector3d n(f.cN()[0], f.cN()[1], f.cN()[2]);
        double agreement = -1, agreement_either_sign = -1;
        for (const Eigen::Vector3d& m : *search->normals) {
            const double cosine = n.dot(m);
            agreement = std::max(agreement, cosine);
            agreement_either_sign = std::max(agreement_either_sign, std::abs(cosine));
        }
        if (agreement >= search->min_cosine) search->facing.offer(f, d, c);
        if (agreement_either_sign >= search->min_cosine) search->facing_either_sign.offer(f, d, c);
        if (d > search->nearest.distance) return false;
        search->nearest.offer(f, d, c);
        bound = d + search->tie;
        q = c;
        return true;
    }
};

// The distance vcg's grid search sees while closest(): vcg's own, after the sphere test.
struct NearestDistance {
    typedef double ScalarType;
    typedef vcg::Point3d QueryType;
    static const vcg::Point3d& Pos(const vcg::Point3d& q) { return q; }
    const SurfaceQuery::Grid* grid;
    bool operator()(const Face& f, const vcg::Point3d& p, double& bound, vcg::Point3d& q) const {
        return grid->may_reach(f, p, bound) && vcg::face::PointDistanceBase(f, p, bound, q);
    }
};

ClosestPoint closest_point(const Mesh& mesh, const Eigen::Vector3d& query, const Face* f, const vcg::Point3d& nearest) {
    ClosestPoint result;
    if (f == nullptr) return result;
    result.found = true;
    result.face = int(vcg::tri::Index(mesh, f));
    result.point = Eigen::Vector3d(nearest[0], nearest[1], nearest[2]);
    result.normal = Eigen::Vector3d(f->cN()[0], f->cN()[1], f->cN()[2]).normalized();
    result.distance = (query - result.point).norm();
    result.signed_distance = (query - result.point).dot(result.normal) >= 0 ? result.distance : -result.distance;
    return result;
}

// vcg's grid search up to max_distance with the given point-face distance: the face it
// ends on (nullptr if none) and the point of it in `nearest`.
template <class Distance>
const Face* grid_closest(vcg::GridStaticPtr<Face, double>& grid, Distance& point_face_distance, QueryMarks marker,
                         const Eigen::Vector3d& query, double max_distance, vcg::Point3d& nearest) {
    const vcg::Point3d p(query.x(), query.y(), query.z());
    double distance = max_distance;
    nearest = vcg::Point3d(0, 0, 0);
    return grid.GetClosest(point_face_distance, marker, p, max_distance, distance, nearest);
}
}  // namespace

namespace {
// landing() on a cloud's discs: the same three answers from the nearest discs.
SurfaceQuery::Landing disc_landing(const std::vector<ClosestPoint>& near, double max_distance, double tie,
                                   const std::vector<Eigen::Vector3d>& normals, double min_cosine) {
    SurfaceQuery::Landing out;
    const ClosestPoint* nearest = nullptr;
    for (const ClosestPoint& c : near)
        if (c.distance <= max_distance && (!nearest || c.distance < nearest->distance)) nearest = &c;
    if (!nearest) return out;
    out.nearest = *nearest;
    const double reach = nearest->distance + tie;
    for (const ClosestPoint& c : near) {
        if (c.distance > reach) continue;
        double agreement = -1, agreement_either_sign = -1;
        for (const Eigen::Vector3d& m : normals) {
            agreement = std::max(agreement, c.normal.dot(m));
            agreement_either_sign = std::max(agreement_either_sign, std::abs(c.normal.dot(m)));
        }
        if (agreement >= min_cosine && (!out.facing.found || c.distance < out.facing.distance)) out.facing = c;
        if (agreement_either_sign >= min_cosine &&
            (!out.facing_either_sign.found || c.distance < out.facing_either_sign.distance))
            out.facing_either_sign = c;
    }
    return out;
}
}  // namespace

std::vector<ClosestPoint> SurfaceQuery::nearest_discs(const Eigen::Vector3d& query) const {
    std::vector<ClosestPoint> near;
    for (int i : discs_->tree.nearest_k(query.data(), discs_->candidates)) near.push_back(discs_->on_disc(i, query));
    return near;
}

SurfaceQuery::Landing SurfaceQuery::landing(const Eigen::Vector3d& query, double max_distance, double tie,
                                            const std::vector<Eigen::Vector3d>& normals, double min_cosine) const {
    if (discs_) return disc_landing(nearest_discs(query), max_distance, tie, normals, min_cosine);
    LandingSearch search{&normals, min_cosine, tie, {}, {}, {}};
    LandingDistance point_face_distance{&search, grid_.get()};
    // The bound starts a tie beyond max_distance: a facing face just beyond it counts
    // when the nearest face lies at max_distance.  What the search records is in `search`.
    vcg::Point3d unused;
    grid_closest(grid_->grid, point_face_distance, QueryMarks(*mesh_, id_), query, max_distance + tie, unused);
    Landing out;
    if (search.nearest.distance > max_distance) return out;  // also when no face was met
    out.nearest = closest_point(*mesh_, query, search.nearest.face, search.nearest.point);
    // Only the faces as near as the nearest one count (see RegionGrower::accepts).
    const double reach = search.nearest.distance + tie;
    if (search.facing.distance <= reach)
        out.facing = closest_point(*mesh_, query, search.facing.face, search.facing.point);
    if (search.facing_either_sign.distance <= reach)
        out.facing_either_sign = closest_point(*mesh_, query, search.facing_either_sign.face, search.facing_either_sign.point);
    return out;
}

ClosestPoint SurfaceQuery::closest(const Eigen::Vector3d& query, double max_distance) const {
    if (discs_) {
        ClosestPoint best;
        for (const ClosestPoint& c : nearest_discs(query))
            if (c.distance <= max_distance && (!best.found || c.distance < best.distance)) best = c;
        return best;
    }
    NearestDistance point_face_distance{grid_.get()};
    vcg::Point3d nearest;
    const Face* f = grid_closest(grid_->grid, point_face_distance, QueryMarks(*mesh_, id_), query, max_distance, nearest);
    return closest_point(*mesh_, query, f, nearest);
}

SurfaceOfRows::SurfaceOfRows(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
    std::vector<int> vertex_of_input;
    MeshRepairs repairs;
    build_mesh(V, F, mesh_, vertex_of_input, &repairs);
    row_of_face_ = std::move(repairs.face_of_input);
    query_ = std::make_unique<SurfaceQuery>(mesh_, 8);  // many queries: a finer grid pays
}

SurfaceOfRows::~SurfaceOfRows() = default;

ClosestPoint SurfaceOfRows::closest(const Eigen::Vector3d& query, double max_distance) const {
    ClosestPoint c = query_->closest(query, max_distance);
    if (c.found) c.face = row_of_face_[size_t(c.face)];
    return c;
}

}  // namespace symmetry
