/* Out-of-tree consumer of the installed libgeom. */
#include <geom/geom.h>

#include <stdio.h>
#include <string.h>

int main(void)
{
    geom_vec3 n;
    if (geom_vec3_normalize(geom_vec3_make(3, 0, 4), &n) != GEOM_OK || n.x != 0.6)
        return 1;
    if (strcmp(geom_version_string(), GEOM_VERSION_STRING) != 0)
        return 1;
    printf("libgeom %s ok\n", geom_version_string());
    return 0;
}
