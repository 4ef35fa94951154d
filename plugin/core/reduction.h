// Symmetry-based reduction (the paper's §5 and Figure 7(c); issue 9): the faces that are
// copies of others are removed, and what is kept, with the transformations that
// re-instantiate each copy from it, rebuilds the model.
//
// A face f of a discrete symmetry T's target patch is a copy when every point of it (its
// corners and its centre), mapped back by T⁻¹, lands within the tolerance on the surface.
// If all land on kept faces, f is rebuilt as T applied to them; if they land on a face
// removed before, that face's own instance M maps them on back, and f is rebuilt as
// (T ∘ M) applied to kept faces.  So a chain of one generator rebuilds a whole orbit: the
// sixth blade of a wingnut is the first one turned five times.  The faces a copy is rebuilt
// from are locked: they stay, and can no longer be removed.  A face whose points come back
// to itself (on a mirror's plane, on a rotation's axis) stays.  Each symmetry is used both
// ways (T on its target patch, then T⁻¹ on its source), and its faces are taken in the
// order of their orbit (along a translation, round a rotation's axis, from one side of a
// mirror), so that an orbit is rebuilt from one member rather than from every other.
// Continuous families have no finite set of copies and are left whole.
#pragma once

#include "detection.h"

#include <Eigen/Core>
#include <vector>

namespace symmetry {

struct ReductionOptions {
    /// A face is a copy only where its corners and centre, mapped back, land within this
    /// multiple of the detection's verification tolerance of the surface (the image of a
    /// kept face then lies that close to the face it replaces).  In (0, 10].
    double max_distance_in_tolerances = 1;
    /// Most symmetries composed into one instance (a chain of one rotation rebuilds an orbit
    /// of that many copies); each step adds the transformations' error.  1 to 64.
    int max_chain_length = 16;
    /// A rotation by less than this is taken as a translation when ordering a symmetry's
    /// faces along its orbit (a row's copies are often turned by a rounding error).  Radians.
    double min_rotation_angle = 0.05;

    /// Throws InputError, with a sentence naming the parameter, for values outside their range.
    void validate() const;
};

/// A removed copy: `transform` applied to the kept `faces` rebuilds it.
struct ReducedInstance {
    /// The detected symmetries composed, as letters: +(k+1) is DetectionResult::symmetries[k],
    /// -(k+1) its inverse (the basis words' convention); transform = T(word[0]) ∘ T(word[1]) ∘ ...
    std::vector<int> word;
    Transformation transform;
    std::vector<int> faces;  ///< rows of F, all kept, increasing
    int removed_faces = 0;   ///< rows of F this copy stands for
};

struct ReductionResult {
    std::vector<int> kept_faces;             ///< rows of F, increasing
    std::vector<ReducedInstance> instances;  ///< in the order they were first used
    double size_ratio = 1;                   ///< kept faces / faces of the input
    /// Largest distance between the input and its reconstruction (reconstruct()), either
    /// way, at vertices and face centres, as a fraction of the diagonal.
    double reconstruction_error = 0;
};

/// Reduces the mesh (V, F) under the discrete symmetries of `detected` (found on this very
/// mesh); `verification_tolerance` is detection's (fraction of the diagonal).  Throws
/// InputError for options out of range or a result that does not belong to the mesh.
ReductionResult reduce_by_symmetry(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                   const DetectionResult& detected, double verification_tolerance,
                                   const ReductionOptions& options);

/// The model rebuilt from a reduction: the kept faces, then each instance's faces
/// transformed (every instance has vertices of its own).  Vertices no face uses are left out.
void reconstruct(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const ReductionResult& reduction,
                 Eigen::MatrixX3d& rebuilt_V, Eigen::MatrixX3i& rebuilt_F);

}  // namespace symmetry
