#include "signatures.h"
// Not written yet.
