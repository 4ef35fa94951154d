// The core's own triangle mesh, in double precision whatever the host's scalar is.
// Every host (pymeshlab in double, the MeshLab GUI and meshlabserver in float, a
// numpy caller) copies its mesh into this type, so the pipeline is written once
// and the host's mesh is never touched until detection has succeeded.
#pragma once

#include <vcg/complex/complex.h>

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

namespace symmetry {

class Vertex;
class Face;
struct UsedTypes : public vcg::UsedTypes<vcg::Use<Vertex>::AsVertexType, vcg::Use<Face>::AsFaceType> {};
class Vertex : public vcg::Vertex<UsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::vertex::VFAdj,
                                  vcg::vertex::Mark, vcg::vertex::BitFlags> {};
class Face : public vcg::Face<UsedTypes, vcg::face::VertexRef, vcg::face::Normal3d, vcg::face::FFAdj,
                              vcg::face::VFAdj, vcg::face::Mark, vcg::face::BitFlags> {};
class Mesh : public vcg::tri::TriMesh<std::vector<Vertex>, std::vector<Face>> {};

/// Thrown for input the pipeline cannot work on; what() is a sentence for the user.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// What build_mesh did to its copy so that the pipeline sees one surface (input_repair.h).
struct MeshRepairs {
    /// Per row of V: the row whose vertex stands for it (itself but for welded duplicates).
    std::vector<int> row_at_same_position;
    int welded_vertices = 0;  ///< rows welded onto another at the same position (a soup's, a repeated face's)
    int repeated_faces = 0;   ///< faces dropped as copies of another over the same positions, turned the same way
    int back_faces = 0;       ///< faces dropped as the other side of a double-sided surface (turned the other way)
    int flipped_faces = 0;    ///< faces turned to orient each component coherently (and outward)
    bool orientable = true;   ///< false: a component could not be oriented and was left as it was
    /// Per face of the built mesh: its row of F (degenerate faces are dropped, so rows skip).
    std::vector<int> face_of_input;
};

/// Builds the core mesh from vertex positions (#V by 3) and triangles (#F by 3
/// indices into V), rejecting what the pipeline cannot handle with an InputError:
/// no vertices, no faces (a point cloud), non-finite coordinates, indices out of
/// range.  A triangle soup's vertices at the same position are welded, repeated faces and
/// the back sides of double-sided surfaces dropped, and each component's faces oriented
/// coherently (input_repair.h; `repairs` says what was done).  Degenerate
/// faces (repeated index or zero area) are dropped, as are vertices no face
/// references, because neither carries surface; if nothing remains the mesh is
/// rejected.  Face-face and vertex-face adjacency, normals and the bounding box are
/// computed.  `vertex_of_input` receives, for every vertex of the result, its row in
/// V, so outputs can be written back to the host mesh (and, through
/// repairs->row_at_same_position, to the rows welded onto it).
void build_mesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Mesh& mesh,
                std::vector<int>& vertex_of_input, MeshRepairs* repairs = nullptr);

/// Total surface area of the mesh.
double surface_area(const Mesh& mesh);

}  // namespace symmetry
