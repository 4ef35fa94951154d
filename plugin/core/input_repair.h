// Two ways a file can write one surface so that the pipeline would not see it as one, and
// what the core does about them on its own copy (the host's mesh is never changed):
//
// - A triangle soup (every triangle with its own three vertices, as STL files and many
//   numpy pipelines write them): no two faces share an edge, so region growing (§4)
//   cannot cross from one triangle to the next and the curvature tensor (§2) sees no
//   dihedral angle.  Vertices at exactly the same position are welded into one, as
//   MeshLab's STL import and Cleaning and Repairing > Remove Duplicate Vertices do.
//   Only a soup is welded: a mesh whose vertices are split only along some edges (flat
//   shading groups, texture seams) is a set of parts the pipeline already relates as
//   components, and welding it joins them at creases where growth stops (a low-poly
//   airliner of 122 such parts lost its exact mirror plane when welded).
// - Faces turned both ways (from exporters and repairs): where the orientation changes
//   the vertex normals cancel, and the frames of the signatures (§2) and the normal test
//   of region growing disagree between copies.  Each connected component is oriented
//   coherently (vcglib's OrientCoherentlyMesh, as Cleaning and Repairing > Re-Orient all
//   faces coherently does), then turned as a whole outward when it is closed (positive
//   signed volume), or else to the orientation most of its area had.
//
// - Every triangle stored twice (double-sided surfaces, as shape collections and many CAD
//   and game exports store them: once more with the opposite orientation, or the same
//   face repeated): each edge is shared by four faces, so the mesh is non-manifold
//   everywhere, the two sides' vertex normals cancel, and the tensor counts every edge
//   twice.  One copy of each triangle is kept (the first in the file); the corners of the
//   copies dropped are welded onto the kept face's corners at the same position, so a back
//   side with vertices of its own leaves no crack where the kept faces alternate sides.
//
// A mesh without duplicates, oriented coherently and outward, is left exactly as it is.
#pragma once

#include "mesh.h"

#include <Eigen/Core>
#include <vector>

namespace symmetry {

/// Whether most faces (more than half) have three corners that no other face uses.
bool is_triangle_soup(const Eigen::MatrixX3i& F, Eigen::Index vertex_count);

/// For every row of V, the first row at exactly the same position (the row itself for
/// all but duplicates).
std::vector<int> rows_at_same_position(const Eigen::MatrixX3d& V);

struct RepeatedFaces {
    std::vector<int> kept;  ///< the faces given, less the copies (in their order)
    int repeated = 0;       ///< copies dropped that turn the same way as the face kept
    int back = 0;           ///< copies dropped that turn the other way: a double-sided surface's back
};

/// Among `faces` (rows of F, each with three corners at distinct positions), those that
/// cover the same three positions as an earlier one, either way round.  `position` gives
/// each row of V the first row at its position (rows_at_same_position).  The corners of a
/// dropped copy are welded in `row_at_same_position` (per row: the row that stands for it)
/// onto the kept face's corners, each row onto the lowest row it is welded with.
RepeatedFaces drop_repeated_faces(const Eigen::MatrixX3i& F, const std::vector<int>& faces,
                                  const std::vector<int>& position, std::vector<int>& row_at_same_position);

struct Orientation {
    int flipped_faces = 0;   ///< faces turned
    bool orientable = true;  ///< false when a component is not (a Möbius band): the mesh is left as it was
};

/// Orients every connected component of the mesh (face-face adjacency computed)
/// coherently, a closed one outward; recomputes the adjacency when a face turned.
/// Normals are not updated.
Orientation orient_components(Mesh& mesh);

}  // namespace symmetry
