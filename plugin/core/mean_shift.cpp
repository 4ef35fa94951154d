#include "mean_shift.h"
// Not written yet.
