#include "surface_query.h"
// Not written yet.
