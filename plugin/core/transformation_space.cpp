#include "transformation_space.h"
// Not written yet.
