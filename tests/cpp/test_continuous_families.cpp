// Continuous families: slippage analysis names the analytic shapes by their kind and axis,
// finds none on a shape without one, and tells the family's own members from other
// symmetries.
#include "core/continuous_families.h"
#include "core/sampling.h"
#include "test_shapes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numeric>
#include <optional>
#include <random>
#include <tuple>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

struct Analysed {
    Mesh mesh;
    MeshNeighbourhoods n;
    std::vector<int> all;
    double diagonal = 0;
};

void analyse(const Shape& s, Analysed& a) {
    std::vector<int> rows;
    build_mesh(s.V, s.F, a.mesh, rows);
    a.n = mesh_neighbourhoods(a.mesh);
    a.all.resize(size_t(a.n.vertex_count()));
    std::iota(a.all.begin(), a.all.end(), 0);
    a.diagonal = a.mesh.bbox.Diag();
}

// The family of a surface of revolution about z through the origin.
ContinuousFamily revolution_about_z() {
    ContinuousFamily f;
    f.kind = ContinuousKind::Rotational;
    f.direction = Eigen::Vector3d::UnitZ();
    f.extent = 1;
    return f;
}

double angle_degrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180 / M_PI;
}

}  // namespace

TEST(ContinuousFamilies, NamesTheAnalyticShapes) {
    const ContinuousFamilyOptions options;
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
    const Eigen::Vector3d shift(0.3, -1.2, 2.0);
    const Eigen::Vector3d axis = tilt * Eigen::Vector3d::UnitZ();
    {
        Analysed a;  // a torus: a surface of revolution about z
        analyse(transformed(torus(2.0, 0.6, 120, 40), tilt, shift), a);
        ContinuousFamily f = slippable_family(a.n, a.all, 0.01 * a.diagonal, options);
        EXPECT_EQ(f.kind, ContinuousKind::Rotational);
        EXPECT_LT(angle_degrees(f.direction, axis), 0.5);
        EXPECT_LT((f.point - shift).cross(axis).norm(), 1e-3 * a.diagonal);  // the axis passes through the centre
        EXPECT_FALSE(f.slides_along_axis);
    }
    {
        Analysed a;  // an open cylinder: turns about its axis and slides along it
        analyse(transformed(cylinder(0.5, 2.0, 96, 40), tilt, shift), a);
        ContinuousFamily f = slippable_family(a.n, a.all, 0.01 * a.diagonal, options);
        EXPECT_EQ(f.kind, ContinuousKind::Rotational);
        EXPECT_TRUE(f.slides_along_axis);
        EXPECT_LT(angle_degrees(f.direction, axis), 0.5);
    }
    {
        Analysed a;  // a sphere: every rotation about its centre
        analyse(transformed(sphere(1.5, 4), tilt, shift), a);
        ContinuousFamily f = slippable_family(a.n, a.all, 0.01 * a.diagonal, options);
        EXPECT_EQ(f.kind, ContinuousKind::Spherical);
        EXPECT_LT((f.point - shift).norm(), 1e-3);
        EXPECT_NEAR(f.radius, 1.5, 0.01);
    }
    {
        Analysed a;  // one face of a box: a plane
        analyse(transformed(box(1, 1, 1, 10), tilt, shift), a);
        std::vector<int> face;
        for (int v = 0; v < a.n.vertex_count(); ++v)
            if (std::abs((tilt.transpose() * (a.n.positions[size_t(v)] - shift)).z() - 1) < 1e-9) face.push_back(v);
        ContinuousFamily f = slippable_family(a.n, face, 0.01 * a.diagonal, options);
        EXPECT_EQ(f.kind, ContinuousKind::Planar);
        EXPECT_LT(angle_degrees(f.direction, axis), 0.5);
    }
    {
        Analysed a;  // a torus whose tube swells on one side: no continuous symmetry
        analyse(deformed_torus(2.0, 0.6, 120, 40, [](double u) { return 1 + 0.3 * std::cos(u); }), a);
        EXPECT_EQ(slippable_family(a.n, a.all, 0.01 * a.diagonal, options).kind, ContinuousKind::Discrete);
    }
}

TEST(ContinuousFamilies, MembersAreTheFamilysOwnMotions) {
    const ContinuousFamily torus_family = revolution_about_z();
    const double tol = 1e-3, degrees = 1;
    Transformation turn;  // any rotation about the axis
    turn.rotation = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_TRUE(is_member(torus_family, turn, tol, degrees));
    Transformation containing;  // the mirror through a plane containing the axis (x = 0)
    containing.reflection = true;
    EXPECT_TRUE(is_member(torus_family, containing, tol, degrees));
    Transformation flip;  // a half-turn about the x axis: the family composed with the mirror z -> -z
    flip.rotation = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    EXPECT_TRUE(is_member(torus_family, flip, tol, degrees));
    Transformation equator = Transformation::from_linear(Eigen::Vector3d(1, 1, -1).asDiagonal(), Eigen::Vector3d::Zero());
    EXPECT_FALSE(is_member(torus_family, equator, tol, degrees));  // a discrete symmetry of its own
    Transformation elsewhere;  // a rotation about a parallel axis
    elsewhere.rotation = turn.rotation;
    elsewhere.translation = Eigen::Vector3d(0.5, 0, 0) - turn.rotation * Eigen::Vector3d(0.5, 0, 0);
    EXPECT_FALSE(is_member(torus_family, elsewhere, tol, degrees));
    Transformation along;  // a shift along the axis moves a surface of revolution off itself...
    along.translation = Eigen::Vector3d(0, 0, 0.3);
    EXPECT_FALSE(is_member(torus_family, along, tol, degrees));
    ContinuousFamily cylinder_family = torus_family;  // ...but not a cylinder
    cylinder_family.slides_along_axis = true;
    EXPECT_TRUE(is_member(cylinder_family, along, tol, degrees));
    // Where the surface slides, a mirror normal to the axis maps it only locally, except
    // the one through the middle of the patch (the family's point): a capped cylinder's
    // mid-plane mirror is a discrete symmetry of its own.
    EXPECT_FALSE(is_member(cylinder_family, equator, tol, degrees));
    Transformation higher = Transformation::from_linear(Eigen::Vector3d(1, 1, -1).asDiagonal(), Eigen::Vector3d(0, 0, 0.4));
    EXPECT_TRUE(is_member(cylinder_family, higher, tol, degrees));
}

TEST(ContinuousFamilies, AnExtrusionsMembersAreItsSlides) {
    ContinuousFamily prism;  // an extrusion along z through the origin
    prism.kind = ContinuousKind::Translational;
    prism.direction = Eigen::Vector3d::UnitZ();
    prism.extent = 1;
    const double tol = 1e-3, degrees = 1;
    Transformation slide;
    slide.translation = Eigen::Vector3d(0, 0, 0.7);
    EXPECT_TRUE(is_member(prism, slide, tol, degrees));
    Transformation mirror;  // across x = 0, a plane along the extrusion: a symmetry of the profile
    mirror.reflection = true;
    EXPECT_FALSE(is_member(prism, mirror, tol, degrees));
    Transformation turn;  // a half-turn about the direction
    turn.rotation = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_FALSE(is_member(prism, turn, tol, degrees));
}

TEST(ContinuousFamilies, FiniteMembersHoldOnlyOnTrueFamilies) {
    for (bool swollen : {false, true}) {
        Analysed a;
        analyse(swollen ? deformed_torus(2.0, 0.6, 120, 40, [](double u) { return 1 + 0.3 * std::cos(u); })
                        : torus(2.0, 0.6, 120, 40),
                a);
        ContinuousFamily f;
        f.kind = ContinuousKind::Rotational;
        f.direction = Eigen::Vector3d::UnitZ();
        f.vertices = a.all;
        const SurfaceQuery surface(a.mesh);
        FamilyCheck check = check_members(a.n, surface, f, 0.01 * a.diagonal, median_edge_length(a.n));
        if (swollen) EXPECT_LT(check.coverage, ContinuousFamilyOptions().min_member_coverage);
        else EXPECT_GT(check.coverage, 0.99);
    }
}

// A small boss on a long plate: a turn about the boss's axis maps nearly every vertex (the
// boss is finely tessellated, the plate is a few large triangles) but carries most of the
// area (the plate) off the surface.  The family is judged by both.
TEST(ContinuousFamilies, ATurnMustMapMostOfThePatchsAreaNotOnlyItsVertices) {
    const Shape boss = cylinder(0.5, 2.0, 96, 40);
    const Shape plate = transformed(box(4.3, 0.6, 0.05, 2), Eigen::Matrix3d::Identity(), Eigen::Vector3d(3.7, 0, -0.5));
    for (bool with_plate : {false, true}) {
        Analysed a;
        analyse(with_plate ? merged(boss, plate) : boss, a);
        ContinuousFamily f;
        f.kind = ContinuousKind::Rotational;
        f.direction = Eigen::Vector3d::UnitZ();
        f.vertices = a.all;
        const SurfaceQuery surface(a.mesh);
        const FamilyCheck check = check_members(a.n, surface, f, 0.01 * a.diagonal, median_edge_length(a.n));
        EXPECT_GT(check.coverage, 0.99);
        if (with_plate) EXPECT_LT(check.area_coverage, ContinuousFamilyOptions().min_member_area_coverage);
        else EXPECT_GT(check.area_coverage, 0.99);
    }
}

TEST(ContinuousFamilies, ACylindersSamplesSuggestItsAxis) {
    // Signatures measured on a tilted cylinder mesh, as the detector measures them.
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
    const Eigen::Vector3d shift(0.3, -1.2, 2.0);
    const Eigen::Vector3d axis = tilt * Eigen::Vector3d::UnitZ();
    const double R = 0.5, radius = 0.1, flatness = 0.05;
    Analysed a;
    analyse(transformed(cylinder(R, 2.0, 96, 40), tilt, shift), a);
    std::mt19937_64 rng(5);
    int suggested = 0, inside = 0;
    for (const SurfaceSignature& s : compute_signatures(a.mesh, uniform_area_sampling(a.mesh, 200, rng), radius)) {
        const double height = axis.dot(s.position - shift);
        if (height < 2 * radius || height > 2.0 - 2 * radius) continue;  // the ball reaches past the open rim
        ++inside;
        ContinuousFamily f = cylinder_of_sample(s, radius, flatness);
        if (f.kind == ContinuousKind::Discrete) continue;
        ++suggested;
        EXPECT_EQ(f.kind, ContinuousKind::Rotational);
        EXPECT_TRUE(f.slides_along_axis);
        EXPECT_LT(angle_degrees(f.direction, axis), 1.0);
        // On the axis within the curvature estimate's error (slippage refines it afterwards).
        EXPECT_LT(axis.cross(f.point - shift).norm(), 0.05 * R);
    }
    EXPECT_GT(inside, 100);
    EXPECT_EQ(suggested, inside);

    SurfaceSignature umbilic;  // a sphere's sample: both curvatures alike
    umbilic.kappa1 = umbilic.kappa2 = 2;
    EXPECT_EQ(cylinder_of_sample(umbilic, radius, flatness).kind, ContinuousKind::Discrete);
    SurfaceSignature flat;  // a plane's: neither bends
    flat.kappa1 = 0.1, flat.kappa2 = 0.2;
    EXPECT_EQ(cylinder_of_sample(flat, radius, flatness).kind, ContinuousKind::Discrete);
    SurfaceSignature saddle;  // a saddle's: both bend
    saddle.kappa1 = -1, saddle.kappa2 = 2;
    EXPECT_EQ(cylinder_of_sample(saddle, radius, flatness).kind, ContinuousKind::Discrete);
}

TEST(ContinuousFamilies, ASphereFlatWithinTheBallStillSuggestsItself) {
    // A whole sphere bends by 0.035 of a ball of 1 % of its diagonal: its samples are flat by
    // the pruning's bound, and the plane each suggests comes first; its own sphere follows.
    const double R = 1.0, flatness = 0.05;
    Analysed a;
    analyse(sphere(R, 6), a);
    const double radius = 0.01 * a.diagonal;
    std::mt19937_64 rng(3);
    for (const SurfaceSignature& s : compute_signatures(a.mesh, uniform_area_sampling(a.mesh, 50, rng), radius)) {
        ASSERT_LT(std::max(std::abs(s.kappa1), std::abs(s.kappa2)) * radius, flatness);
        const std::vector<ContinuousFamily> suggested = families_of_pruned_sample(s, radius, flatness);
        ASSERT_EQ(suggested.size(), 2u);
        EXPECT_EQ(suggested[0].kind, ContinuousKind::Planar);
        EXPECT_EQ(suggested[1].kind, ContinuousKind::Spherical);
        EXPECT_LT(suggested[1].point.norm(), 0.1 * R);  // the centre, within the curvature's error
        EXPECT_NEAR(suggested[1].radius, R, 0.1 * R);
    }
    SurfaceSignature saddle;  // flat within the ball, bending both ways: a plane's only
    saddle.kappa1 = -0.1, saddle.kappa2 = 0.2;
    EXPECT_EQ(families_of_pruned_sample(saddle, 0.1, flatness).size(), 1u);
    SurfaceSignature curved;  // bending beyond the bound: its sphere alone
    curved.kappa1 = curved.kappa2 = 2;
    const std::vector<ContinuousFamily> sphere_only = families_of_pruned_sample(curved, 0.1, flatness);
    ASSERT_EQ(sphere_only.size(), 1u);
    EXPECT_EQ(sphere_only[0].kind, ContinuousKind::Spherical);
}

TEST(ContinuousFamilies, ABandOfAConeIsNoCylinder) {
    // A cylinder and a cone of half-angle about 10 degrees share an axis; the cylinder
    // family's patch lies on one cylinder, a band of the cone (a tenth of its height) not.
    const ContinuousFamilyOptions options;
    Shape cone = cylinder(0.5, 2.0, 96, 40);
    for (Eigen::Index i = 0; i < cone.V.rows(); ++i) cone.V.row(i).head<2>() *= 1 - 0.35 * cone.V(i, 2);
    for (const auto& [shape, band_height, on_cylinder] :
         {std::tuple{cylinder(0.5, 2.0, 96, 40), 2.0, true}, std::tuple{cone, 0.2, false}}) {
        Analysed a;
        analyse(shape, a);
        ContinuousFamily f;
        f.kind = ContinuousKind::Rotational;
        f.slides_along_axis = true;
        f.direction = Eigen::Vector3d::UnitZ();
        for (int v = 0; v < a.n.vertex_count(); ++v)
            if (a.n.positions[size_t(v)].z() <= band_height + 1e-9) f.vertices.push_back(v);
        EXPECT_EQ(lies_on_cylinder(a.n, f, 0.01 * a.diagonal, options), on_cylinder) << band_height;
    }
}

namespace {

// Gaussian noise of standard deviation `sigma` on every coordinate of a shape's vertices.
Shape with_noise(Shape s, double sigma, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss(0.0, sigma);
    for (Eigen::Index i = 0; i < s.V.rows(); ++i)
        for (int k = 0; k < 3; ++k) s.V(i, k) += gauss(rng);
    return s;
}

}  // namespace

TEST(ContinuousFamilies, RoughnessIsTheNoiseNotTheCurvature) {
    // A clean sphere and cylinder are curved but not rough; with noise of 0.2 % of the radius
    // on every coordinate, the typical vertex offset is of the order of that noise.
    for (const Shape& clean : {sphere(1.0, 5), cylinder(1.0, 2.0, 96, 48)}) {
        Analysed a;
        analyse(clean, a);
        const SurfaceRoughness r = surface_roughness(a.n);
        EXPECT_LT(r.position, 1e-4);
        EXPECT_LT(r.normal, 0.05);
    }
    const double sigma = 0.002;
    Analysed a;
    analyse(with_noise(sphere(1.0, 5), sigma, 3), a);
    const SurfaceRoughness r = surface_roughness(a.n);
    EXPECT_GT(r.position, 0.4 * sigma);
    EXPECT_LT(r.position, 1.5 * sigma);
    EXPECT_GT(r.normal, 0.05);  // the sphere's edges are about 0.03 long: a tilt of sigma/edge
}

TEST(ContinuousFamilies, ANoisySphereIsOneSphericalFamilyWhenItsRoughnessIsAllowedFor) {
    // Noise of 0.1 % of the diagonal: with the clean bounds no motion slides the sphere; with
    // the roughness allowed for, it is a sphere about its true centre.
    Analysed a;
    analyse(with_noise(sphere(1.0, 5), 0.001 * 2 * std::sqrt(3.0), 5), a);
    const double tolerance = 0.01 * a.diagonal;
    ContinuousFamilyOptions options;
    EXPECT_EQ(slippable_family(a.n, a.all, tolerance, options).kind, ContinuousKind::Discrete);
    options.roughness = surface_roughness(a.n);
    const ContinuousFamily f = slippable_family(a.n, a.all, tolerance, options);
    ASSERT_EQ(f.kind, ContinuousKind::Spherical);
    EXPECT_LT(f.point.norm(), tolerance);
    EXPECT_NEAR(f.radius, 1.0, tolerance);
}

TEST(ContinuousFamilies, ANoisySurfaceThatOnlyComesNearASphereIsNoSphere) {
    // A spheroid stretched by 1.5 % along z, with the same noise: within the allowances for
    // roughness it lies near enough to a sphere, but its distance from the fitted sphere is
    // smooth and survives averaging over neighbourhoods, where the noise does not.
    Shape s = sphere(1.0, 5);
    s.V.col(2) *= 1.015;
    Analysed a;
    analyse(with_noise(s, 0.001 * 2 * std::sqrt(3.0), 5), a);
    const double tolerance = 0.01 * a.diagonal;
    ContinuousFamilyOptions options;
    options.roughness = surface_roughness(a.n);
    EXPECT_EQ(slippable_family(a.n, a.all, tolerance, options).kind, ContinuousKind::Discrete);
    options.max_systematic_share_off_sphere = 1;  // without the test, it passes for a sphere
    EXPECT_EQ(slippable_family(a.n, a.all, tolerance, options).kind, ContinuousKind::Spherical);
}

TEST(ContinuousFamilies, ARotoreflectionMemberGivesTheMirrorNormalToTheAxis) {
    const ContinuousFamily torus_family = revolution_about_z();
    const double tol = 1e-3, degrees = 1;
    // The mirror across z = 0.3, composed with a turn by 50 degrees about the axis.
    const Transformation mirror =
        Transformation::from_linear(Eigen::Vector3d(1, 1, -1).asDiagonal(), Eigen::Vector3d(0, 0, 0.6));
    Transformation turn;
    turn.rotation = Eigen::AngleAxisd(50 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Transformation rotoreflection = turn * mirror;
    ASSERT_TRUE(is_member(torus_family, rotoreflection, tol, degrees));
    const std::optional<Transformation> found = mirror_in_rotoreflection(torus_family, rotoreflection, degrees);
    ASSERT_TRUE(found.has_value());
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.4, -0.2, 0.1), Eigen::Vector3d(-1, 0.5, 0.9)})
        EXPECT_LT((found->apply(p) - mirror.apply(p)).norm(), 1e-12);
    // Nothing for the mirror itself, a turn, a mirror through the axis, or another family.
    EXPECT_FALSE(mirror_in_rotoreflection(torus_family, mirror, degrees).has_value());
    EXPECT_FALSE(mirror_in_rotoreflection(torus_family, turn, degrees).has_value());
    const Transformation through_axis = Transformation::from_linear(Eigen::Vector3d(-1, 1, 1).asDiagonal(), Eigen::Vector3d::Zero());
    EXPECT_FALSE(mirror_in_rotoreflection(torus_family, through_axis, degrees).has_value());
    ContinuousFamily helix = torus_family;
    helix.kind = ContinuousKind::Helical;
    EXPECT_FALSE(mirror_in_rotoreflection(helix, rotoreflection, degrees).has_value());
}

TEST(ContinuousFamilies, AMirrorAlongACylindersSideGivesTheMirrorThroughItsMiddle) {
    // A capped cylinder about z, its patch from z = -0.5 to 0.5 (the family's point in the
    // middle, as recorded).  Its side alone is mapped onto itself by the mirror across any
    // plane normal to the axis; only the one across z = 0 maps the caps too.
    ContinuousFamily cylinder = revolution_about_z();
    cylinder.slides_along_axis = true;
    const double tol = 0.01, degrees = 1;
    auto mirror_across = [](double z) {
        return Transformation::from_linear(Eigen::Vector3d(1, 1, -1).asDiagonal(), Eigen::Vector3d(0, 0, 2 * z));
    };
    const std::optional<Transformation> found = mirror_through_middle(cylinder, mirror_across(0.02), tol, degrees);
    ASSERT_TRUE(found.has_value());
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, 0, 0.5), Eigen::Vector3d(-0.1, 0.2, -0.5)})
        EXPECT_LT((found->apply(p) - mirror_across(0).apply(p)).norm(), 1e-12);
    // Nothing for a mirror that moves the caps by less than the tolerance (a plane 0.004
    // off the middle moves them by 0.008), a mirror through the axis, a rotoreflection
    // (mirror_in_rotoreflection's), a turn, or a mirror across a parallel axis's plane.
    EXPECT_FALSE(mirror_through_middle(cylinder, mirror_across(0.004), tol, degrees).has_value());
    const Transformation through_axis = Transformation::from_linear(Eigen::Vector3d(-1, 1, 1).asDiagonal(), Eigen::Vector3d::Zero());
    EXPECT_FALSE(mirror_through_middle(cylinder, through_axis, tol, degrees).has_value());
    Transformation turn;
    turn.rotation = Eigen::AngleAxisd(50 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_FALSE(mirror_through_middle(cylinder, turn * mirror_across(0.02), tol, degrees).has_value());
    EXPECT_FALSE(mirror_through_middle(cylinder, turn, tol, degrees).has_value());
    Transformation elsewhere = mirror_across(0.02);  // normal to the axis, but the axis moved off itself
    elsewhere.translation += Eigen::Vector3d(0.1, 0, 0);
    EXPECT_FALSE(mirror_through_middle(cylinder, elsewhere, tol, degrees).has_value());
}

TEST(ContinuousFamilies, MirrorsThroughOneLineGiveThatLineOnce) {
    // Planes through the line x = 0.3, y = -0.2 (along z) at five angles, oracle: the
    // line itself; beside them a plane parallel to one of them, and one normal to the line.
    const Eigen::Vector3d on_line(0.3, -0.2, 0.7);
    std::vector<Eigen::Vector4d> planes;
    auto plane = [](const Eigen::Vector3d& n, const Eigen::Vector3d& through) {
        return Eigen::Vector4d(n.x(), n.y(), n.z(), n.dot(through));
    };
    for (int k = 0; k < 5; ++k) {
        const double angle = k * M_PI / 5 + 0.1;
        planes.push_back(plane(Eigen::Vector3d(std::cos(angle), std::sin(angle), 0), on_line));
    }
    const Eigen::Vector3d n0 = planes[0].head<3>();
    planes.push_back(plane(n0, on_line + 0.5 * n0));                     // parallel to the first
    planes.push_back(plane(Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, 0, 0.4)));  // normal to the line
    const double tol = 0.01, degrees = 2;
    const std::vector<MirrorAxis> lines = lines_of_mirrors(planes, 3, tol, degrees);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_NEAR(std::abs(lines[0].direction.z()), 1, 1e-12);
    EXPECT_LT(((lines[0].point - on_line) - (lines[0].point - on_line).dot(lines[0].direction) * lines[0].direction).norm(), 1e-9);
    EXPECT_EQ(lines[0].mirrors, (std::vector<size_t>{0, 1, 2, 3, 4}));
    // A plane tilted by 5 degrees from the line, or passing 0.035 beside it, is not through
    // it.  (Nearer, the planes meet in other lines that three of them pass through within
    // the tolerance and angle.)
    std::vector<Eigen::Vector4d> off = {planes[0], planes[1]};
    const double tilt = 5 * M_PI / 180;
    off.push_back(plane(Eigen::Vector3d(0, std::cos(tilt), std::sin(tilt)), on_line));
    off.push_back(plane(Eigen::Vector3d(1, 1, 0).normalized(), on_line + Eigen::Vector3d(0.05, 0, 0)));
    EXPECT_TRUE(lines_of_mirrors(off, 3, tol, degrees).empty());
    // Two planes are not enough for three.
    EXPECT_TRUE(lines_of_mirrors({planes[0], planes[1]}, 3, tol, degrees).empty());
}

TEST(ContinuousFamilies, ATurnAboutTheAxisKeepsTheSurfaceOfRevolutionNotAFinAlongIt) {
    // A cylinder about z with a thin fin along the meridian plane y = 0 (a wingnut's blade
    // on its hub).  Oracle: the turn about z slides along the cylinder's side and moves
    // across the fin's two large faces, so the cylinder's vertices are tangent and the
    // fin's face vertices are not (its thin rim, whose normals lie in the meridian plane,
    // may be).
    const double R = 0.5;
    const Shape side = cylinder(R, 2.0, 96, 40);
    const Shape fin = transformed(box(0.3, 0.01, 0.6, 8), Eigen::Matrix3d::Identity(), Eigen::Vector3d(R + 0.3, 0, 1.0));
    Analysed a;
    analyse(merged(side, fin), a);
    const ContinuousFamilyOptions options;
    ContinuousFamily about_z = revolution_about_z();
    about_z.motions = {Motion::turn_about(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ())};
    const std::vector<int> kept = tangent_vertices(a.n, about_z, a.all, 0.01 * a.diagonal, options);
    std::vector<char> is_kept(a.all.size(), 0);
    for (int v : kept) is_kept[size_t(v)] = 1;
    const Eigen::Index side_vertices = side.V.rows();
    int side_kept = 0, fin_face_vertices = 0, fin_face_kept = 0;
    for (int v : a.all) {
        const Eigen::Vector3d& p = a.n.positions[size_t(v)];
        const bool on_side = std::abs(std::hypot(p.x(), p.y()) - R) < 1e-9 && v < side_vertices;
        side_kept += on_side && is_kept[size_t(v)];
        // Inside the fin's large faces (y = ±0.01), away from its rim.
        const bool fin_face = std::abs(std::abs(p.y()) - 0.01) < 1e-9 && std::abs(p.x() - (R + 0.3)) < 0.25 &&
                              std::abs(p.z() - 1.0) < 0.55;
        fin_face_vertices += fin_face;
        fin_face_kept += fin_face && is_kept[size_t(v)];
    }
    EXPECT_EQ(side_kept, int(side_vertices));
    EXPECT_GT(fin_face_vertices, 50);
    EXPECT_EQ(fin_face_kept, 0);
    EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
}

TEST(ContinuousFamilies, TheLeanOfAPatchFromAnAxisIsTheMeanSineOfItsNormals) {
    // Oracles: a cylinder's side about z leans 1 from z; a box's two faces normal to z lean
    // 0; a sphere leans π/4 from any axis (the area-weighted mean of sin θ, ∫ sin²θ dθ over
    // ∫ sin θ dθ on [0, π]).
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    Analysed side;
    analyse(cylinder(0.5, 2.0, 96, 40), side);
    EXPECT_NEAR(mean_lean_from(side.n, side.all, z), 1.0, 1e-9);

    Analysed slab;
    analyse(box(1.0, 0.8, 0.1, 10), slab);
    std::vector<int> top_and_bottom;
    for (int v : slab.all)
        if (std::abs(std::abs(slab.n.positions[size_t(v)].z()) - 0.1) < 1e-9) top_and_bottom.push_back(v);
    EXPECT_NEAR(mean_lean_from(slab.n, top_and_bottom, z), 0.0, 1e-9);
    EXPECT_GT(mean_lean_from(slab.n, slab.all, z), 0.05);  // with its rim

    Analysed ball;
    analyse(sphere(1.0, 4), ball);
    EXPECT_NEAR(mean_lean_from(ball.n, ball.all, z), M_PI / 4, 0.01);
    EXPECT_NEAR(mean_lean_from(ball.n, ball.all, Eigen::Vector3d(1, 2, 2) / 3), M_PI / 4, 0.01);
}
