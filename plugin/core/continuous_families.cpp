#include "continuous_families.h"

#include "kd_tree.h"
#include "statistics.h"
#include "verification.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>

namespace symmetry {

namespace {

// The bounds of ContinuousFamilyOptions widened by the surface's roughness: a true family's
// residual is the noise, not zero.  Angles add as independent tilts (in quadrature),
// distances as a bias.  For slippage, of a motion whose RMS speed over the patch is `speed`:
// the noise tilts each face by about the roughness, which adds that much normal speed per
// unit of speed.
double slippage_bound(const ContinuousFamilyOptions& o, double speed) {
    return std::hypot(o.max_slippage, o.slippage_per_normal_roughness * o.roughness.normal * speed);
}
double tangency_bound(double max_sine, const ContinuousFamilyOptions& o) {
    return std::hypot(max_sine, o.tangency_per_normal_roughness * o.roughness.normal);
}
double shape_bound(const ContinuousFamilyOptions& o, double tolerance) {
    return o.shape_tolerance * tolerance + o.extreme_per_position_roughness * o.roughness.position;
}

double sine_of(double degrees) { return std::sin(degrees * M_PI / 180.0); }
double cosine_of(double degrees) { return std::cos(degrees * M_PI / 180.0); }

// The faces whose three corners are in the patch: centroid, unit normal, area.  Faces
// rather than vertices, because a vertex normal on a crease (a cylinder's rim) belongs
// to neither side and would make every motion look non-slippable.
struct PatchFaces {
    std::vector<Eigen::Vector3d> centroids, normals;
    std::vector<double> areas;
};

// On a noisy patch the largest distance says little about the shape: the RMS distance must
// stay within the noise as well (on a clean patch the bound on the largest implies it).
bool near_shape(const PatchFaces& faces, double total, const std::function<double(const Eigen::Vector3d&)>& distance,
                const ContinuousFamilyOptions& o, double tolerance) {
    double sum = 0;
    for (size_t i = 0; i < faces.areas.size(); ++i) {
        const double d = std::abs(distance(faces.centroids[i]));
        if (d > shape_bound(o, tolerance)) return false;
        sum += faces.areas[i] * d * d;
    }
    return std::sqrt(sum / total) <= o.shape_tolerance * tolerance + o.rms_per_position_roughness * o.roughness.position;
}

PatchFaces patch_faces(const MeshNeighbourhoods& mesh, const std::vector<int>& patch) {
    std::vector<char> member(size_t(mesh.vertex_count()), 0);
    for (int v : patch) member[size_t(v)] = 1;
    PatchFaces out;
    for (int v : patch)
        for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k) {
            const int f = mesh.faces_around[size_t(k)];
            const auto& c = mesh.faces[size_t(f)];
            if (c[0] != v || !member[size_t(c[1])] || !member[size_t(c[2])] || !(mesh.face_areas[size_t(f)] > 0)) continue;
            out.centroids.push_back((mesh.positions[size_t(c[0])] + mesh.positions[size_t(c[1])] + mesh.positions[size_t(c[2])]) / 3);
            out.normals.push_back(mesh.face_normals[size_t(f)]);
            out.areas.push_back(mesh.face_areas[size_t(f)]);
        }
    return out;
}

// The point of the line (p, d) nearest to q.
Eigen::Vector3d nearest_on_line(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& q) {
    return p + d * d.dot(q - p);
}

double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& q) {
    return (q - nearest_on_line(p, d, q)).norm();
}

// Two lines (point, unit direction) are one: parallel within `degrees` and the second's
// point within `tolerance` of the first line.
bool same_line(const Eigen::Vector3d& pa, const Eigen::Vector3d& da, const Eigen::Vector3d& pb,
               const Eigen::Vector3d& db, double tolerance, double degrees) {
    return std::abs(da.dot(db)) >= cosine_of(degrees) && distance_to_line(pa, da, pb) <= tolerance;
}

// One slippable motion: a translation when it hardly turns, a rotation about an axis
// otherwise, or a screw when it also advances along the axis.
void classify_single_motion(const Motion& m, const Eigen::Vector3d& centroid, double extent,
                            const ContinuousFamilyOptions& options, ContinuousFamily& family) {
    const double w = m.omega.norm();
    // A rotation about an axis many patch radii away is indistinguishable from a translation.
    if (w * extent < 0.1 * m.velocity(centroid).norm()) {
        family.kind = ContinuousKind::Translational;
        family.direction = m.v.normalized();
        family.point = centroid;
        return;
    }
    family.direction = m.omega / w;
    const double advance_per_radian = m.omega.dot(m.v) / (w * w);
    family.point = nearest_on_line(m.omega.cross(m.v) / (w * w), family.direction, centroid);
    if (std::abs(advance_per_radian) > options.min_helical_pitch * extent) {
        family.kind = ContinuousKind::Helical;
        family.pitch = 2 * M_PI * advance_per_radian;
    } else {
        family.kind = ContinuousKind::Rotational;
    }
}

// The sphere nearest to the patch's faces in the least-squares sense (Gauss-Newton from the
// centre the slippable turns share): on a noisy patch those turns are noisy too, and a
// centre a little off puts one side of the patch outside any tight bound.
void fit_sphere(const PatchFaces& faces, double total, const Eigen::Vector3d& start, ContinuousFamily& family) {
    Eigen::Vector3d centre = start;
    double radius = 0;
    for (int iteration = 0; iteration < 5; ++iteration) {
        radius = 0;
        for (size_t i = 0; i < faces.areas.size(); ++i) radius += faces.areas[i] * (faces.centroids[i] - centre).norm();
        radius /= total;
        // Residual (|c_i - x| - r) with gradient -(c_i - x)/|c_i - x| in x; r is eliminated above.
        Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
        Eigen::Vector3d Jtr = Eigen::Vector3d::Zero(), mean_direction = Eigen::Vector3d::Zero();
        for (size_t i = 0; i < faces.areas.size(); ++i) mean_direction += faces.areas[i] * (faces.centroids[i] - centre).normalized();
        mean_direction /= total;
        for (size_t i = 0; i < faces.areas.size(); ++i) {
            const Eigen::Vector3d d = faces.centroids[i] - centre;
            const Eigen::Vector3d g = -(d.normalized() - mean_direction);  // with r's dependence on x
            const double residual = d.norm() - radius;
            JtJ += faces.areas[i] * g * g.transpose();
            Jtr += faces.areas[i] * g * residual;
        }
        const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
        if (!step.allFinite()) break;
        centre += step;
        if (step.norm() < 1e-9 * radius) break;
    }
    radius = 0;
    for (size_t i = 0; i < faces.areas.size(); ++i) radius += faces.areas[i] * (faces.centroids[i] - centre).norm();
    family.point = centre;
    family.radius = radius / total;
}

// Least-squares centre x of rotations v_i = x × ω_i (each motion turns about x).
Eigen::Vector3d common_centre(const std::vector<Motion>& motions) {
    Eigen::MatrixXd A(3 * motions.size(), 3);
    Eigen::VectorXd b(3 * motions.size());
    for (size_t i = 0; i < motions.size(); ++i) {
        const Eigen::Vector3d& w = motions[i].omega;
        Eigen::Matrix3d cross;  // x × w = -[w]× x
        cross << 0, w.z(), -w.y(), -w.z(), 0, w.x(), w.y(), -w.x(), 0;
        A.block<3, 3>(3 * long(i), 0) = cross;
        b.segment<3>(3 * long(i)) = motions[i].v;
    }
    return A.colPivHouseholderQr().solve(b);
}

// Whether the patch's vertices lie off the sphere (fitted to them by least squares) by noise
// alone: their distance from it, averaged over neighbourhoods, shrinks as noise does (see
// ContinuousFamilyOptions::max_systematic_share_off_sphere).
bool off_sphere_by_noise_alone(const MeshNeighbourhoods& mesh, const std::vector<int>& patch,
                               const Eigen::Vector3d& centre, double radius, const ContinuousFamilyOptions& options) {
    std::vector<double> distance(size_t(mesh.vertex_count()), 0.0);
    double sum2 = 0;
    for (int v : patch) {
        const double d = (mesh.positions[size_t(v)] - centre).norm() - radius;
        distance[size_t(v)] = d;
        sum2 += d * d;
    }
    const double rms = std::sqrt(sum2 / double(patch.size()));
    const double bound = options.presmoothed ? options.max_systematic_share_off_sphere_presmoothed
                                             : options.max_systematic_share_off_sphere;
    return systematic_deviation(mesh, patch, distance, options.systematic_smoothing_iterations) <= bound * rms;
}

// The patch as slippage measures it: on a point cloud, without the points whose normal is
// fitted across a sharp edge (ContinuousFamilyOptions::cloud_edge_variation_floor).
std::vector<int> with_surface_normals(const MeshNeighbourhoods& mesh, const std::vector<int>& patch,
                                      const ContinuousFamilyOptions& options) {
    if (mesh.surface_variation.empty()) return patch;
    const double edge = std::max(options.cloud_edge_variation_floor,
                                 options.cloud_edge_variation_per_median * mesh.median_surface_variation);
    std::vector<int> kept;
    kept.reserve(patch.size());
    for (int v : patch)
        if (mesh.surface_variation[size_t(v)] <= edge) kept.push_back(v);
    return kept;
}
}  // namespace

ContinuousFamily slippable_family(const MeshNeighbourhoods& mesh, const std::vector<int>& patch, double tolerance,
                                  const ContinuousFamilyOptions& options) {
    ContinuousFamily family;
    const PatchFaces faces = patch_faces(mesh, with_surface_normals(mesh, patch, options));
    if (faces.areas.size() < 6) return family;
    double total = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < faces.areas.size(); ++i) { total += faces.areas[i]; centroid += faces.areas[i] * faces.centroids[i]; }
    centroid /= total;
    double spread = 0;
    for (size_t i = 0; i < faces.areas.size(); ++i) spread += faces.areas[i] * (faces.centroids[i] - centroid).squaredNorm();
    const double extent = std::sqrt(spread / total);
    if (!(extent > 0)) return family;
    family.extent = extent;

    // C = Σ a u uᵀ with u = [q × n; n] on the patch scaled to unit radius: uᵀ[ω; v] is the
    // normal speed of the motion (ω, v) at the face, so C's small eigenvalues are the
    // motions that slide the patch along itself.
    Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
    for (size_t i = 0; i < faces.areas.size(); ++i) {
        Eigen::Matrix<double, 6, 1> u;
        const Eigen::Vector3d q = (faces.centroids[i] - centroid) / extent;
        u << q.cross(faces.normals[i]), faces.normals[i];
        C += faces.areas[i] * u * u.transpose();
    }
    C /= total;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(C);
    int slippable = 0;
    // The RMS speed over the patch of the unit motion m (column of C's eigenvectors), and
    // its RMS normal speed.
    auto speed = [&](const Eigen::Matrix<double, 6, 1>& m) {
        double sum = 0;
        for (size_t i = 0; i < faces.areas.size(); ++i) {
            const Eigen::Vector3d q = (faces.centroids[i] - centroid) / extent;
            sum += faces.areas[i] * (m.head<3>().cross(q) + m.tail<3>()).squaredNorm();
        }
        return std::sqrt(sum / total / m.squaredNorm());
    };
    auto normal_speed = [&](const Eigen::Matrix<double, 6, 1>& m) {
        return std::sqrt(std::max(0.0, m.dot(C * m)) / m.squaredNorm());
    };
    auto slides = [&](const Eigen::Matrix<double, 6, 1>& m) {
        return normal_speed(m) <= slippage_bound(options, speed(m));
    };
    while (slippable < 6 && slides(eigen.eigenvectors().col(slippable))) ++slippable;
    if (slippable == 0 || slippable > 3) return family;  // none, or a degenerate patch (a line, a point)

    // Back to absolute coordinates: at p = c + extent·q the velocity ω × q + v̂ of the unit
    // patch is extent·(ω × (p - c)/extent + v̂) = ω × p + (extent·v̂ - ω × c).
    Eigen::Matrix3Xd rotations(3, slippable);
    for (int i = 0; i < slippable; ++i) {
        Eigen::Matrix<double, 6, 1> m = eigen.eigenvectors().col(i);
        Motion motion;
        motion.omega = m.head<3>();
        motion.v = extent * m.tail<3>() - motion.omega.cross(centroid);
        family.motions.push_back(motion);
        rotations.col(i) = m.head<3>();
    }
    Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(rotations, Eigen::ComputeFullV);
    int turning = 0;  // independent rotation axes among the slippable motions
    for (int i = 0; i < svd.singularValues().size(); ++i) turning += svd.singularValues()(i) > 0.1;

    if (slippable == 1) {
        classify_single_motion(family.motions[0], centroid, extent, options, family);
        // A noisy patch's slippable turn carries some advance along its axis from the noise:
        // helical only if the turn without it does not slide the patch as well.
        if (family.kind == ContinuousKind::Helical) {
            Eigen::Matrix<double, 6, 1> turn = eigen.eigenvectors().col(0);
            const Eigen::Vector3d w = turn.head<3>();
            turn.tail<3>() -= (w.dot(turn.tail<3>()) / w.squaredNorm()) * w;
            // ...that is, unless the advance takes away more normal speed than a clean patch's
            // slippage may show.
            const double helical = std::sqrt(std::max(0.0, eigen.eigenvalues()(0)));
            const double turning = normal_speed(turn);
            if (std::sqrt(std::max(0.0, turning * turning - helical * helical)) <= options.max_slippage) {
                family.kind = ContinuousKind::Rotational;
                family.pitch = 0;
                family.motions[0].v -= family.direction.dot(family.motions[0].v) * family.direction;
            }
        }
    } else if (slippable == 2 && turning == 1) {
        // A rotation and a translation along its axis: a cylinder.
        Eigen::Vector2d spin = svd.matrixV().col(0).head<2>();
        Motion m;
        m.omega = spin(0) * family.motions[0].omega + spin(1) * family.motions[1].omega;
        m.v = spin(0) * family.motions[0].v + spin(1) * family.motions[1].v;
        classify_single_motion(m, centroid, extent, options, family);
        if (family.kind == ContinuousKind::Helical) family.pitch = 0;
        family.kind = family.kind == ContinuousKind::Translational ? ContinuousKind::Translational : ContinuousKind::Rotational;
        family.slides_along_axis = true;
    } else if (slippable == 3 && turning == 1) {
        // Two translations and a turn about the normal: a plane.
        family.kind = ContinuousKind::Planar;
        family.direction = (rotations * svd.matrixV().col(0)).normalized();
        family.point = centroid;
        const Eigen::Vector3d normal = family.direction;
        if (!near_shape(faces, total, [&](const Eigen::Vector3d& c) { return normal.dot(c - centroid); }, options, tolerance))
            return ContinuousFamily();
    } else if (slippable == 3 && turning == 3) {
        family.kind = ContinuousKind::Spherical;
        fit_sphere(faces, total, common_centre(family.motions), family);
        const Eigen::Vector3d centre = family.point;
        const double radius = family.radius;
        if (!near_shape(faces, total, [&](const Eigen::Vector3d& c) { return (c - centre).norm() - radius; }, options, tolerance))
            return ContinuousFamily();
        if (options.roughness.position > 0 && !off_sphere_by_noise_alone(mesh, patch, centre, radius, options))
            return ContinuousFamily();
    } else {
        return ContinuousFamily();
    }
    return family;
}

namespace {

// The cosine of the turn θ of a reflection T that flips an axis, as a mirror across the
// plane normal to the axis composed with a turn by θ about it: trace(T's linear part) is
// 2 cos θ - 1 (1 for the mirror itself, -3 for the point inversion).
double rotoreflection_cosine(const Transformation& T) {
    return std::clamp(((T.linear() / T.scale).trace() + 1) / 2, -1.0, 1.0);
}

}  // namespace

bool is_member(const ContinuousFamily& f, const Transformation& T, double tolerance, double degrees) {
    const double parallel = cosine_of(degrees);
    const Eigen::Vector3d image = (T.linear() * f.direction / T.scale);
    switch (f.kind) {
    case ContinuousKind::Discrete: return false;
    case ContinuousKind::Rotational:
    case ContinuousKind::Helical: {
        const Eigen::Vector3d a = f.point, b = f.point + f.extent * f.direction;
        if (distance_to_line(f.point, f.direction, T.apply(a)) > tolerance ||
            distance_to_line(f.point, f.direction, T.apply(b)) > tolerance)
            return false;  // the axis is not mapped onto itself
        if (std::abs(image.dot(f.direction)) < parallel) return false;
        if (f.kind == ContinuousKind::Helical) return true;
        if (image.dot(f.direction) > 0)
            return f.slides_along_axis || std::abs((T.apply(a) - a).dot(f.direction)) <= tolerance;
        // The axis flipped: a half-turn is the family composed with the mirror across the
        // plane normal to the axis; that mirror itself (T² = I) is reported, also where the
        // surface slides along the axis (a capped cylinder's mirror across its mid-plane).
        // Where the surface slides, every mirror normal to the axis maps it locally; only the
        // one through the middle of the patch (f.point, see record_family) maps all of it.
        // (A mirror composed with a turn about the axis is a member: see
        // mirror_in_rotoreflection.)
        const Transformation twice = T * T;
        const bool mirror_normal_to_axis = T.reflection && (twice.apply(a) - a).norm() <= tolerance &&
                                           (twice.apply(b) - b).norm() <= tolerance &&
                                           (twice.linear() - Eigen::Matrix3d::Identity()).norm() < 0.05;
        const bool through_middle = std::abs((0.5 * (a + T.apply(a)) - f.point).dot(f.direction)) <= tolerance;
        return !(mirror_normal_to_axis && (!f.slides_along_axis || through_middle));
    }
    case ContinuousKind::Translational: {
        // The members are the slides along the direction: no turn, no mirror (a mirror
        // across a plane along an extrusion maps it onto itself only if its profile is
        // mirror-symmetric, which is a discrete symmetry of its own).
        if (T.reflection) return false;
        const Eigen::Matrix3d turn = T.linear() / T.scale;
        if (std::clamp((turn.trace() - 1) / 2, -1.0, 1.0) < parallel) return false;
        const Eigen::Vector3d shift = T.apply(f.point) - f.point;
        return (shift - f.direction * f.direction.dot(shift)).norm() <= tolerance;
    }
    case ContinuousKind::Planar:
        return std::abs(image.dot(f.direction)) >= parallel && std::abs(f.direction.dot(T.apply(f.point) - f.point)) <= tolerance;
    case ContinuousKind::Spherical: return (T.apply(f.point) - f.point).norm() <= tolerance;
    }
    return false;
}

namespace {
// The mirror across the plane through `on_plane` with unit normal n.
Transformation mirror_normal_to(const Eigen::Vector3d& n, const Eigen::Vector3d& on_plane) {
    const Eigen::Matrix3d linear = Eigen::Matrix3d::Identity() - 2 * n * n.transpose();
    return Transformation::from_linear(linear, 2 * n * n.dot(on_plane));
}
}  // namespace

std::optional<Transformation> mirror_in_rotoreflection(const ContinuousFamily& f, const Transformation& T, double degrees) {
    if (f.kind != ContinuousKind::Rotational || !T.reflection) return std::nullopt;
    if ((T.linear() * f.direction / T.scale).dot(f.direction) > -cosine_of(degrees)) return std::nullopt;
    if (rotoreflection_cosine(T) >= cosine_of(degrees)) return std::nullopt;  // the mirror already
    // A turn about the axis fixes the axis point by point, so T moves an axis point a as
    // the mirror does: the mirror's plane passes half way between a and T(a).
    return mirror_normal_to(f.direction, 0.5 * (f.point + T.apply(f.point)));
}

std::optional<Transformation> mirror_through_middle(const ContinuousFamily& f, const Transformation& T,
                                                    double tolerance, double degrees) {
    if (f.kind != ContinuousKind::Rotational || !T.reflection) return std::nullopt;
    const Eigen::Vector3d& n = f.direction;
    if ((T.linear() * n / T.scale).dot(n) > -cosine_of(degrees)) return std::nullopt;  // the axis not flipped
    if (rotoreflection_cosine(T) < cosine_of(degrees)) return std::nullopt;  // not a mirror
    const Eigen::Vector3d a = f.point, b = f.point + f.extent * n;
    if (distance_to_line(f.point, n, T.apply(a)) > tolerance || distance_to_line(f.point, n, T.apply(b)) > tolerance)
        return std::nullopt;  // the axis not mapped onto itself
    // T moves the family's ends along the axis by twice its plane's distance to the middle.
    if (2 * std::abs((0.5 * (a + T.apply(a)) - f.point).dot(n)) <= tolerance) return std::nullopt;
    return mirror_normal_to(n, f.point);
}

std::vector<MirrorAxis> lines_of_mirrors(const std::vector<Eigen::Vector4d>& planes, size_t min_mirrors,
                                         double tolerance, double degrees) {
    const double sine = sine_of(degrees);
    std::vector<MirrorAxis> lines;
    for (size_t i = 0; i < planes.size(); ++i)
        for (size_t j = i + 1; j < planes.size(); ++j) {
            const Eigen::Vector3d ni = planes[i].head<3>(), nj = planes[j].head<3>();
            const double di = planes[i][3], dj = planes[j][3];
            Eigen::Vector3d u = ni.cross(nj);
            if (u.norm() < sine) continue;  // parallel planes meet in no line
            // The point of both planes nearest the origin: n_i·p = d_i and n_j·p = d_j.
            const Eigen::Vector3d p = (di * nj.cross(u) + dj * u.cross(ni)) / u.squaredNorm();
            u.normalize();
            if (std::any_of(lines.begin(), lines.end(), [&](const MirrorAxis& l) {
                    return same_line(l.point, l.direction, p, u, tolerance, degrees);
                }))
                continue;
            MirrorAxis line{p, u, {}};
            for (size_t k = 0; k < planes.size(); ++k)
                if (std::abs(planes[k].head<3>().dot(u)) <= sine && std::abs(planes[k].head<3>().dot(p) - planes[k][3]) <= tolerance)
                    line.mirrors.push_back(k);
            if (line.mirrors.size() >= min_mirrors) lines.push_back(std::move(line));
        }
    return lines;
}

namespace {

ContinuousFamily plane_of_sample(const SurfaceSignature& sample, double radius) {
    ContinuousFamily family;
    family.kind = ContinuousKind::Planar;
    family.point = sample.position;
    family.direction = sample.normal;
    family.extent = radius;
    Motion a, b, turn;
    a.v = sample.direction1;
    b.v = sample.direction2;
    turn.omega = sample.normal;
    turn.v = -sample.normal.cross(sample.position);
    family.motions = {a, b, turn};
    return family;
}

ContinuousFamily sphere_of_sample(const SurfaceSignature& sample, double radius) {
    ContinuousFamily family;
    const double mean = 0.5 * (sample.kappa1 + sample.kappa2);
    family.kind = ContinuousKind::Spherical;
    family.radius = 1 / std::abs(mean);
    family.point = sample.position - sample.normal / mean;  // the outward normal points away from a convex centre
    family.extent = radius;
    for (int a = 0; a < 3; ++a) {
        const Eigen::Vector3d axis = Eigen::Vector3d::Unit(a);
        Motion m;
        m.omega = axis;
        m.v = -axis.cross(family.point);
        family.motions.push_back(m);
    }
    return family;
}

}  // namespace

std::vector<ContinuousFamily> families_of_pruned_sample(const SurfaceSignature& sample, double radius, double flatness) {
    const double largest = std::max(std::abs(sample.kappa1), std::abs(sample.kappa2));
    if (!(largest * radius < flatness)) return {sphere_of_sample(sample, radius)};
    // Flat within the ball, yet a sphere larger than the ball is flat there too: a whole
    // sphere's curvature times the default radius (1 % of its diagonal, 2 sqrt(3) radii) is
    // 0.035.  Its plane stops growing after a few faces (shape_tangency_degrees); the sphere
    // of the sample's curvature, where both curvatures bend the same way, is tried next.
    if (sample.kappa1 * sample.kappa2 > 0) return {plane_of_sample(sample, radius), sphere_of_sample(sample, radius)};
    return {plane_of_sample(sample, radius)};
}

ContinuousFamily cylinder_of_sample(const SurfaceSignature& sample, double radius, double flatness) {
    ContinuousFamily family;
    const bool first_vanishes = std::abs(sample.kappa1) < std::abs(sample.kappa2);
    const double vanishing = first_vanishes ? sample.kappa1 : sample.kappa2;
    const double bending = first_vanishes ? sample.kappa2 : sample.kappa1;
    if (!(std::abs(vanishing) * radius < flatness && std::abs(bending) * radius >= flatness)) return family;
    family.kind = ContinuousKind::Rotational;
    family.slides_along_axis = true;
    family.direction = first_vanishes ? sample.direction1 : sample.direction2;
    family.point = sample.position - sample.normal / bending;  // as for a sphere: the outward normal points away from a convex axis
    family.extent = radius;
    Motion slide;
    slide.v = family.direction;
    family.motions = {Motion::turn_about(family.point, family.direction), slide};
    return family;
}

bool lies_on_cylinder(const MeshNeighbourhoods& mesh, const ContinuousFamily& family, double tolerance,
                      const ContinuousFamilyOptions& options) {
    if (family.vertices.empty()) return false;
    std::vector<double> radii;
    radii.reserve(family.vertices.size());
    for (int v : family.vertices)
        radii.push_back(family.direction.cross(mesh.positions[size_t(v)] - family.point).norm());
    const auto [lo, hi] = std::minmax_element(radii.begin(), radii.end());
    return *hi - *lo <= 2 * shape_bound(options, tolerance);
}

bool same_family(const ContinuousFamily& a, const ContinuousFamily& b, double tolerance,
                 const ContinuousFamilyOptions& options) {
    if (a.kind != b.kind || a.kind == ContinuousKind::Discrete) return false;
    const double parallel = cosine_of(options.axis_agreement_degrees);
    switch (a.kind) {
    case ContinuousKind::Spherical:
        return (a.point - b.point).norm() <= tolerance && std::abs(a.radius - b.radius) <= tolerance;
    case ContinuousKind::Planar:
        return std::abs(a.direction.dot(b.direction)) >= parallel && std::abs(a.direction.dot(b.point - a.point)) <= tolerance;
    case ContinuousKind::Translational: {
        if (std::abs(a.direction.dot(b.direction)) < parallel) return false;
        // Parallel extrusions elsewhere are other families: the patches must meet.
        std::vector<int> common;
        std::set_intersection(a.vertices.begin(), a.vertices.end(), b.vertices.begin(), b.vertices.end(),
                              std::back_inserter(common));
        return !common.empty();
    }
    default:
        return same_line(a.point, a.direction, b.point, b.direction, tolerance, options.axis_agreement_degrees);
    }
}

namespace {

Transformation rotation_about(const Eigen::Vector3d& point, const Eigen::Vector3d& axis, double angle, double advance) {
    Transformation t;
    t.rotation = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    t.translation = point - t.rotation * point + advance * axis;
    return t;
}

Transformation shift(const Eigen::Vector3d& by) {
    Transformation t;
    t.translation = by;
    return t;
}

// The range of the patch's vertices along a direction.
double extent_along(const MeshNeighbourhoods& mesh, const std::vector<int>& patch, const Eigen::Vector3d& axis) {
    double lo = INFINITY, hi = -INFINITY;
    for (int v : patch) {
        const double t = axis.dot(mesh.positions[size_t(v)]);
        lo = std::min(lo, t);
        hi = std::max(hi, t);
    }
    return patch.empty() ? 0.0 : hi - lo;
}

// Finite members of the family that move its patch well beyond the tolerance.  Rotations
// of a surface of revolution may be large; a translational or planar family is finite,
// so its members move the patch by a fraction of its own length, which keeps most of it
// on itself.
std::vector<Transformation> finite_members(const MeshNeighbourhoods& mesh, const ContinuousFamily& f) {
    std::vector<Transformation> members;
    const Eigen::Vector3d u = f.direction.unitOrthogonal(), w = f.direction.cross(u);
    switch (f.kind) {
    case ContinuousKind::Rotational:
        for (double d : {45.0, 90.0, 180.0}) members.push_back(rotation_about(f.point, f.direction, d * M_PI / 180, 0));
        break;
    case ContinuousKind::Helical:
        for (double d : {-90.0, -45.0, 45.0, 90.0})
            members.push_back(rotation_about(f.point, f.direction, d * M_PI / 180, f.pitch * d / 360));
        break;
    case ContinuousKind::Translational: {
        const double length = extent_along(mesh, f.vertices, f.direction);
        for (double s : {-0.25, -0.1, 0.1, 0.25}) members.push_back(shift(s * length * f.direction));
        break;
    }
    case ContinuousKind::Planar: {
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (int v : f.vertices) centre += mesh.positions[size_t(v)];
        if (!f.vertices.empty()) centre /= double(f.vertices.size());
        for (double d : {-30.0, -15.0, 15.0, 30.0}) members.push_back(rotation_about(centre, f.direction, d * M_PI / 180, 0));
        for (const Eigen::Vector3d& axis : {u, w}) {
            const double length = extent_along(mesh, f.vertices, axis);
            for (double s : {-0.15, 0.15}) members.push_back(shift(s * length * axis));
        }
        break;
    }
    case ContinuousKind::Spherical:
        for (int a = 0; a < 3; ++a) members.push_back(rotation_about(f.point, Eigen::Vector3d::Unit(a), M_PI / 4, 0));
        break;
    case ContinuousKind::Discrete: break;
    }
    return members;
}

// The share of the patch's area (its faces, at their centroids) that T maps within the
// tolerance of the surface.
double area_share_mapped(const PatchFaces& faces, const SurfaceQuery& surface, const Transformation& T, double tolerance) {
    double landed = 0, total = 0;
    for (size_t i = 0; i < faces.areas.size(); ++i) {
        total += faces.areas[i];
        if (surface.closest(T.apply(faces.centroids[i]), tolerance).found) landed += faces.areas[i];
    }
    return total > 0 ? landed / total : 0.0;
}

}  // namespace

SurfaceRoughness surface_roughness(const MeshNeighbourhoods& mesh) {
    const size_t n = size_t(mesh.vertex_count());
    std::vector<Eigen::Vector3d> vertex_normal(n, Eigen::Vector3d::Zero());
    for (size_t v = 0; v < n; ++v) {
        for (int k = mesh.face_offsets[v]; k < mesh.face_offsets[v + 1]; ++k) {
            const int f = mesh.faces_around[size_t(k)];
            vertex_normal[v] += mesh.face_areas[size_t(f)] * mesh.face_normals[size_t(f)];
        }
        vertex_normal[v].normalize();
    }
    std::vector<double> tilts, offsets;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& c = mesh.faces[f];
        if (c[0] < 0) continue;
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (int v : c) mean += vertex_normal[size_t(v)];
        // A cloud's point is a face of its own: its neighbours' normals are its surroundings.
        if (c[0] == c[1])
            for (int k = mesh.neighbour_offsets[size_t(c[0])]; k < mesh.neighbour_offsets[size_t(c[0]) + 1]; ++k)
                mean += vertex_normal[size_t(mesh.neighbours[size_t(k)])];
        if (mean.squaredNorm() > 0) tilts.push_back(mesh.face_normals[f].cross(mean.normalized()).norm());
    }
    // A vertex's offset from its neighbours' centroid is the surface's curvature (the same
    // for its neighbours) plus its noise (its own): the noise is what differs from theirs.
    std::vector<double> offset(n, NAN);
    for (size_t v = 0; v < n; ++v) {
        const int first = mesh.neighbour_offsets[v], last = mesh.neighbour_offsets[v + 1];
        if (last == first || !vertex_normal[v].allFinite()) continue;
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        for (int k = first; k < last; ++k) centroid += mesh.positions[size_t(mesh.neighbours[size_t(k)])];
        centroid /= double(last - first);
        offset[v] = vertex_normal[v].dot(mesh.positions[v] - centroid);
    }
    for (size_t v = 0; v < n; ++v) {
        if (!std::isfinite(offset[v])) continue;
        double sum = 0;
        int count = 0;
        for (int k = mesh.neighbour_offsets[v]; k < mesh.neighbour_offsets[v + 1]; ++k)
            if (std::isfinite(offset[size_t(mesh.neighbours[size_t(k)])])) {
                sum += offset[size_t(mesh.neighbours[size_t(k)])];
                ++count;
            }
        if (count > 0) offsets.push_back(std::abs(offset[v] - sum / count));
    }
    return {median(std::move(tilts)), median(std::move(offsets))};
}

FamilyCheck check_members(const MeshNeighbourhoods& mesh, const SurfaceQuery& surface, const ContinuousFamily& family,
                          double tolerance, double edge_length) {
    FamilyCheck check;
    check.deviation.assign(family.vertices.size(), 0.0);
    std::vector<double> best(family.vertices.size(), INFINITY);
    const std::vector<Transformation> members = finite_members(mesh, family);
    if (members.empty() || family.vertices.empty()) return check;
    // A finite family (an extrusion, a face, a cap) maps part of its patch beyond its own
    // end: only the vertices whose image stays over the patch (within a few edges of one
    // of its vertices) are tested.  A surface of revolution is tested whole, and by area.
    const bool clipped = family.kind != ContinuousKind::Rotational;
    const PatchFaces faces = clipped ? PatchFaces() : patch_faces(mesh, family.vertices);
    KdTree::Points points(Eigen::Index(family.vertices.size()), 3);
    for (size_t i = 0; i < family.vertices.size(); ++i) points.row(Eigen::Index(i)) = mesh.positions[size_t(family.vertices[i])].transpose();
    const KdTree footprint(std::move(points));
    const double reach = 3 * edge_length;
    double coverage = 1, area_coverage = 1;
    int most = -1;
    for (const Transformation& T : members) {
        int tested = 0, landed = 0;
        std::vector<double> magnitudes;
        for (size_t i = 0; i < family.vertices.size(); ++i) {
            const Eigen::Vector3d image = T.apply(mesh.positions[size_t(family.vertices[i])]);
            if (clipped && footprint.nearest(image.data()).second > reach) continue;
            ++tested;
            ClosestPoint cp = surface.closest(image, tolerance);
            if (!cp.found) continue;
            ++landed;
            magnitudes.push_back(cp.distance);
            if (std::abs(cp.signed_distance) < std::abs(best[i])) best[i] = cp.signed_distance;
        }
        if (!magnitudes.empty()) check.median_deviation = std::max(check.median_deviation, median(std::move(magnitudes)));
        // Too little left over the patch to tell: the member does not hold.
        const double share = tested >= int(family.vertices.size() / 4) ? double(landed) / double(tested) : 0.0;
        if (!faces.areas.empty()) area_coverage = std::min(area_coverage, area_share_mapped(faces, surface, T, tolerance));
        coverage = std::min(coverage, share);
        if (landed > most) { most = landed; check.best_member = T; }
    }
    check.coverage = coverage;
    check.area_coverage = area_coverage;
    for (size_t i = 0; i < best.size(); ++i) check.deviation[i] = std::isfinite(best[i]) ? best[i] : 0.0;
    return check;
}

namespace {

// Whether a vertex belongs to the family's patch: some face around it is tangent to every
// generating motion there (within tangency_degrees), and for a plane or a sphere it lies on
// the shape within the tolerance.
class FamilyTangency {
public:
    FamilyTangency(const MeshNeighbourhoods& mesh, const ContinuousFamily& family, double tolerance,
                   const ContinuousFamilyOptions& options)
        : mesh_(mesh), family_(family), tolerance_(tolerance), off_(shape_bound(options, tolerance)) {
        const bool shape = family.kind == ContinuousKind::Planar || family.kind == ContinuousKind::Spherical;
        max_sine_ = tangency_bound(sine_of(shape ? options.shape_tangency_degrees : options.tangency_degrees), options);
    }

    bool operator()(int v) const {
        const Eigen::Vector3d& p = mesh_.positions[size_t(v)];
        if (!on_shape(p)) return false;
        for (int k = mesh_.face_offsets[v]; k < mesh_.face_offsets[v + 1]; ++k)
            if (tangent_to_motions(mesh_.face_normals[size_t(mesh_.faces_around[size_t(k)])], p)) return true;
        return false;
    }

private:
    bool on_shape(const Eigen::Vector3d& p) const {
        if (family_.kind == ContinuousKind::Planar) return std::abs(family_.direction.dot(p - family_.point)) <= off_;
        if (family_.kind == ContinuousKind::Spherical) return std::abs((p - family_.point).norm() - family_.radius) <= off_;
        return true;
    }

    bool tangent_to_motions(const Eigen::Vector3d& n, const Eigen::Vector3d& p) const {
        for (const Motion& m : family_.motions) {
            const Eigen::Vector3d u = m.velocity(p);
            // Near a rotation axis points hardly move: measure against the speed a
            // tolerance away from it.
            const double speed = std::max(u.norm(), m.omega.norm() * tolerance_);
            if (std::abs(n.dot(u)) > max_sine_ * speed) return false;
        }
        return true;
    }

    const MeshNeighbourhoods& mesh_;
    const ContinuousFamily& family_;
    double tolerance_, off_, max_sine_ = 0;
};

}  // namespace

double mean_lean_from(const MeshNeighbourhoods& mesh, const std::vector<int>& patch, const Eigen::Vector3d& direction) {
    const PatchFaces faces = patch_faces(mesh, patch);
    double total = 0, lean = 0;
    for (size_t i = 0; i < faces.areas.size(); ++i) {
        total += faces.areas[i];
        lean += faces.areas[i] * faces.normals[i].cross(direction).norm();
    }
    return total > 0 ? lean / total : 0.0;
}

std::vector<int> tangent_vertices(const MeshNeighbourhoods& mesh, const ContinuousFamily& family,
                                  const std::vector<int>& vertices, double tolerance,
                                  const ContinuousFamilyOptions& options) {
    const FamilyTangency tangent(mesh, family, tolerance, options);
    std::vector<int> kept;
    for (int v : vertices)
        if (tangent(v)) kept.push_back(v);
    return kept;
}

std::vector<int> grow_family_patch(const MeshNeighbourhoods& mesh, const ContinuousFamily& family,
                                   const std::vector<int>& seeds, double tolerance,
                                   const ContinuousFamilyOptions& options) {
    const FamilyTangency tangent(mesh, family, tolerance, options);
    std::vector<char> state(size_t(mesh.vertex_count()), 0);  // 1 in the patch, 2 rejected
    std::deque<int> queue;
    for (int s : seeds)
        if (state[size_t(s)] == 0) {
            state[size_t(s)] = tangent(s) ? 1 : 2;
            if (state[size_t(s)] == 1) queue.push_back(s);
        }
    std::vector<int> patch(queue.begin(), queue.end());
    while (!queue.empty()) {
        int v = queue.front();
        queue.pop_front();
        for (int k = mesh.neighbour_offsets[v]; k < mesh.neighbour_offsets[v + 1]; ++k) {
            int u = mesh.neighbours[size_t(k)];
            if (state[size_t(u)]) continue;
            state[size_t(u)] = tangent(u) ? 1 : 2;
            if (state[size_t(u)] == 1) { patch.push_back(u); queue.push_back(u); }
        }
    }
    std::sort(patch.begin(), patch.end());
    return patch;
}

}  // namespace symmetry
