/* Private to the step module: the Part 21 instance table, the B-rep
 * builder and the evaluators shared by the mapping and the tessellation. */
#ifndef GEOM_SRC_STEP_INTERNAL_H
#define GEOM_SRC_STEP_INTERNAL_H

#include "core/internal.h"
#include "geom/step.h"

#include <stdint.h>

/* ------------------------------------------------------------ Part 21 */

enum {
    GEOM__P21_NULL = 0, /* $ */
    GEOM__P21_DERIVED,  /* * */
    GEOM__P21_INT,
    GEOM__P21_REAL,
    GEOM__P21_STRING,   /* off: pool offset (NUL-terminated UTF-8), n: length */
    GEOM__P21_ENUM,     /* off: pool offset of the name without dots */
    GEOM__P21_REF,      /* u.ref: entity index after resolution; n, off: line, column */
    GEOM__P21_LIST,     /* off: first child value, n: count */
    GEOM__P21_TYPED,    /* u.name: pool offset of the type; off: the one child value */
    GEOM__P21_BINARY    /* off: pool offset of the hex digits */
};

typedef struct geom__p21_value {
    uint32_t kind;
    uint32_t n;
    uint64_t off;
    union {
        double r;
        int64_t i;
        uint64_t ref;
        uint64_t name;
    } u;
} geom__p21_value;

typedef struct geom__p21_part_t {
    uint32_t name; /* pool offset of the type name (upper case) */
    uint32_t args; /* value index of its parameter list */
} geom__p21_part_t;

typedef struct geom__p21_entity {
    uint64_t id;
    uint32_t first_part, nparts;
    uint32_t line, column;
} geom__p21_entity;

typedef struct geom__p21 {
    const geom_allocator *alloc;
    geom__p21_value *vals;
    size_t nvals, capvals;
    geom__p21_part_t *parts;
    size_t nparts, capparts;
    geom__p21_entity *ents;
    size_t nents, capents;
    char *pool;
    size_t npool, cappool;
    geom__hindex hash; /* entity index by id (core's hash index) */
    size_t nheader; /* header entities come first in ents (id 0) */
    char source[GEOM_DIAG_MESSAGE_MAX];
} geom__p21;

/* Parse the whole text; on success the table is complete and every
 * reference resolved to an entity index. */
geom_status geom__p21_parse(geom__p21 *p, const char *text, size_t size, const char *source,
                            size_t max_bytes, int max_depth, const geom_allocator *alloc,
                            geom_diag *diag);
void geom__p21_free(geom__p21 *p);
/* Entity index of #id, or UINT32_MAX. */
uint32_t geom__p21_find(const geom__p21 *p, uint64_t id);
/* The part of entity e named `name` (any part of a complex instance), or NULL. */
const geom__p21_part_t *geom__p21_part(const geom__p21 *p, uint32_t e, const char *name);
static inline const char *geom__p21_str(const geom__p21 *p, uint64_t off)
{
    return p->pool + off;
}
/* The type name of a simple instance, or of the first part of a complex one. */
const char *geom__p21_type(const geom__p21 *p, uint32_t e);

/* --------------------------------------------------------- evaluators */

void geom__brep_curve_eval(const geom_brep_curve *c, double t, double *p, double *d);
void geom__brep_surface_eval(const geom_brep *b, const geom_brep_surface *s, double u, double v,
                             double p[3], double du[3], double dv[3]);
/* Closest parameter on curve c to q (3D), starting from the guess when
 * has_guess, else from samples. Returns the distance. */
double geom__brep_curve_invert(const geom_brep_curve *c, const double q[3], double guess,
                               int has_guess, double *t);
/* Closest (u, v) on surface s to q, from a guess (has_guess) or samples;
 * returns the distance. */
double geom__brep_surface_invert(const geom_brep *b, const geom_brep_surface *s, const double q[3],
                                 const double guess[2], int has_guess, double uv[2]);
/* Parameter range of a curve: bounded curves give their domain, others
 * (line, circle) return 0. */
int geom__brep_curve_domain(const geom_brep_curve *c, double *t0, double *t1);
int geom__brep_curve_periodic(const geom_brep_curve *c);

/* The default chordal tolerance: 1e-3 of the diagonal of the vertices'
 * box (estimate.c; geom_brep_tess_options::tolerance 0). */
double geom__step_default_tolerance(const geom_brep *b);

#endif
