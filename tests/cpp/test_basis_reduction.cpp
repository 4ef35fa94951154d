// Algorithm 1 (§4.1) on groups whose generators are known.
#include "core/basis_reduction.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

using namespace symmetry;

namespace {
Transformation translation(double x, double y, double z) {
    Transformation t;
    t.translation = Eigen::Vector3d(x, y, z);
    return t;
}
Transformation rotation_z(double angle) {
    Transformation t;
    t.rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return t;
}
const TransformationSpace space(Eigen::Vector3d::Zero(), 10.0);
}  // namespace

TEST(BasisReduction, RowOfCopiesHasOneGenerator) {
    // A row of four copies: T, T², T³ and the inverse of T all come from T.
    std::vector<Transformation> T = {translation(1, 0, 0), translation(2, 0, 0), translation(3, 0, 0),
                                     translation(-1, 0, 0)};
    SymmetryBasis basis = reduce_basis(T, space, 3, 0.01);
    ASSERT_EQ(basis.generators, std::vector<int>({0}));
    EXPECT_EQ(basis.words[1], Word({1, 1}));
    EXPECT_EQ(basis.words[2], Word({1, 1, 1}));
    EXPECT_EQ(basis.words[3], Word({-1}));
    for (size_t i = 0; i < T.size(); ++i)
        EXPECT_LT(space.distance(evaluate_word(basis.words[i], {T[0]}), T[i]), 1e-12);
}

TEST(BasisReduction, LoopLengthLimitsTheSearch) {
    std::vector<Transformation> T = {translation(1, 0, 0), translation(3, 0, 0)};
    EXPECT_EQ(reduce_basis(T, space, 2, 0.01).generators.size(), 2u);  // 3 = 1+1+1 needs η = 3
    EXPECT_EQ(reduce_basis(T, space, 3, 0.01).generators.size(), 1u);
}

TEST(BasisReduction, GridNeedsTwoGenerators) {
    std::vector<Transformation> T = {translation(1, 0, 0), translation(0, 1, 0), translation(1, 1, 0),
                                     translation(2, -1, 0)};
    SymmetryBasis basis = reduce_basis(T, space, 3, 0.01);
    EXPECT_EQ(basis.generators, std::vector<int>({0, 1}));
    EXPECT_EQ(basis.words[2].size(), 2u);
    EXPECT_EQ(basis.words[3].size(), 3u);
}

TEST(BasisReduction, CyclicRotationGroupAndTolerance) {
    // C4: the quarter turn generates the half and three-quarter turns; a slightly
    // perturbed half turn is still compound within δ, but not within a tiny δ.
    std::vector<Transformation> T = {rotation_z(M_PI / 2), rotation_z(M_PI + 0.01), rotation_z(-M_PI / 2)};
    SymmetryBasis basis = reduce_basis(T, space, 3, 0.02);
    EXPECT_EQ(basis.generators, std::vector<int>({0}));
    EXPECT_EQ(basis.words[2], Word({-1}));
    EXPECT_EQ(reduce_basis(T, space, 3, 1e-4).generators, std::vector<int>({0, 1}));
}

TEST(BasisReduction, MirrorsAreTheirOwnInverse) {
    Transformation mirror;
    mirror.reflection = true;
    std::vector<Transformation> T = {mirror, translation(2, 0, 0), mirror * translation(2, 0, 0)};
    SymmetryBasis basis = reduce_basis(T, space, 2, 0.01);
    EXPECT_EQ(basis.generators, std::vector<int>({0, 1}));
    EXPECT_EQ(basis.words[2], Word({1, 2}));
}
