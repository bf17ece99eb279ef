/*
 * Image files for the scene tools: PNG (8-bit, through libspng) and PFM
 * (Portable Float Map: linear 32-bit floats). Colours in a geom_image are
 * linear; PNG files are sRGB-encoded (IEC 61966-2-1 transfer function).
 * Writers go through cli_output (temporary file, then rename).
 */
#ifndef GEOM_TOOLS_IMAGE_IO_H
#define GEOM_TOOLS_IMAGE_IO_H

#include <stdio.h>

#include "geom/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** sRGB transfer function and its inverse on [0, 1] (values clamped). */
double image_srgb_encode(double linear);
double image_srgb_decode(double encoded);

/** Write img (1 or 3 channels, linear) as an 8-bit PNG to fp: grey or RGB,
 *  sRGB-encoded when `srgb` is nonzero (colour) or linear bytes (data such as
 *  normals already mapped to [0,1]). GEOM_ERR_INVALID_ARG for other channel
 *  counts, GEOM_ERR_IO on a libspng or write error (diag names it). */
geom_status image_write_png(FILE *fp, const geom_image *img, int srgb, geom_diag *diag);

/** Write img (1 channel: "Pf", 3 channels: "PF") as a little-endian PFM
 *  (scale -1, rows bottom to top, as the format says). */
geom_status image_write_pfm(FILE *fp, const geom_image *img, geom_diag *diag);

/** Write to `path` by its extension: ".png" (srgb as image_write_png) or
 *  ".pfm"; GEOM_ERR_INVALID_ARG for another extension. Atomic. */
geom_status image_write_file(const char *path, const geom_image *img, int srgb, geom_diag *diag);

/**
 * Read a PNG (any bit depth and colour type) or PFM file into out (1 channel
 * for grey PNG/"Pf", 3 for colour, 4 when the PNG has alpha; alpha stays
 * linear). PNG values are mapped to [0,1] and decoded from sRGB to linear
 * when `srgb` is nonzero (colour textures), left as they are otherwise
 * (height and normal maps). Free with geom_scene_image_free(out, NULL).
 * GEOM_ERR_IO (cannot open), GEOM_ERR_PARSE (malformed: diag names the file),
 * GEOM_ERR_NOMEM.
 */
geom_status image_read_file(const char *path, int srgb, geom_image *out, geom_diag *diag);

#ifdef __cplusplus
}
#endif

#endif
