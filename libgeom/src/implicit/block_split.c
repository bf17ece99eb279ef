/*
 * Recursive subdivision of a box of blocks (a quadtree in 2D, an octree in
 * 3D): the block pruning shared by marching squares' block map
 * (contour_estimate.c) and marching cubes' block classes (iso/extract.c).
 */
#include "implicit/implicit_internal.h"

void geom__block_split(int dim, const size_t *b0, const size_t *b1, geom__block_visit visit,
                       void *user)
{
    int single = 1;
    for (int a = 0; a < dim; a++)
        single &= b1[a] - b0[a] == 1;
    if (!visit(user, b0, b1, single) || single)
        return;
    size_t mid[3];
    for (int a = 0; a < dim; a++)
        mid[a] = b1[a] - b0[a] > 1 ? b0[a] + (b1[a] - b0[a]) / 2 : b1[a];
    for (int q = 0; q < (1 << dim); q++) {
        size_t c0[3], c1[3];
        int empty = 0;
        for (int a = 0; a < dim; a++) {
            int up = (q >> a) & 1;
            c0[a] = up ? mid[a] : b0[a];
            c1[a] = up ? b1[a] : mid[a];
            empty |= c0[a] >= c1[a];
        }
        if (!empty)
            geom__block_split(dim, c0, c1, visit, user);
    }
}
