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

struct Orientation {
    int flipped_faces = 0;   ///< faces turned
    bool orientable = true;  ///< false when a component is not (a Möbius band): the mesh is left as it was
};

/// Orients every connected component of the mesh (face-face adjacency computed)
/// coherently, a closed one outward; recomputes the adjacency when a face turned.
/// Normals are not updated.
Orientation orient_components(Mesh& mesh);

}  // namespace symmetry
