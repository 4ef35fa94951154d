#include "surface_query.h"

#include <vcg/complex/algorithms/closest.h>
#include <vcg/space/index/grid_static_ptr.h>

namespace symmetry {

struct SurfaceQuery::Grid {
    vcg::GridStaticPtr<Face, double> grid;
};

SurfaceQuery::SurfaceQuery(const Mesh& mesh) : mesh_(mesh), grid_(std::make_unique<Grid>()) {
    Mesh& m = const_cast<Mesh&>(mesh);  // vcg's grid stores non-const face pointers; it never writes
    grid_->grid.Set(m.face.begin(), m.face.end());
}

SurfaceQuery::~SurfaceQuery() = default;

namespace {
// vcg's point-face distance, blind to the faces whose normal does not match.
struct FacingDistance {
    typedef double ScalarType;
    typedef vcg::Point3d QueryType;
    static const vcg::Point3d& Pos(const vcg::Point3d& q) { return q; }
    const std::vector<Eigen::Vector3d>* normals;
    double min_cosine;
    bool either_sign;
    vcg::face::PointDistanceBaseFunctor<double> distance;
    bool operator()(const Face& f, const vcg::Point3d& p, double& min_distance, vcg::Point3d& q) {
        const Eigen::Vector3d n(f.cN()[0], f.cN()[1], f.cN()[2]);
        bool facing = false;
        for (const Eigen::Vector3d& m : *normals) {
            const double c = n.dot(m);
            if ((either_sign ? std::abs(c) : c) >= min_cosine) { facing = true; break; }
        }
        return facing && distance(f, p, min_distance, q);
    }
};

// The closest point under vcg's grid search with the given point-face distance.
// EmptyTMark instead of the mesh's marks: a face may be tested twice, but queries do not
// write to the mesh, so they can later run from several threads.
template <class Distance>
ClosestPoint closest_under(const Mesh& mesh, vcg::GridStaticPtr<Face, double>& grid, Distance& point_face_distance,
                           const Eigen::Vector3d& query, double max_distance) {
    ClosestPoint result;
    vcg::tri::EmptyTMark<Mesh> marker;
    const vcg::Point3d p(query.x(), query.y(), query.z());
    double distance = max_distance;
    vcg::Point3d nearest(0, 0, 0);
    Face* f = grid.GetClosest(point_face_distance, marker, p, max_distance, distance, nearest);
    if (f == nullptr) return result;
    result.found = true;
    result.face = int(vcg::tri::Index(mesh, f));
    result.point = Eigen::Vector3d(nearest[0], nearest[1], nearest[2]);
    result.normal = Eigen::Vector3d(f->N()[0], f->N()[1], f->N()[2]).normalized();
    result.distance = (query - result.point).norm();
    result.signed_distance = (query - result.point).dot(result.normal) >= 0 ? result.distance : -result.distance;
    return result;
}
}  // namespace

ClosestPoint SurfaceQuery::closest_facing(const Eigen::Vector3d& query, double max_distance,
                                          const std::vector<Eigen::Vector3d>& normals, double min_cosine,
                                          bool either_sign) const {
    FacingDistance point_face_distance{&normals, min_cosine, either_sign, {}};
    return closest_under(mesh_, grid_->grid, point_face_distance, query, max_distance);
}

ClosestPoint SurfaceQuery::closest(const Eigen::Vector3d& query, double max_distance) const {
    vcg::face::PointDistanceBaseFunctor<double> point_face_distance;
    return closest_under(mesh_, grid_->grid, point_face_distance, query, max_distance);
}

}  // namespace symmetry
