// Stage 7a (§4): one side of a symmetric patch pair, grown over the mesh from a seed
// vertex: "we look at the one-ring neighbors of p_i, apply T_k, and check whether the
// distance of the transformed points to the surface around p_j is below a given error
// threshold.  If so, we add them to the current patch."
#pragma once

#include "mesh.h"
#include "surface_query.h"
#include "transformation_space.h"

#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

namespace symmetry {

/// The mesh as region growing walks it, read once per mesh: vertex positions, the
/// vertices and faces around every vertex (compressed rows), and per-face data.
struct MeshNeighbourhoods {
    std::vector<Eigen::Vector3d> positions;
    std::vector<int> neighbour_offsets, neighbours;  ///< neighbours of v: [offsets[v], offsets[v+1])
    std::vector<int> face_offsets, faces_around;     ///< faces with v as a corner, same layout
    std::vector<std::array<int, 3>> faces;           ///< corners of every face (deleted faces: -1)
    std::vector<Eigen::Vector3d> face_normals;       ///< unit, outward
    std::vector<double> face_areas;
    /// A third of the area of the faces around each vertex: the surface a vertex stands
    /// for, so that a fit over vertices weighs the surface and not its tessellation.
    std::vector<double> vertex_areas;
    /// Connected components over mesh edges: the component of every vertex, and the
    /// vertices of component c in members[member_offsets[c] .. member_offsets[c+1]).
    std::vector<int> component_of;
    std::vector<int> member_offsets, members;
    std::vector<double> component_areas;
    /// Whether a component has border edges: an open surface, whose faces may face either
    /// way (a wing modelled as a single sheet), so normals are compared without their sign.
    std::vector<char> component_open;
    /// A point cloud's, empty for a mesh: per point, the surface variation λ0 / (λ0 + λ1 +
    /// λ2) of the points around it (itself and its neighbours), and its median over the
    /// cloud.  It is 0 on a plane and grows with curvature and noise, and most where the
    /// neighbours straddle a sharp edge: there a point's normal is a plane fitted across the
    /// edge, tilted between the faces, and no normal of the surface.
    std::vector<double> surface_variation;
    double median_surface_variation = 0;

    int vertex_count() const { return int(positions.size()); }
};
MeshNeighbourhoods mesh_neighbourhoods(const Mesh& mesh);

/// A point cloud walked the same way: its neighbours are those of the symmetric
/// `neighbours`-nearest graph (point_cloud.h), and each point is a face of its own, a disc
/// with corners (i, i, i), the point's normal and the area it stands for, so that a patch's
/// area and a landing face mean for a cloud what they mean for a mesh (SurfaceQuery's discs
/// answer with the same index).  Normals are oriented (point_cloud.h): no part is open.
MeshNeighbourhoods cloud_neighbourhoods(const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        const std::vector<double>& areas, int neighbours);

/// What counts as debris (scanner specks, stray triangles): the smallest connected
/// components that together hold at most `area_share` of the area, each of them smaller
/// than `max_component_area`.  The second bound keeps a part repeated many times (120
/// window sills of 0.03 % of a facade each) from being taken for debris because its
/// copies are small; a speck is smaller than anything the curvature ball can see.
struct DebrisRule {
    double area_share = 0;               ///< fraction of the mesh's area; 0: nothing is debris
    double max_component_area = INFINITY; ///< absolute units
};

/// Flags, per connected component, those that are not debris.  Every component is
/// flagged when all of them would be debris.
std::vector<char> components_beyond_debris(const MeshNeighbourhoods& mesh, const DebrisRule& debris);

/// The median length of the mesh's edges, leaving out those of its debris (by default,
/// nothing is debris: every edge).
double median_edge_length(const MeshNeighbourhoods& mesh, const DebrisRule& debris = {});

/// Area of the faces whose three corners are all in `vertices` (flagged in `member`).
/// Visits only the faces around those vertices, so it costs O(|vertices|), not O(F).
double patch_area(const MeshNeighbourhoods& mesh, const std::vector<int>& vertices, const std::vector<char>& member);
/// patch_area of `vertices`, flagged in `scratch` (all zero, one per mesh vertex) for the
/// call and cleared again.
double area_of(const MeshNeighbourhoods& mesh, const std::vector<int>& vertices, std::vector<char>& scratch);

struct RegionGrowingOptions {
    double tolerance = 0;  ///< largest distance of T(v) to the surface, absolute units
    /// Largest angle, in degrees, between T's image of a face normal around v and the
    /// normal of the surface where T(v) lands.  Normals must agree as well as positions,
    /// or a thin plate's two sides, or a surface crossing another, would match.
    double normal_agreement_degrees = 45;
};

/// Where T maps vertex v, as region growing accepts it: the nearest point within
/// `max_distance` of T(v) on a face whose normal agrees (cosine at least
/// `min_normal_cosine`) with T's image of the normal of one of the faces around v, among
/// the faces as near as the nearest one; up to sign when `any_open` (some component of the
/// mesh is an open sheet, which may face either way).  found=false if there is none.
/// `normals` is work space.
ClosestPoint facing_landing(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, int v,
                            const Transformation& T, double max_distance, double min_normal_cosine, bool any_open,
                            std::vector<Eigen::Vector3d>& normals);

/// Whether some connected component of the mesh is open (has a boundary).
bool any_open_component(const MeshNeighbourhoods& mesh);

/// What a refit between growth steps reports (see RegionGrower::grow).
enum class RefitOutcome { Unchanged, Refitted, Hopeless };

/// The state of one side of one candidate symmetry: which vertices are in a patch,
/// which were tried and rejected, and for each accepted vertex its signed deviation
/// and the face its image landed on.
class RegionGrower {
public:
    RegionGrower(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, const RegionGrowingOptions& options);

    /// Whether T maps vertex v onto the surface: T(v) lies within the tolerance of it,
    /// and T maps the normal of at least one face around v onto the normal where T(v)
    /// lands (up to sign where either side is an open surface).  One face suffices so that growth crosses sharp creases, where the vertex
    /// normal is an average that agrees with neither side.  With `allowed_faces`, T(v)
    /// must also land on one of those faces.  Records the deviation and landing face.
    bool accepts(int v, const Transformation& T, const std::vector<char>* allowed_faces);

    /// Called with the patch so far each time it has doubled; may refine T in place.
    using Refit = std::function<RefitOutcome(const std::vector<int>& patch, Transformation& T)>;

    /// Breadth-first growth from `seed` over mesh edges.  After a refit the border
    /// rejected under the old transformation is tried again.  Returns the patch (empty
    /// if the seed itself fails or is already in a patch); sets `hopeless` when a refit
    /// said so, in which case the patch is returned as grown so far.
    std::vector<int> grow(int seed, Transformation& T, const std::vector<char>* allowed_faces, const Refit& refit,
                          bool& hopeless);

    /// Marks the vertices of a rejected component as tried, so that later seeds inside
    /// it do not grow it again (they start from the same transformation and would).
    void forbid(const std::vector<int>& patch);

    bool in_patch(int v) const { return state_[size_t(v)] == kInPatch; }
    bool tried(int v) const { return state_[size_t(v)] != kUntried; }
    double deviation(int v) const { return deviation_[size_t(v)]; }
    /// Per mesh vertex: the signed deviation recorded when it was last accepted.
    const std::vector<double>& deviations() const { return deviation_; }
    int landing_face(int v) const { return landing_face_[size_t(v)]; }

private:
    enum : char { kUntried = 0, kInPatch = 1, kRejected = 2 };
    const MeshNeighbourhoods& mesh_;
    const SurfaceQuery& surface_;
    double tolerance_;
    double min_normal_cosine_;
    std::vector<char> state_;
    std::vector<double> deviation_;
    std::vector<int> landing_face_;
    bool any_open_;
    std::vector<Eigen::Vector3d> normals_;  // work space of accepts()
};

}  // namespace symmetry
