// Continuous symmetries (beyond the paper, whose §6 names them as its limitation: "Continuous
// symmetries, such as those found in rotational or helical surfaces, lead to smooth curves in
// transformation space and are currently not detected by our method").
//
// A surface of revolution, a cylinder, an extrusion, a helix, a plane or a sphere maps onto
// itself under a whole continuum of transformations, so its pairs vote all along a curve or
// sheet of Γ and mean shift finds one mode after another on it: each verifies, and they fill
// every result slot.  Here a verified candidate whose patch pair is slippable (Gelfand and
// Guibas 2004: some rigid motion moves every point tangentially to the surface) and whose
// transformation maps that motion's axis onto itself is recognised as one member of a
// continuous family; the family is reported once, with its kind and axis, and the other
// members are skipped without verification.
#pragma once

#include "region_growing.h"
#include "signatures.h"
#include "surface_query.h"
#include "transformation_space.h"

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace symmetry {

/// The kinds of continuous symmetry, numbered as in the filter's `continuous_kinds` output.
enum class ContinuousKind {
    Discrete = 0,       ///< no continuous symmetry
    Rotational = 1,     ///< surfaces of revolution, cones; a cylinder (whose translations run along the same axis)
    Translational = 2,  ///< extrusions of a non-circular profile
    Helical = 3,        ///< screws, helical tubes
    Planar = 4,         ///< a flat patch
    Spherical = 5       ///< a patch of a sphere
};

/// A rigid motion as a velocity field: velocity(p) = omega × p + v.
struct Motion {
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    Eigen::Vector3d velocity(const Eigen::Vector3d& p) const { return omega.cross(p) + v; }

    /// The unit turn about the line through `point` along the unit `direction`.
    static Motion turn_about(const Eigen::Vector3d& point, const Eigen::Vector3d& direction) {
        return {direction, -direction.cross(point)};
    }
};

struct ContinuousFamily {
    ContinuousKind kind = ContinuousKind::Discrete;
    /// Rotational, helical: a point on the axis.  Planar: a point on the plane.  Spherical:
    /// the centre.  Translational: the centroid of the patch.
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    /// The axis, the plane's normal or the translation direction (unit); zero for a sphere.
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
    double pitch = 0;              ///< helical: advance along the direction per full turn, absolute units
    double radius = 0;             ///< spherical: the sphere's radius
    double extent = 0;             ///< RMS distance of the patch from its centroid, absolute units
    /// Rotational: the family also slides along its axis (a cylinder), so shifts along the
    /// axis and flips of it are members too.
    bool slides_along_axis = false;
    std::vector<Motion> motions;   ///< the slippable motions that generate the family
    std::vector<int> vertices;     ///< the family's patch, increasing mesh vertex indices
};

/// How rough the surface the families are looked for on is, beyond its shape: what noise
/// (a scan's grain, or what presmoothing left of it) adds to every residual of a true family.
struct SurfaceRoughness {
    /// Typical sine of the angle between a face's normal and the mean normal of its corners
    /// (the median over the faces).
    double normal = 0;
    /// Typical distance of a vertex from the plane through its neighbours' centroid, along
    /// its normal (the median over the vertices), absolute units.
    double position = 0;
};
struct ContinuousFamilyOptions {
    /// A motion is slippable when the RMS of its normal speed over the patch is below this
    /// fraction of the speed of a unit motion of the patch normalised to unit radius: the
    /// sine of the average angle at which the motion leaves the surface (0.05: about 3°).
    double max_slippage = 0.05;
    /// On a point cloud, slippage leaves out the points whose surface variation exceeds the
    /// larger of this floor and `cloud_edge_variation_per_median` times the cloud's median:
    /// at a sharp edge a cloud's normal is fitted across the edge, and a band of such tilted
    /// normals along a box's caps kept its sides from sliding along it (measured: the slide
    /// moved the normals at 0.08-0.10 RMS, against a bound of 0.05, and at 0.001-0.003 without
    /// that band).  Measured surface variations: 0 on a clean box's faces and 0.02-0.13 along
    /// its edges (15 % of its points); up to 0.006 on a clean torus; a median of 0.011 on a
    /// torus with noise of 0.1 % of the diagonal.  Dimensionless.  A mesh's faces all count.
    double cloud_edge_variation_floor = 0.01;
    double cloud_edge_variation_per_median = 4;
    /// Helical rather than rotational when the advance along the axis per radian exceeds
    /// this fraction of the patch's radius.
    double min_helical_pitch = 0.02;
    /// Region growing of a family's patch: the largest angle, in degrees, between a face
    /// around a vertex and the direction in which each generating motion moves the vertex.
    double tangency_degrees = 5;
    /// A planar or spherical patch lies within this fraction of the verification tolerance
    /// of its plane or sphere: a gently bulging region lies within the tolerance of a plane
    /// without being one.
    double shape_tolerance = 0.1;
    /// The tangency angle for planes and spheres, in degrees: tighter, since a smooth
    /// model has flat-looking regions (around inflections) a few degrees from any plane.
    double shape_tangency_degrees = 2;
    /// Two families with axes (or normals) within this angle, in degrees, and within the
    /// verification tolerance of each other are the same family.
    double axis_agreement_degrees = 2;
    /// A family is reported only when each of its finite members (rotations by 45°, 90° and
    /// 180°; shifts by a tenth and a quarter of the patch's length; small turns and shifts
    /// of a plane) maps at least this fraction of its patch onto the surface (of the part
    /// that stays over the patch, for a finite family).  Slippage is
    /// a first-order, local property: a quarter-cylinder fillet or a scan's roughly tubular
    /// ear is slippable but not a rotational symmetry.  (Its members are still not
    /// reported as discrete symmetries.)
    double min_member_coverage = 0.8;
    /// ...and, for a surface of revolution, at least this fraction of its area.  Its patch
    /// grows onto every face normal to the axis (a turn slides such a face along itself
    /// locally), and a CAD part's flat face is a few large triangles: a small boss on a
    /// plate gives a patch whose vertices are mostly on the boss, where every turn maps
    /// them, and whose area is mostly the plate, which a turn carries off its outline.
    /// Lower than the vertex share: a hammer's handle keeps the head's underside beside it
    /// (a turn maps 77 % of that patch's area, 84 % of its vertices).
    double min_member_area_coverage = 0.5;
    /// ...with a median deviation below this fraction of the tolerance (as for a discrete
    /// symmetry, VerificationOptions::max_median_deviation): a bumpy torus turned about its
    /// axis stays within a coarse tolerance, but not closely.
    double max_member_median_deviation = 0.1;
    /// The same for planes and spheres, stricter: a smooth model is flat within a tenth of
    /// the tolerance over a few percent of its area around every inflection, and those
    /// regions deviate from their plane by 0.02-0.05 of the tolerance where a designed
    /// plane deviates by nothing.
    double max_shape_member_median_deviation = 0.02;
    /// A discrete symmetry whose patch lies on continuous families for at least this share
    /// of its vertices...
    double min_family_share = 0.9;
    /// ...is reported only if it covers at least this fraction of every family it touches
    /// (see drop_partial_family_relations in detection.cpp).
    double min_family_coverage = 0.8;
    /// ...unless it holds at least this share of the area of separate parts of the mesh
    /// (connected components), min_patch_area of them in all: it carries those parts whole.
    double min_whole_part_share = 0.8;
    /// A discrete symmetry that is a member of a rotational or helical family (a mirror
    /// through the axis of a wingnut's hub) and whose patch lies on that family's patch for at least this share of
    /// its vertices is that family, spilled a little onto the parts beside it: not reported.
    double min_member_share = 0.5;
    /// A member that is a surface of revolution's mirror composed with a turn
    /// (mirror_in_rotoreflection) has that mirror verified in its own right, with T held,
    /// from this many of the member's source vertices spread over its patch (a count): one
    /// seed grows a connected patch whole, the others start the components it misses.
    int mirror_seeds = 16;
    /// Where this many verified mirrors or more pass through one line and no rotational
    /// family about it was found, the vertices all of them map are tried for one (see
    /// Verifier::add_families_of_mirror_axes in detection.cpp; a count).  Two planes always
    /// meet in a line unless parallel: slippage on what both map, not their number, is the
    /// judge (a box's two mirrors meet in a line too, and its faces do not turn about it).
    size_t min_mirrors_through_axis = 2;
    /// ...and where the points they all map, and a turn about the line slides along, lean
    /// from the line by at least this much (mean_lean_from: the mean sine of the angle
    /// between normal and line).  Measured on the points of the lines tried: 0.70 on the
    /// wingnut's hub (clean and noisy clouds), at most 0.03 where a facade's two mirrors meet
    /// in the normal of its wall, whose faces a turn about any normal slides.
    double min_lean_from_mirror_axis = 0.25;
    /// The surface's roughness (surface_roughness); the pipeline measures it on the surface
    /// it analyses.  Each test above allows for it, in these units of it, so that a family
    /// on a noisy scan is recognised and a clean surface is judged as before (measured, face
    /// tilt and vertex offset: 0.011 and 0.00027 of the diagonal on a clean cylinder of 23,500
    /// faces; 0.16 and 0.00077 with noise of 0.1 % of the diagonal on its vertices, which no
    /// presmoothing took away)...
    SurfaceRoughness roughness;
    /// ...but only on a surface whose estimated noise (denoising.h) exceeds this fraction of
    /// the tolerance: a clean surface's roughness is its tessellation and curvature, not
    /// noise (measured: a clean scene of stretched triangles estimated at 0.022 of the
    /// tolerance, whose roughness let five spherical families through; noise of 0.05 % and
    /// 0.1 % of the diagonal estimated at 0.09 and 0.15).
    double min_noise_for_roughness = 0.05;
    /// Above this fraction, no allowance: a bump and a family are no longer told apart within
    /// the tolerance, and the clean bounds apply (measured: a cloud of the scene with noise of
    /// 0.5 % on both copies and 0.1 % on every point, estimated at 0.38, gave 11 spherical
    /// families of its bunny and cow with the allowance).
    double max_noise_for_roughness = 0.3;
    /// ...the RMS normal speed of a slippable motion per unit of face tilt (measured: 0.44 on
    /// that noisy cylinder, whose slippable motion showed 0.072 where max_slippage is 0.05;
    /// the next motion, not slippable, 0.44);
    double slippage_per_normal_roughness = 1.2;
    /// ...the tangency of a face, tested face by face, in units of the typical face tilt;
    double tangency_per_normal_roughness = 2;
    /// ...the largest distance of a patch from its plane, sphere or cylinder: the extreme of
    /// tens of thousands of noisy vertices (the typical offset is 0.7 of the noise's standard
    /// deviation, and the largest of 20,000 Gaussian values is 4.4 deviations);
    double extreme_per_position_roughness = 6.5;
    /// ...the RMS distance of a patch from its plane or sphere: the noise's standard
    /// deviation at a face's centroid is about 0.8 of the typical offset;
    double rms_per_position_roughness = 1.5;
    /// ...and the median deviation of a member (check_members), over both sides' noise.
    double median_per_position_roughness = 3;
    /// With those allowances, a surface that merely comes near a sphere passes for one (two
    /// regions of a noisy vase's bulb did).  Noise and shape differ in how they average out:
    /// the vertices' distance from the sphere, fitted to them by least squares, averaged over
    /// mesh neighbourhoods (`systematic_smoothing_iterations` rounds, as for a symmetry's
    /// systematic deviation), keeps at most this fraction of its RMS on a sphere (measured,
    /// noise of 0.1 % of the diagonal: 0.14-0.27 on a sphere's patches of 114-7164
    /// vertices; 0.40-0.54 on the vase's near-spheres of 149-533).  Planes are not tested so:
    /// their normal comes from slippage, not a least-squares fit, and a slightly tilted fit
    /// leaves a smooth residual on a true face (0.24-0.61 on a noisy box's faces).
    double max_systematic_share_off_sphere = 0.33;
    /// The same on a surface presmoothed for its noise (denoising.h, a noisy cloud's
    /// projection on local fits), whose noise was averaged once already, so what is left
    /// of it averages out less (measured, clouds with noise of 0.1 % of the diagonal: 0.32-0.43
    /// on a sphere's patches, which the bound above split into small families; 0.46-0.68 on
    /// the near-spheres of the planted scenes' clouds, and one at 0.38).
    double max_systematic_share_off_sphere_presmoothed = 0.45;
    bool presmoothed = false;  ///< the analysed surface was presmoothed; the pipeline sets it
    int systematic_smoothing_iterations = 4;  ///< rounds of averaging over mesh neighbours
};

/// Slippage analysis of a patch (Gelfand and Guibas 2004) and the family it belongs to,
/// with kind Discrete when no motion is slippable.  The patch must lie within
/// shape_tolerance × `tolerance` of its plane (planar) or sphere (spherical), which
/// slippage alone cannot see.
ContinuousFamily slippable_family(const MeshNeighbourhoods& mesh, const std::vector<int>& patch, double tolerance,
                                  const ContinuousFamilyOptions& options);

/// Whether T is one of the family's own members, which are not reported beside it:
/// - rotational: rotations about the axis and reflections through planes containing it
///   (T fixes the axis point by point), and the half-turns that flip the axis (a mirror
///   across a plane normal to the axis, if there is one, is a discrete symmetry of its own);
///   for a cylinder also every motion that maps the axis onto itself;
/// - helical: every motion that maps the axis onto itself;
/// - translational: motions that map the direction onto ± itself and move the patch's
///   centroid along it only; planar: those mapping the plane onto itself; spherical:
///   those fixing the centre.
/// `tolerance` (absolute) and `degrees` are how far T may be from exact: the verification
/// tolerance and axis_agreement_degrees for a refined T, more for a cluster's mode.
bool is_member(const ContinuousFamily& family, const Transformation& T, double tolerance, double degrees);

/// A rotational family's member that flips the axis by a reflection, other than the mirror
/// across the plane normal to the axis, is that mirror composed with a turn about the
/// axis (a rotoreflection).  Where the surface has that mirror, ICP on a noisy surface
/// drifts along the family and settles on such a member instead of it: this returns the
/// mirror, to be verified in its own right; nothing when T is not such a member (`degrees`
/// as for is_member).
std::optional<Transformation> mirror_in_rotoreflection(const ContinuousFamily& family, const Transformation& T,
                                                       double degrees);

/// A patch that slides along a rotational family's axis (a cylinder's side) is mapped onto
/// itself by every mirror normal to the axis, and ICP on it settles anywhere along the
/// axis; of the family's whole patch (its caps too) only the mirror through the middle
/// (family.point, as recorded) can map all.  This returns that mirror when T is another
/// mirror normal to the axis that moves the family's ends by more than the tolerance
/// (its plane off the middle by more than half of it); nothing otherwise
/// (`degrees` as for is_member).
std::optional<Transformation> mirror_through_middle(const ContinuousFamily& family, const Transformation& T,
                                                    double tolerance, double degrees);

/// A line that several mirror planes pass through, and which of the mirrors do.
struct MirrorAxis {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit
    std::vector<size_t> mirrors;                          ///< indices into the planes given
};

/// The lines that at least `min_mirrors` of the mirror planes n·x = d (rows n, d; n unit)
/// pass through, each line once: a plane passes through it when its normal is within
/// `degrees` of normal to the line and a point of the line within `tolerance` of it.  A
/// surface of revolution is mapped onto itself by the mirror across every plane through its
/// axis, so two or more such mirrors say where to look for its rotational family.
std::vector<MirrorAxis> lines_of_mirrors(const std::vector<Eigen::Vector4d>& planes, size_t min_mirrors,
                                         double tolerance, double degrees);

/// The families a sample that umbilic pruning (§2.1) discarded suggests, to be tried in
/// this order: for a flat sample (largest |κ| r below `flatness`) the plane through it,
/// then, if both its curvatures bend the same way, the sphere of its mean curvature (a
/// sphere larger than the ball); for any other, that sphere alone.  Their patches are left
/// empty, to be grown (grow_family_patch) and refined (slippable_family on the grown patch).
std::vector<ContinuousFamily> families_of_pruned_sample(const SurfaceSignature& sample, double radius,
                                                        double flatness);

/// The cylinder a sample suggests when one principal curvature vanishes (|κ| r below
/// `flatness`) and the other does not: its axis runs along the direction of the vanishing
/// curvature through the centre of the other, p − n/κ; its motions are the turn about the
/// axis and the slide along it.  Kind Discrete when the sample is not cylinder-like.  A
/// cone's or any ruled surface's sample suggests a wrong cylinder: grown, refined and
/// checked (see Verifier::add_cylinders_of_kept_samples) it fails.
ContinuousFamily cylinder_of_sample(const SurfaceSignature& sample, double radius, double flatness);

/// Whether every vertex of a rotational family's patch lies within shape_tolerance ×
/// `tolerance` of one cylinder about its axis: slippage alone takes a narrow band of a
/// cone or of a vase for a cylinder, since a short band slides along the axis nearly.
bool lies_on_cylinder(const MeshNeighbourhoods& mesh, const ContinuousFamily& family, double tolerance,
                      const ContinuousFamilyOptions& options);

/// Whether two families are one: same kind, axes within the agreement angle and tolerance.
bool same_family(const ContinuousFamily& a, const ContinuousFamily& b, double tolerance,
                 const ContinuousFamilyOptions& options);

SurfaceRoughness surface_roughness(const MeshNeighbourhoods& mesh);

/// How a family's finite members map its patch onto the surface.
struct FamilyCheck {
    double coverage = 0;                 ///< fraction of the patch mapped within the tolerance, worst member
    double area_coverage = 1;            ///< the same by area (faces at their centroids); 1 for a finite family
    double median_deviation = 0;         ///< median distance of the mapped vertices, worst member, absolute units
    Transformation best_member;          ///< the member that maps most of the patch (the family's representative)
    std::vector<double> deviation;       ///< per patch vertex: the smallest signed deviation under a member (0: none lands)
};

/// Applies finite members of the family (see min_member_coverage) to its patch;
/// `edge_length` is the surface's median edge (median_edge_length), absolute units.
FamilyCheck check_members(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, const ContinuousFamily& family,
                          double tolerance, double edge_length);

/// The area-weighted mean, over the patch's faces (a cloud's points), of the sine of the
/// angle between the normal and the unit `direction`: 0 on flat faces normal to it, 1 on a
/// cylinder about it.  A turn about a line slides flat faces normal to it as well as a turn
/// about any line parallel to it: only the patch's lean pins a surface of revolution's axis.
double mean_lean_from(const MeshNeighbourhoods& mesh, const std::vector<int>& patch, const Eigen::Vector3d& direction);

/// The vertices of `vertices` that grow_family_patch would take into the family's patch, in
/// their order: those around which some face is tangent to every generating motion (and
/// which lie on a plane's or a sphere's shape), without growing beyond them.
std::vector<int> tangent_vertices(const MeshNeighbourhoods& mesh, const ContinuousFamily& family,
                                  const std::vector<int>& vertices, double tolerance,
                                  const ContinuousFamilyOptions& options);

/// The family's whole patch: grown over the mesh from `seeds` through every vertex around
/// which some face is tangent to every generating motion (within tangency_degrees), and
/// for a plane or a sphere lies on it within the tolerance.  Increasing indices.
std::vector<int> grow_family_patch(const MeshNeighbourhoods& mesh, const ContinuousFamily& family,
                                   const std::vector<int>& seeds, double tolerance,
                                   const ContinuousFamilyOptions& options);

}  // namespace symmetry
