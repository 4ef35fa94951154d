#include "pairing.h"
// Not written yet.
