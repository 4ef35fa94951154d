// Stage 8 (§4.1, Algorithm 1): symmetry basis reduction into generators and compound
// transformations.
#pragma once

#include "transformation_space.h"

#include <vector>

namespace symmetry {

/// A compound transformation written in the generators: letter +k (k >= 1) is generator
/// k-1, letter -k its inverse.  The identity I of the alphabet is never written.
using Word = std::vector<int>;

struct SymmetryBasis {
    std::vector<int> generators;  ///< indices into the input of the transformations kept as generators
    std::vector<Word> words;      ///< for every input transformation, its word; a generator g is {+(k+1)}
};

/// Algorithm 1: transformations are taken in the given order (decreasing significance);
/// each is written as the shortest product of at most `loop_length` (η) letters of the
/// alphabet A = {I} ∪ {A_k, A_k⁻¹} that lies within `tolerance` (δ) of it in `space`,
/// or else becomes a new generator.  Among words of equal length the closest wins.
SymmetryBasis reduce_basis(const std::vector<Transformation>& transformations, const TransformationSpace& space,
                           int loop_length, double tolerance);

/// The product a word stands for, in the given generators (rightmost letter applied first).
Transformation evaluate_word(const Word& word, const std::vector<Transformation>& generators);

}  // namespace symmetry
