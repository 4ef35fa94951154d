#include "detection.h"

namespace symmetry {

void DetectionOptions::validate() const {}

DetectionResult detect_partial_symmetries(const Eigen::MatrixX3d&, const Eigen::MatrixX3i&, const DetectionOptions&,
                                          const Progress&) {
    throw InputError("The detection pipeline is not built yet.");
}

}  // namespace symmetry
