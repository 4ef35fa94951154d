#include "transformation_space.h"

#include <Eigen/SVD>

#include <cmath>

namespace symmetry {

namespace {
// §3: a rotation by 180° (Frobenius distance 2√2) weighs as much as half the diagonal,
// and so does a scale factor of 10.  Lengths are already in units of the diagonal.
const double kRotationWeight = 0.5 / (2.0 * std::sqrt(2.0));
const double kScaleWeight = 0.5 / std::log(10.0);

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& A) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
    return svd.matrixU() * D * svd.matrixV().transpose();
}
}  // namespace

Eigen::Matrix3d Transformation::mirror() { return Eigen::Vector3d(-1, 1, 1).asDiagonal(); }

Eigen::Matrix3d Transformation::linear() const {
    return reflection ? Eigen::Matrix3d(scale * rotation * mirror()) : Eigen::Matrix3d(scale * rotation);
}

Eigen::Matrix4d Transformation::matrix() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = linear();
    m.topRightCorner<3, 1>() = translation;
    return m;
}

Eigen::Vector3d Transformation::apply(const Eigen::Vector3d& x) const { return linear() * x + translation; }

Eigen::Vector3d Transformation::apply_to_normal(const Eigen::Vector3d& n) const {
    return reflection ? Eigen::Vector3d(rotation * (mirror() * n)) : Eigen::Vector3d(rotation * n);
}

Transformation Transformation::from_linear(const Eigen::Matrix3d& A, const Eigen::Vector3d& t) {
    Transformation r;
    double det = A.determinant();
    r.reflection = det < 0;
    r.scale = std::cbrt(std::abs(det));
    // A = s R M^r, and M = M^-1, so R = A M^r / s.
    Eigen::Matrix3d R = r.reflection ? Eigen::Matrix3d(A * mirror()) : A;
    r.rotation = nearest_rotation(R / r.scale);
    r.translation = t;
    return r;
}

// Inverse and composition stay exact in the (scale, rotation, mirror) split, with no
// re-orthogonalisation, so long products in basis reduction (§4.1) do not drift.
Transformation Transformation::inverse() const {
    // (s R M^r)^-1 = (1/s) M^r Rᵀ = (1/s) (M^r Rᵀ M^r) M^r, and M^r Rᵀ M^r is a rotation.
    Transformation r;
    r.reflection = reflection;
    r.scale = 1.0 / scale;
    r.rotation = reflection ? Eigen::Matrix3d(mirror() * rotation.transpose() * mirror())
                            : Eigen::Matrix3d(rotation.transpose());
    r.translation = -(r.linear() * translation);
    return r;
}

Transformation Transformation::operator*(const Transformation& rhs) const {
    // s R M^a · s' R' M^b = s s' (R M^a R' M^b M^(a xor b)) M^(a xor b).
    Transformation r;
    r.scale = scale * rhs.scale;
    r.reflection = reflection != rhs.reflection;
    Eigen::Matrix3d L = rotation;
    if (reflection) L = L * mirror();
    L = L * rhs.rotation;
    if (rhs.reflection) L = L * mirror();
    if (r.reflection) L = L * mirror();
    r.rotation = L;
    r.translation = linear() * rhs.translation + translation;
    return r;
}

TransformationSpace::TransformationSpace(const Eigen::Vector3d& center, double diagonal)
    : center_(center), diagonal_(diagonal) {}

TransformationSpace::Point TransformationSpace::coordinates(const Transformation& t) const {
    Point p;
    p.head<3>() = (t.apply(center_) - center_) / diagonal_;
    p(3) = kScaleWeight * std::log(t.scale);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) p(4 + 3 * r + c) = kRotationWeight * t.rotation(r, c);
    return p;
}

void TransformationSpace::project(Eigen::Ref<Eigen::VectorXd> p) const {
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R(r, c) = p(4 + 3 * r + c) / kRotationWeight;
    R = nearest_rotation(R);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) p(4 + 3 * r + c) = kRotationWeight * R(r, c);
}

Transformation TransformationSpace::transformation(const Point& p, bool reflection) const {
    Transformation t;
    t.reflection = reflection;
    t.scale = std::exp(p(3) / kScaleWeight);
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R(r, c) = p(4 + 3 * r + c) / kRotationWeight;
    t.rotation = nearest_rotation(R);
    // p.head = (T(c) - c) / diag, with T(c) = A c + translation.
    t.translation = center_ + diagonal_ * p.head<3>() - t.linear() * center_;
    return t;
}

double TransformationSpace::rotation_degrees(double distance) {
    // A rotation by θ is 2√2 sin(θ/2) away from the identity in the Frobenius norm.
    const double s = std::min(1.0, distance / (kRotationWeight * 2 * std::sqrt(2.0)));
    return 2 * std::asin(s) * 180 / M_PI;
}

double TransformationSpace::distance(const Transformation& a, const Transformation& b) const {
    if (a.reflection != b.reflection) return INFINITY;
    return (coordinates(a) - coordinates(b)).norm();
}

namespace {
// Columns (direction1, direction2, normal): a right-handed orthonormal frame.
Eigen::Matrix3d frame(const SurfaceSignature& s) {
    Eigen::Matrix3d F;
    F << s.direction1, s.direction2, s.normal;
    return F;
}

double curvature_magnitude(const SurfaceSignature& s) { return std::hypot(s.kappa1, s.kappa2); }

bool parallel(const Eigen::Vector3d& a, const Eigen::Vector3d& b, bool up_to_sign) {
    double c = a.dot(b);
    if (up_to_sign) c = std::abs(c);
    return c >= std::cos(kFrameAngleTolerance);
}
}  // namespace

std::vector<Transformation> transformations_from_frames(const SurfaceSignature& a, const SurfaceSignature& b,
                                                        TransformationGroup group) {
    std::vector<Transformation> out;
    switch (group) {
    case TransformationGroup::Rigid:
    case TransformationGroup::Similarity: {
        double scale = 1;
        if (group == TransformationGroup::Similarity) {
            double ka = curvature_magnitude(a), kb = curvature_magnitude(b);
            if (!(ka > 0 && kb > 0)) return out;
            scale = ka / kb;  // curvature scales as 1/s
        }
        const Eigen::Matrix3d Fa = frame(a), Fb = frame(b);
        // Through the fixed mirror M the frame of a becomes (M d1, M d2, M n), which is
        // left-handed; flipping its second axis makes it right-handed again, and since a
        // principal direction's sign is arbitrary that frame is just as valid.
        const Eigen::Matrix3d Ga = Transformation::mirror() * Fa * Eigen::Vector3d(1, -1, 1).asDiagonal();
        const Eigen::Matrix3d flip = Eigen::Vector3d(-1, -1, 1).asDiagonal();  // the other sign choice
        for (bool reflection : {false, true}) {
            const Eigen::Matrix3d& source = reflection ? Ga : Fa;
            for (bool flipped : {false, true}) {
                Transformation t;
                t.reflection = reflection;
                t.scale = scale;
                t.rotation = flipped ? Eigen::Matrix3d(Fb * flip * source.transpose())
                                     : Eigen::Matrix3d(Fb * source.transpose());
                t.translation = b.position - t.linear() * a.position;
                out.push_back(t);
            }
        }
        break;
    }
    case TransformationGroup::Reflections: {
        Eigen::Vector3d d = b.position - a.position;
        double length = d.norm();
        if (!(length > 0)) return out;
        Eigen::Vector3d n = d / length;
        Eigen::Matrix3d H = Eigen::Matrix3d::Identity() - 2 * n * n.transpose();
        // The mirror through the bisector plane must also carry a's frame onto b's.
        if (!parallel(H * a.normal, b.normal, false) || !parallel(H * a.direction1, b.direction1, true)) return out;
        Transformation t;
        t.reflection = true;
        t.rotation = H * Transformation::mirror();  // H = R M
        t.translation = 2 * n.dot(0.5 * (a.position + b.position)) * n;
        out.push_back(t);
        break;
    }
    case TransformationGroup::Translations: {
        if (!parallel(a.normal, b.normal, false) || !parallel(a.direction1, b.direction1, true)) return out;
        Transformation t;
        t.translation = b.position - a.position;
        out.push_back(t);
        break;
    }
    }
    return out;
}

}  // namespace symmetry
