#include "basis_reduction.h"
// Not written yet.
