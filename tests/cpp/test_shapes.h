// Analytic shapes for the unit tests, as (V, F) arrays with outward-facing triangles.
#pragma once

#include <Eigen/Core>

#include <functional>

namespace symmetry::testing {

struct Shape {
    Eigen::MatrixX3d V;
    Eigen::MatrixX3i F;
};

/// Sphere of the given radius: an icosahedron subdivided `levels` times and projected.
Shape sphere(double radius, int levels);
/// Open cylinder around the z axis, z in [0, height], `around` by `along` quads split in two.
Shape cylinder(double radius, double height, int around, int along);
/// Torus around the z axis: tube radius r at distance R from the axis.
Shape torus(double R, double r, int around, int tube);
/// Torus whose tube radius at angle u around the axis is r * tube_scale(u): with a
/// non-constant scale it has no continuous rotational symmetry.
Shape deformed_torus(double R, double r, int around, int tube, const std::function<double(double)>& tube_scale);
/// Closed box [-a, a] x [-b, b] x [-c, c], every face an n by n grid of quads split in two.
Shape box(double a, double b, double c, int n);
/// Apply x -> A x + t to every vertex; flips the faces' orientation when det(A) < 0 so the
/// normals stay outward.
Shape transformed(const Shape& s, const Eigen::Matrix3d& A, const Eigen::Vector3d& t);
/// Two shapes in one mesh.
Shape merged(const Shape& a, const Shape& b);

}  // namespace symmetry::testing
