// Closest-point queries on the mesh, shared by verification (§4) and the deviation
// output: vcglib's uniform grid over the faces does the search.
#pragma once

#include "mesh.h"

#include <Eigen/Core>
#include <memory>
#include <vector>

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

    /// The closest point among the faces whose normal n agrees with one of `normals`
    /// (n·m >= min_cosine, or |n·m| >= min_cosine when `either_sign`).  Where several
    /// faces meet at the closest point (a crease, or separate parts that touch there),
    /// the nearest face alone may face another way than the one that matches.
    ClosestPoint closest_facing(const Eigen::Vector3d& query, double max_distance,
                                const std::vector<Eigen::Vector3d>& normals, double min_cosine,
                                bool either_sign) const;

private:
    struct Grid;
    const Mesh& mesh_;
    std::unique_ptr<Grid> grid_;
};

}  // namespace symmetry
