/* PNG through libspng, PFM by hand. */
#include "image_io.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <spng.h>

#include "cli.h"

double image_srgb_encode(double x)
{
    if (!(x > 0))
        return 0;
    if (x >= 1)
        return 1;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
}

double image_srgb_decode(double x)
{
    if (!(x > 0))
        return 0;
    if (x >= 1)
        return 1;
    return x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4);
}

geom_status image_write_png(FILE *fp, const geom_image *img, int srgb, geom_diag *diag)
{
    if (!fp || !img || !img->data || (img->channels != 1 && img->channels != 3))
        return cli_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                            "PNG needs a 1- or 3-channel image");
    size_t n = (size_t)img->width * img->height * img->channels;
    unsigned char *buf = malloc(n ? n : 1);
    if (!buf)
        return cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
    for (size_t i = 0; i < n; i++) {
        double v = img->data[i];
        v = srgb ? image_srgb_encode(v) : (v > 0 ? (v < 1 ? v : 1) : 0);
        buf[i] = (unsigned char)lrint(v * 255.0);
    }
    spng_ctx *ctx = spng_ctx_new(SPNG_CTX_ENCODER);
    geom_status st = GEOM_OK;
    int err = ctx ? 0 : SPNG_EMEM;
    if (!err)
        err = spng_set_png_file(ctx, fp);
    if (!err) {
        struct spng_ihdr ih;
        memset(&ih, 0, sizeof ih);
        ih.width = img->width;
        ih.height = img->height;
        ih.bit_depth = 8;
        ih.color_type = img->channels == 3 ? SPNG_COLOR_TYPE_TRUECOLOR : SPNG_COLOR_TYPE_GRAYSCALE;
        err = spng_set_ihdr(ctx, &ih);
    }
    if (!err && srgb)
        err = spng_set_srgb(ctx, 0); /* perceptual intent */
    if (!err)
        err = spng_encode_image(ctx, buf, n, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
    if (err && ferror(fp)) /* the stream failed (ENOSPC, EIO): say why */
        st = cli_diag_set(diag, GEOM_ERR_IO, NULL, 0, 0, "write error: %s", strerror(errno));
    else if (err)
        st = cli_diag_set(diag, GEOM_ERR_IO, NULL, 0, 0, "PNG encoding failed: %s",
                          spng_strerror(err));
    spng_ctx_free(ctx);
    free(buf);
    return st;
}

geom_status image_write_pfm(FILE *fp, const geom_image *img, geom_diag *diag)
{
    if (!fp || !img || !img->data || (img->channels != 1 && img->channels != 3))
        return cli_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                            "PFM needs a 1- or 3-channel image");
    fprintf(fp, "%s\n%u %u\n-1.0\n", img->channels == 3 ? "PF" : "Pf", img->width, img->height);
    size_t row = (size_t)img->width * img->channels;
    float *buf = malloc(row * sizeof(float));
    if (!buf)
        return cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
    geom_status st = GEOM_OK;
    for (uint32_t j = img->height; j-- > 0 && st == GEOM_OK;) {
        for (size_t i = 0; i < row; i++) {
            float f = (float)img->data[(size_t)j * row + i];
            /* little-endian on disk */
            uint32_t u;
            memcpy(&u, &f, 4);
            unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8),
                                  (unsigned char)(u >> 16), (unsigned char)(u >> 24)};
            memcpy(&buf[i], b, 4);
        }
        if (fwrite(buf, sizeof(float), row, fp) != row)
            st = cli_diag_set(diag, GEOM_ERR_IO, NULL, 0, 0, "write error");
    }
    free(buf);
    return st;
}

geom_status image_write_file(const char *path, const geom_image *img, int srgb, geom_diag *diag)
{
    int png = cli_ends_with(path, ".png"), pfm = cli_ends_with(path, ".pfm");
    if (!png && !pfm)
        return cli_diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0,
                            "unknown image format (use .png or .pfm)");
    cli_output out;
    geom_status st = cli_output_open(&out, path, diag);
    if (st != GEOM_OK)
        return st;
    st = png ? image_write_png(out.fp, img, srgb, diag) : image_write_pfm(out.fp, img, diag);
    if (st != GEOM_OK) {
        cli_output_abort(&out);
        return st;
    }
    return cli_output_commit(&out, diag);
}

static geom_status read_pfm(const char *path, const unsigned char *d, size_t n, geom_image *out,
                            geom_diag *diag)
{
    char hdr[3] = {0};
    unsigned w = 0, h = 0;
    double scale = 0;
    int used = 0;
    char text[128];
    size_t tl = n < sizeof text - 1 ? n : sizeof text - 1;
    memcpy(text, d, tl);
    text[tl] = 0;
    if (sscanf(text, "%2s %u %u %lf%n", hdr, &w, &h, &scale, &used) != 4 || w == 0 || h == 0 ||
        (strcmp(hdr, "PF") && strcmp(hdr, "Pf")) || scale == 0 || used >= (int)tl)
        return cli_diag_set(diag, GEOM_ERR_PARSE, path, 1, 1, "not a PFM header");
    used++; /* the single whitespace after the scale */
    uint32_t ch = hdr[1] == 'F' ? 3 : 1;
    size_t need = (size_t)w * h * ch;
    if (need / ch / w != h || n - (size_t)used < need * 4)
        return cli_diag_set(diag, GEOM_ERR_PARSE, path, 0, 0, "PFM data too short");
    geom_status st = geom_scene_image_init(out, w, h, ch, NULL);
    if (st != GEOM_OK)
        return cli_diag_set(diag, st, path, 0, 0, "cannot allocate the image");
    const unsigned char *p = d + used;
    size_t row = (size_t)w * ch;
    for (size_t j = 0; j < h; j++)
        for (size_t i = 0; i < row; i++, p += 4) {
            uint32_t u = scale < 0 ? (uint32_t)p[0] | (uint32_t)p[1] << 8 |
                                         (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
                                   : (uint32_t)p[3] | (uint32_t)p[2] << 8 |
                                         (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
            float f;
            memcpy(&f, &u, 4);
            out->data[(h - 1 - j) * row + i] = f;
        }
    return GEOM_OK;
}

geom_status image_read_file(const char *path, int srgb, geom_image *out, geom_diag *diag)
{
    memset(out, 0, sizeof *out);
    geom_file file_;
    geom_status st = geom_file_map(path, NULL, &file_, diag);
    if (st != GEOM_OK)
        return st;
    const unsigned char *data = file_.data;
    size_t size = file_.size;
    if (size >= 2 && data[0] == 'P' && (data[1] == 'F' || data[1] == 'f')) {
        st = read_pfm(path, data, size, out, diag);
        geom_file_unmap(&file_);
        return st;
    }
    spng_ctx *ctx = spng_ctx_new(0);
    struct spng_ihdr ih;
    int err = ctx ? 0 : SPNG_EMEM;
    if (!err)
        err = spng_set_png_buffer(ctx, data, size);
    if (!err)
        err = spng_get_ihdr(ctx, &ih);
    size_t len = 0;
    int grey = 0, alpha = 0;
    if (!err) {
        grey = ih.color_type == SPNG_COLOR_TYPE_GRAYSCALE ||
               ih.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA;
        alpha = ih.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA ||
                ih.color_type == SPNG_COLOR_TYPE_GRAYSCALE_ALPHA;
        err = spng_decoded_image_size(ctx, SPNG_FMT_RGBA16, &len);
    }
    uint16_t *pix = NULL;
    if (!err) {
        pix = malloc(len);
        err = pix ? spng_decode_image(ctx, pix, len, SPNG_FMT_RGBA16, SPNG_DECODE_TRNS) : SPNG_EMEM;
    }
    if (err) {
        st = cli_diag_set(diag, err == SPNG_EMEM ? GEOM_ERR_NOMEM : GEOM_ERR_PARSE, path, 0, 0,
                          "PNG: %s", spng_strerror(err));
    } else {
        uint32_t ch = grey ? 1 : (alpha ? 4 : 3);
        st = geom_scene_image_init(out, ih.width, ih.height, ch, NULL);
        if (st == GEOM_OK) {
            size_t np = (size_t)ih.width * ih.height;
            for (size_t k = 0; k < np; k++)
                for (uint32_t c = 0; c < ch; c++) {
                    double v = pix[4 * k + c] / 65535.0;
                    if (srgb && c < 3)
                        v = image_srgb_decode(v);
                    out->data[k * ch + c] = v;
                }
        } else {
            cli_diag_set(diag, st, path, 0, 0, "cannot allocate the image");
        }
    }
    free(pix);
    spng_ctx_free(ctx);
    geom_file_unmap(&file_);
    return st;
}
