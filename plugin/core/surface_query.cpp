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

ClosestPoint SurfaceQuery::closest(const Eigen::Vector3d& query, double max_distance) const {
    ClosestPoint result;
    // EmptyTMark instead of the mesh's marks: a face may be tested twice, but queries
    // do not write to the mesh, so they can later run from several threads.
    vcg::tri::EmptyTMark<Mesh> marker;
    vcg::face::PointDistanceBaseFunctor<double> point_face_distance;
    const vcg::Point3d p(query.x(), query.y(), query.z());
    double distance = max_distance;
    vcg::Point3d nearest(0, 0, 0);
    Face* f = grid_->grid.GetClosest(point_face_distance, marker, p, max_distance, distance, nearest);
    if (f == nullptr) return result;
    result.found = true;
    result.face = int(vcg::tri::Index(mesh_, f));
    result.point = Eigen::Vector3d(nearest[0], nearest[1], nearest[2]);
    result.normal = Eigen::Vector3d(f->N()[0], f->N()[1], f->N()[2]).normalized();
    result.distance = (query - result.point).norm();
    result.signed_distance = (query - result.point).dot(result.normal) >= 0 ? result.distance : -result.distance;
    return result;
}

}  // namespace symmetry
