// Consistent editing (the paper's §5 and Figure 7(d); issue 9): an edit made on one copy is
// carried to every copy a detected symmetry relates it to.
//
// The edit is a displacement field d = edited - original over the vertices (same mesh, same
// connectivity).  For a discrete symmetry T mapping patch P onto Q, a vertex q of Q lands
// under T⁻¹ on a face of the original surface; where a corner of that face is displaced, q
// receives the displacement interpolated there (zero at corners that are not), turned by T's
// linear part (rotated, mirrored, scaled): the copy moves as the original moved.  Each
// symmetry is used both ways, and passes repeat on what the previous one carried, so an edit
// travels along a chain (copy 0 to 1 to 2 of a row).  Every displacement remembers the
// transformation that brought it from the user's edit, and a vertex refuses one that would
// bring it back onto itself: the unedited ring around the edit stays unedited, though the
// copy beside it now carries the edit.  Vertices the user moved keep their edited position;
// continuous families (no single T) carry nothing.
#pragma once

#include "detection.h"

#include <Eigen/Core>

namespace symmetry {

struct EditingOptions {
    /// A vertex counts as edited when it moved by more than this, fraction of the diagonal
    /// (below: rounding of a round trip through single precision).
    double min_edit = 1e-7;
    /// A vertex maps back onto the surface only within this multiple of the detection's
    /// verification tolerance.  In (0, 10].
    double max_distance_in_tolerances = 2;
    /// Passes of carrying, each from what the previous carried (the longest chain of copies
    /// an edit travels).  1 to 64.
    int max_passes = 16;

    /// Throws InputError, with a sentence naming the parameter, for values outside their range.
    void validate() const;
};

struct EditingResult {
    Eigen::MatrixX3d V;        ///< the edited mesh with the edit carried to every copy
    int edited_vertices = 0;   ///< vertices the user moved
    int carried_vertices = 0;  ///< vertices that received the edit
    int passes = 0;            ///< passes that carried something
};

/// Carries the edit (V_edited - V_original, on the mesh F) to the copies that `detected`
/// (found on the original) relates; `verification_tolerance` is detection's (fraction of
/// the diagonal).  Throws InputError when the two meshes differ in size, nothing was
/// edited, options are out of range or the result belongs to another mesh.
EditingResult carry_edit(const Eigen::MatrixX3d& V_original, const Eigen::MatrixX3i& F,
                         const Eigen::MatrixX3d& V_edited, const DetectionResult& detected,
                         double verification_tolerance, const EditingOptions& options);

}  // namespace symmetry
