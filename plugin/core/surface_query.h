// Closest-point queries on the mesh, shared by verification (§4) and the deviation
// output: vcglib's uniform grid over the faces does the search.
#pragma once

#include "mesh.h"

#include <Eigen/Core>
#include <memory>

namespace symmetry {

struct ClosestPoint {
    bool found = false;
    int face = -1;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit normal of that face
    double distance = 0;         ///< unsigned distance from the query
    double signed_distance = 0;  ///< positive when the query lies on the outer side of the face
};

class SurfaceQuery {
public:
    explicit SurfaceQuery(const Mesh& mesh);  ///< the mesh must outlive the query
    ~SurfaceQuery();
    /// The closest point of the surface within `max_distance` of `query`; found=false if none.
    ClosestPoint closest(const Eigen::Vector3d& query, double max_distance) const;

private:
    struct Grid;
    const Mesh& mesh_;
    std::unique_ptr<Grid> grid_;
};

}  // namespace symmetry
