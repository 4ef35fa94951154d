// Stage 0 (beyond the paper): the resolution the pipeline works at.  The paper's stages
// see the surface through a fixed number of samples (§5) and a verification tolerance of
// about 1 % of the diagonal; a scan of a million faces carries detail far below both, and
// verifying it vertex by vertex costs time in proportion to the tessellation instead of the
// symmetries (§6 claims cost that grows with the output).  A large input is therefore
// analysed on a copy simplified by quadric edge collapse (Garland and Heckbert 1997, the
// "Quadric Edge Collapse Decimation" of MeshLab, from vcglib; a large input in two halves at
// once, one per core, since a collapse is sequential), and only what is reported
// is carried back to every input vertex: its patches, and its deviation measured on the
// input surface itself.  A large point cloud is likewise analysed on a subset of its points
// chosen by Poisson-disk pruning (vcglib's, which MeshLab's "Point Cloud Simplification"
// runs): evenly spread, so that every part of the surface keeps its share of points.
#pragma once

#include "mesh.h"

#include <memory>
#include <vector>

namespace symmetry {

struct WorkingMeshOptions {
    /// An input with more vertices than this is analysed on a copy simplified to about this
    /// many (a point cloud: on about this many of its points); 0 analyses every input at its
    /// own resolution.  At 50,000 vertices the mean edge
    /// is about 0.3 % of the diagonal of a compact model: several edges per verification
    /// tolerance and curvature radius at their defaults (1 %).
    int max_vertices = 50000;
    /// Collapses that would leave triangles of lower quality (radius ratio, 0..1) are
    /// penalised: vcglib's QualityThr, MeshLab's default.
    double min_triangle_quality = 0.3;
    /// An input of at least this many faces is simplified as two halves at once (one per
    /// core), the cut between them held, and then the strip along the cut.  A smaller one is
    /// simplified whole on one core: it takes under a second, and on a copy that keeps few of
    /// its faces the seam's tessellation weighs more (measured with `--working-fraction 0.5`).
    int min_faces_to_halve = 100000;
    /// The strip along the cut that the last pass simplifies, in edges either side of it.
    int seam_rings = 3;
    /// A coarse mesh is refined only if it is faceted as CAD parts are, its edges flat or
    /// creased: fewer than this share of its interior edges bend smoothly...
    double max_smooth_edge_share = 0.5;
    /// ...their faces' normals between these two angles apart, in degrees (a coarse smooth
    /// surface, a decimated scan or an icosphere, bends by a few degrees at every edge).
    double flat_edge_degrees = 1.0;
    double crease_edge_degrees = 20.0;
    /// A refined copy (refined_copy_within) holds about this many vertices at most: where
    /// splitting down to the edge asked for would give more, the longest edge kept grows (and
    /// the curvature ball with the median edge).  Capped by max_vertices when that is set.
    int max_refined_vertices = 30000;
    /// ...tried this many times, the edge grown each time by the square root of the excess.
    int refinement_attempts = 4;
    /// A point cloud's subset: the Poisson-disk radius is corrected this many times at most...
    int poisson_attempts = 6;
    /// ...until the subset holds max_vertices points within this fraction.
    double poisson_count_tolerance = 0.05;
};

/// A copy of `input` simplified to about `target_vertices` vertices by quadric edge
/// collapse that preserves the topology (no handles or components appear or vanish) and
/// flips no face normal by more than 45 degrees, with the same setup as build_mesh gives.
/// From options.min_faces_to_halve faces on, the two halves of the input either side of a
/// plane are simplified at once, one per core, and then the strip along the cut
/// (options.seam_rings): the copy is the same at any thread count.
std::unique_ptr<Mesh> simplified_copy(const Mesh& input, int target_vertices, const WorkingMeshOptions& options);

/// A copy of `input` whose edges longer than `max_edge` are split at their midpoints until
/// none is, with the same setup as build_mesh gives: a coarse tessellation (the long thin
/// triangles CAD exports lay over flat faces) made fine enough for the curvature ball, its
/// surface unchanged.  Every input vertex is a vertex of the copy.  nullptr if a pass would
/// leave more than `max_vertices` (0: no limit).
std::unique_ptr<Mesh> refined_copy(const Mesh& input, double max_edge, int max_vertices = 0);

/// The share of the mesh's interior edges (two faces, face-face adjacency computed) whose
/// faces' normals lie between options.flat_edge_degrees and crease_edge_degrees apart: the
/// edges where a coarse smooth surface bends, which a CAD part's flat faces and creases lack.
double smooth_edge_share(const Mesh& mesh, const WorkingMeshOptions& options);

/// refined_copy with the longest edge grown until the copy holds at most about
/// options.max_refined_vertices (and max_vertices, if set), within refinement_attempts;
/// nullptr if none came within four times that.
std::unique_ptr<Mesh> refined_copy_within(const Mesh& input, double max_edge, const WorkingMeshOptions& options);

/// The indices, increasing, of about `target_points` of the vertices of `cloud` (a mesh of
/// points alone, covering `area`) spread evenly over it by Poisson-disk pruning (vcglib's),
/// within options.poisson_count_tolerance unless poisson_attempts run out.  Deterministic
/// for a given `seed`.
std::vector<int> poisson_disk_subset(const Mesh& cloud, int target_points, double area, unsigned seed,
                                     const WorkingMeshOptions& options);

/// For every vertex of `fine`, the index of the nearest vertex of `coarse`.
std::vector<int> nearest_vertices(const Mesh& fine, const Mesh& coarse);

}  // namespace symmetry
