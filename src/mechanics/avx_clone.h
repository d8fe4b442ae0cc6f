#pragma once
/// VISCERA_AVX_CLONE: an AVX clone of a hot function of the mechanics (common/target_clones.h).
/// Products and sums only, never fused (-ffp-contract=off, src/mechanics/CMakeLists.txt) and
/// never reassociated (no -ffast-math): the AVX clone gives the baseline one's numbers bit for
/// bit, only with wider registers.
#include "common/target_clones.h"

#define VISCERA_AVX_CLONE VISCERA_TARGET_CLONES("avx")
