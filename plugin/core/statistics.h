// An order statistic several stages take of their measurements.
#pragma once

#include <algorithm>
#include <vector>

namespace symmetry {

/// The median of `values` (of an even count, the upper of the two middle ones), 0 if there
/// are none.  Takes its own copy, which it reorders.
inline double median(std::vector<double> values) {
    if (values.empty()) return 0;
    const auto middle = values.begin() + long(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
}

}  // namespace symmetry
