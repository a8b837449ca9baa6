// Reliability suite (issue 25): outputs. Filled in by the work on that issue.
#include <gtest/gtest.h>

#include "end_to_end_fixture.h"
