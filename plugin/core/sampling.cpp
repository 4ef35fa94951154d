#include "sampling.h"
// Not written yet.
