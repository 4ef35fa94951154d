#include "verification.h"
// Not written yet.
