// Closest-point queries on the mesh, shared by verification (§4) and the deviation
// output: vcglib's uniform grid over the faces does the search.
#pragma once

#include "mesh.h"

#include <Eigen/Core>
#include <cstdint>
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
    /// The mesh must outlive the query.  The grid has `cells_per_face` cells per face (vcg's
    /// default is one): a surface fills few of a grid's cells, so with one per face each
    /// filled cell holds many faces, and every query tests them all.  Region growing asks
    /// one query per vertex, many times over: a finer grid pays there.
    explicit SurfaceQuery(const Mesh& mesh, double cells_per_face = 1);
    /// A point cloud as a surface of discs (surfels): disc i is centred on points[i],
    /// orthogonal to normals[i] (unit, outward), of radius radii[i].  Answers name the disc
    /// by its point's index in `face`.  The arrays are copied.  Each query measures the
    /// discs of the `candidate_discs` nearest centres: a disc reaches no farther than its
    /// radius, a few spacings of the cloud, so the nearest disc is among them.
    SurfaceQuery(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                 const std::vector<double>& radii, int candidate_discs = 16);
    ~SurfaceQuery();
    /// The closest point of the surface within `max_distance` of `query`; found=false if none.
    ClosestPoint closest(const Eigen::Vector3d& query, double max_distance) const;

    /// Where a point lands on the surface for region growing, from one grid search:
    /// the nearest face within `max_distance`, and among the faces at most `tie` farther
    /// than it, the nearest one whose normal n agrees with one of `normals` (n·m >=
    /// min_cosine: `facing`; |n·m| >= min_cosine: `facing_either_sign`).  Where several
    /// faces meet at the closest point (a crease, or separate parts that touch there), the
    /// nearest face alone may face another way than the one that matches.  One search for
    /// all three costs about as much as closest() alone.
    struct Landing {
        ClosestPoint nearest, facing, facing_either_sign;
    };
    Landing landing(const Eigen::Vector3d& query, double max_distance, double tie,
                    const std::vector<Eigen::Vector3d>& normals, double min_cosine) const;

    struct Grid;  // a mesh's faces as searched (surface_query.cpp)

private:
    std::vector<ClosestPoint> nearest_discs(const Eigen::Vector3d& query) const;
    struct Discs;
    const Mesh* mesh_ = nullptr;
    std::uint64_t id_ = 0;  // names the surface to the grid search's per-thread marks
    std::unique_ptr<Grid> grid_;    // a mesh's faces
    std::unique_ptr<Discs> discs_;  // or a cloud's discs
};

/// The triangle mesh (V, F) itself, searchable, answering with rows of F: for the uses of a
/// result (reduction, consistent editing), which work on the input's rows, not on the
/// pipeline's copy.  Built by build_mesh (degenerate faces are never found).
class SurfaceOfRows {
public:
    SurfaceOfRows(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
    ~SurfaceOfRows();
    /// The closest point within `max_distance`, its `face` a row of F; found=false if none.
    ClosestPoint closest(const Eigen::Vector3d& query, double max_distance) const;

private:
    Mesh mesh_;
    std::vector<int> row_of_face_;
    std::unique_ptr<SurfaceQuery> query_;
};

}  // namespace symmetry
