#pragma once
// svr::Error, which the public API declares (include/svr/error.h).

#include "svr/error.h"
