#include "basis_reduction.h"

#include <cmath>
#include <cstdlib>

namespace symmetry {

namespace {
Transformation letter(int l, const std::vector<Transformation>& generators) {
    const Transformation& g = generators[std::abs(l) - 1];
    return l > 0 ? g : g.inverse();
}

// Depth-first enumeration of the words of exactly `length` letters, keeping the closest
// one to `target` within `tolerance`.  Prefix products are reused along the recursion.
void search(const Transformation& prefix, Word& word, int length, const std::vector<Transformation>& letters,
            const std::vector<int>& names, const Transformation& target, const TransformationSpace& space,
            double tolerance, Word& best, double& best_distance) {
    if (int(word.size()) == length) {
        double d = space.distance(prefix, target);
        if (d <= tolerance && d < best_distance) { best_distance = d; best = word; }
        return;
    }
    for (size_t k = 0; k < letters.size(); ++k) {
        // A letter next to its own inverse cancels: that word has a shorter equivalent.
        if (!word.empty() && word.back() == -names[k]) continue;
        word.push_back(names[k]);
        search(prefix * letters[k], word, length, letters, names, target, space, tolerance, best, best_distance);
        word.pop_back();
    }
}
}  // namespace

Transformation evaluate_word(const Word& word, const std::vector<Transformation>& generators) {
    Transformation product;
    for (int l : word) product = product * letter(l, generators);
    return product;
}

SymmetryBasis reduce_basis(const std::vector<Transformation>& transformations, const TransformationSpace& space,
                           int loop_length, double tolerance) {
    SymmetryBasis basis;
    std::vector<Transformation> generators;  // A without I; the letters are A_k and A_k⁻¹
    for (size_t i = 0; i < transformations.size(); ++i) {
        const Transformation& T = transformations[i];
        std::vector<Transformation> letters;
        std::vector<int> names;
        for (size_t k = 0; k < generators.size(); ++k) {
            letters.push_back(generators[k]);
            names.push_back(int(k) + 1);
            letters.push_back(generators[k].inverse());
            names.push_back(-(int(k) + 1));
        }
        Word best;
        double best_distance = INFINITY;
        for (int length = 1; length <= loop_length && best.empty(); ++length) {
            Word word;
            search(Transformation(), word, length, letters, names, T, space, tolerance, best, best_distance);
        }
        if (best.empty()) {
            generators.push_back(T);
            basis.generators.push_back(int(i));
            basis.words.push_back({int(generators.size())});
        } else {
            basis.words.push_back(best);
        }
    }
    return basis;
}

}  // namespace symmetry
