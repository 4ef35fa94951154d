// Symmetrization (the paper's §7, future work; issue 9): an approximately symmetric patch
// pair moved towards its exactly symmetric average.  A use of the detected symmetries,
// after detection; beyond the paper, which names it as a use of the symmetry graph.
//
// For a detected T mapping source patch P onto target patch Q, a vertex p of P lands at
// T(p), at some distance from the surface, nearest to c.  Moving p so that its image
// goes half-way to c, and the surface near c half-way to T(p) (Q's vertices by the same
// rule under T⁻¹), meets both sides at their average: the deviation of the pair shrinks,
// and a perfectly symmetric pair does not move.  Each pass measures on the surface the
// previous one left (Jacobi steps: every displacement of a pass is computed first, then
// applied).  A vertex moves under the most significant symmetry it belongs to (the
// detection's vertex_symmetry_id), as its deviation is measured; vertices in no symmetry,
// and in continuous families (no single T), do not move.
#pragma once

#include "detection.h"

#include <Eigen/Core>

namespace symmetry {

struct SymmetrizationOptions {
    /// Fraction of the way to the symmetric average each vertex moves in a pass: 0 leaves
    /// the mesh as it is, 1 moves both sides to their average.  In [0, 1].
    double strength = 1;
    /// Passes, each measured on the surface the previous one left: one pass leaves the
    /// error of interpolating the other side's surface, a few remove most of it.  1 to 100.
    int iterations = 3;
    /// A vertex moves only where its image lands within this multiple of the detection's
    /// verification tolerance of the surface (the correspondence is not trusted beyond).
    double max_distance_in_tolerances = 2;

    /// Throws InputError, with a sentence naming the parameter, for values outside their range.
    void validate() const;
};

struct SymmetrizationResult {
    Eigen::MatrixX3d V;          ///< the moved positions (rows of the input V)
    int moved_vertices = 0;      ///< vertices in a discrete symmetry that moved
    double rms_before = 0;       ///< RMS deviation of those vertices before, fraction of the diagonal
    double rms_after = 0;        ///< ...and after the last pass
};

/// Symmetrizes the mesh (V, F) under the discrete symmetries of `detected` (found on this
/// very mesh, so that its patches are rows of V); `verification_tolerance` is detection's
/// (fraction of the diagonal).  Throws InputError for options out of range or a result
/// that does not belong to the mesh.
SymmetrizationResult symmetrize(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const DetectionResult& detected,
                                double verification_tolerance, const SymmetrizationOptions& options);

}  // namespace symmetry
