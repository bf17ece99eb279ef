/* Uses only the bary module: tests/link checks which objects get linked. */
#include "geom/bary.h"

#include <stdio.h>

int main(void)
{
    const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, p[2] = {0.25, 0.25};
    double l[3];
    if (geom_bary_tri2(a, b, c, p, l) != GEOM_OK)
        return 1;
    printf("%.17g %.17g %.17g\n", l[0], l[1], l[2]);
    return l[0] == 0.5 && l[1] == 0.25 && l[2] == 0.25 ? 0 : 1;
}
