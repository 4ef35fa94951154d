#include "test_shapes.h"

#include <Eigen/LU>

#include <cmath>
#include <map>
#include <tuple>
#include <vector>

namespace symmetry::testing {

Shape sphere(double radius, int levels) {
    const double g = (1 + std::sqrt(5.0)) / 2;
    std::vector<Eigen::Vector3d> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                      {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (auto& p : v) p.normalize();
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back((v[a] + v[b]).normalized());
            return mid[key] = int(v.size()) - 1;
        };
        std::vector<Eigen::Vector3i> next;
        for (const auto& t : f) {
            int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            next.push_back({t[0], a, c});
            next.push_back({t[1], b, a});
            next.push_back({t[2], c, b});
            next.push_back({a, b, c});
        }
        f = next;
    }
    Shape s;
    s.V.resize(v.size(), 3);
    s.F.resize(f.size(), 3);
    for (size_t i = 0; i < v.size(); ++i) s.V.row(i) = radius * v[i].transpose();
    for (size_t i = 0; i < f.size(); ++i) s.F.row(i) = f[i].transpose();
    return s;
}

Shape cylinder(double radius, double height, int around, int along) {
    Shape s;
    s.V.resize(around * (along + 1), 3);
    for (int j = 0; j <= along; ++j)
        for (int i = 0; i < around; ++i) {
            double a = 2 * M_PI * i / around;
            s.V.row(j * around + i) << radius * std::cos(a), radius * std::sin(a), height * j / along;
        }
    s.F.resize(2 * around * along, 3);
    int k = 0;
    for (int j = 0; j < along; ++j)
        for (int i = 0; i < around; ++i) {
            int a = j * around + i, b = j * around + (i + 1) % around, c = a + around, d = b + around;
            s.F.row(k++) << a, b, d;
            s.F.row(k++) << a, d, c;
        }
    return s;
}

Shape torus(double R, double r, int around, int tube) {
    Shape s;
    s.V.resize(around * tube, 3);
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < tube; ++j) {
            double u = 2 * M_PI * i / around, w = 2 * M_PI * j / tube;
            s.V.row(i * tube + j) << (R + r * std::cos(w)) * std::cos(u), (R + r * std::cos(w)) * std::sin(u),
                r * std::sin(w);
        }
    s.F.resize(2 * around * tube, 3);
    int k = 0;
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < tube; ++j) {
            int a = i * tube + j, b = ((i + 1) % around) * tube + j, c = i * tube + (j + 1) % tube,
                d = ((i + 1) % around) * tube + (j + 1) % tube;
            s.F.row(k++) << a, b, d;
            s.F.row(k++) << a, d, c;
        }
    return s;
}

Shape deformed_torus(double R, double r, int around, int tube, const std::function<double(double)>& tube_scale) {
    Shape s = torus(R, r, around, tube);
    for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
        Eigen::Vector3d p = s.V.row(i);
        double u = std::atan2(p.y(), p.x());
        Eigen::Vector3d centre(R * std::cos(u), R * std::sin(u), 0.0);
        s.V.row(i) = (centre + (p - centre) * tube_scale(u)).transpose();
    }
    return s;
}

Shape box(double a, double b, double c, int n) {
    // Each face: a grid over the two free axes at the fixed coordinate, oriented outwards.
    Shape s;
    std::vector<Eigen::Vector3d> v;
    std::vector<Eigen::Vector3i> f;
    const Eigen::Vector3d half(a, b, c);
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
            const int u = (axis + 1) % 3, w = (axis + 2) % 3;
            const int first = int(v.size());
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n; ++j) {
                    Eigen::Vector3d p;
                    p[axis] = side * half[axis];
                    p[u] = half[u] * (2.0 * i / n - 1);
                    p[w] = half[w] * (2.0 * j / n - 1);
                    v.push_back(p);
                }
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    int p00 = first + i * (n + 1) + j, p10 = p00 + n + 1, p01 = p00 + 1, p11 = p10 + 1;
                    // (u, w, axis) is right-handed: u x w = +axis, so (p00, p10, p11) faces +axis.
                    if (side > 0) { f.push_back({p00, p10, p11}); f.push_back({p00, p11, p01}); }
                    else { f.push_back({p00, p11, p10}); f.push_back({p00, p01, p11}); }
                }
        }
    // Weld the vertices the faces share along the edges.
    std::map<std::tuple<long, long, long>, int> index;
    std::vector<int> remap(v.size());
    std::vector<Eigen::Vector3d> welded;
    for (size_t i = 0; i < v.size(); ++i) {
        auto key = std::make_tuple(std::lround(v[i].x() * 1e6), std::lround(v[i].y() * 1e6), std::lround(v[i].z() * 1e6));
        auto it = index.find(key);
        if (it == index.end()) { index[key] = int(welded.size()); remap[i] = int(welded.size()); welded.push_back(v[i]); }
        else remap[i] = it->second;
    }
    s.V.resize(Eigen::Index(welded.size()), 3);
    for (size_t i = 0; i < welded.size(); ++i) s.V.row(Eigen::Index(i)) = welded[i].transpose();
    s.F.resize(Eigen::Index(f.size()), 3);
    for (size_t i = 0; i < f.size(); ++i) s.F.row(Eigen::Index(i)) << remap[size_t(f[i][0])], remap[size_t(f[i][1])], remap[size_t(f[i][2])];
    return s;
}

Shape transformed(const Shape& s, const Eigen::Matrix3d& A, const Eigen::Vector3d& t) {
    Shape out = s;
    for (Eigen::Index i = 0; i < s.V.rows(); ++i) out.V.row(i) = (A * s.V.row(i).transpose() + t).transpose();
    if (A.determinant() < 0) out.F.col(1).swap(out.F.col(2));
    return out;
}

Shape merged(const Shape& a, const Shape& b) {
    Shape out;
    out.V.resize(a.V.rows() + b.V.rows(), 3);
    out.V << a.V, b.V;
    out.F.resize(a.F.rows() + b.F.rows(), 3);
    out.F << a.F, (b.F.array() + int(a.V.rows())).matrix();
    return out;
}

}  // namespace symmetry::testing
