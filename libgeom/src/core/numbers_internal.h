/* Private tables and helpers of core's number printer and parser. */
#ifndef GEOM_SRC_CORE_NUMBERS_INTERNAL_H
#define GEOM_SRC_CORE_NUMBERS_INTERNAL_H

#include <stdint.h>

enum { GEOM__POW5_QMIN = -342, GEOM__POW5_QMAX = 325,
       GEOM__POW5_COUNT = GEOM__POW5_QMAX - GEOM__POW5_QMIN + 1 };

/* 5^q as a normalised 128-bit significand (top bit set), truncated:
 * {high, low} at index q - GEOM__POW5_QMIN. See pow5_table.py. */
extern const uint64_t geom__pow5_128[GEOM__POW5_COUNT][2];

/* floor(log2(5^e)) + 1 = bit length of 5^e, for 0 <= e <= 3528. */
static inline int32_t geom__pow5_bits(int32_t e)
{
    return (int32_t)(((uint32_t)e * 1217359u) >> 19) + 1;
}

/* Decimal digits of v (1..20). */
int geom__decimal_length(uint64_t v);
/* Exactly n decimal digits of v (v < 10^n) at p[0..n), two at a time; no
 * NUL. Shared by the double printer and meshio's integer output. */
void geom__put_digits(char *p, uint64_t v, int n);

#endif
