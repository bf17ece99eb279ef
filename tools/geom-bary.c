/* geom-module: bary */
/*
 * geom-bary: barycentric coordinates of points in triangles, one per line.
 *
 * Input (FILE or standard input): one query per line, numbers separated by
 * whitespace and/or commas:
 *   12 numbers  ax ay az bx by bz cx cy cz px py pz   3D (geom_bary_tri3: p is
 *               projected orthogonally onto the triangle's plane)
 *    8 numbers  ax ay bx by cx cy px py               2D (geom_bary_tri2)
 * Blank lines and lines whose first non-blank character is '#' are skipped.
 *
 * Output, one line per query: "l1 l2 l3" with 17 significant digits (so the
 * values read back exactly; -0 is printed as 0), or "degenerate" for a
 * zero-area triangle. With --json, one JSON object per query:
 *   {"line":N,"status":"ok","l":[l1,l2,l3]}   or   {"line":N,"status":"degenerate"}
 * where N is the query's line number in the input.
 *
 * Errors: a malformed line (not 8 or 12 numbers, a bad number, NaN or
 * infinity) stops the run with "geom-bary: FILE:LINE:COL: message" on stderr
 * and exit status 1. Output is streamed: on standard output the results of
 * the lines before the bad one have already been written (and are kept);
 * with -o FILE nothing is written to FILE (the temporary file is removed and
 * an existing FILE is left untouched). A triangle so small relative to the
 * point's distance that a coordinate overflows the range of double is also
 * an error (exit 1), never printed as inf.
 */
#include "cli.h"

#include <math.h>

#include "geom/bary.h"

static const cli_tool tool = {
    "geom-bary",
    "[OPTION]... [FILE]",
    "Compute barycentric coordinates of points in triangles, one query per line\n"
    "of FILE (or standard input when FILE is '-' or absent).",
    NULL,
    "Each input line holds 12 numbers (3D: ax ay az bx by bz cx cy cz px py pz;\n"
    "p is projected onto the triangle's plane) or 8 numbers (2D: ax ay bx by cx cy\n"
    "px py), separated by whitespace and/or commas. Blank lines and lines starting\n"
    "with '#' are skipped. Each query prints 'l1 l2 l3' (p = l1 a + l2 b + l3 c,\n"
    "17 significant digits) or 'degenerate' for a zero-area triangle. With --json\n"
    "each query prints {\"line\":N,\"status\":\"ok\",\"l\":[l1,l2,l3]} or\n"
    "{\"line\":N,\"status\":\"degenerate\"}.\n"
    "A malformed line (wrong count, bad number, NaN/Inf) stops the run with\n"
    "'geom-bary: FILE:LINE:COL: message' and exit status 1; results already\n"
    "written to standard output are kept, an -o FILE is not created.\n",
    "  geom-bary data/bary_points.txt\n"
    "  geom-bary --json - < queries.txt\n",
};

/* Print one result line. l is ignored unless status is GEOM_OK. */
static void print_result(FILE *fp, bool json, size_t lineno, geom_status status,
                         const double l[3])
{
    if (json) {
        fprintf(fp, "{\"line\":%zu,\"status\":", lineno);
        if (status == GEOM_OK) {
            fputs("\"ok\",\"l\":[", fp);
            for (int i = 0; i < 3; i++) {
                if (i)
                    fputc(',', fp);
                cli_json_number(fp, l[i] + 0.0); /* + 0.0 turns -0 into 0 */
            }
            fputs("]}\n", fp);
        } else {
            fputs("\"degenerate\"}\n", fp);
        }
        return;
    }
    if (status == GEOM_OK) {
        for (int i = 0; i < 3; i++) {
            if (i)
                fputc(' ', fp);
            cli_print_double(fp, l[i] + 0.0);
        }
        fputc('\n', fp);
    } else {
        fputs("degenerate\n", fp);
    }
}

/* Process every line of `in`, writing to `out`. Returns GEOM_OK or an error
 * status with diag filled (source, line, column). */
static geom_status run(cli_lines *lines, FILE *out, bool json, geom_diag *diag)
{
    char *line;
    size_t len;
    int r;
    while ((r = cli_lines_next(lines, &line, &len, diag)) > 0) {
        if (cli_line_is_blank_or_comment(line, len))
            continue;
        double v[12];
        size_t n = 0;
        geom_status st = cli_parse_numbers(line, len, 0, v, 12, &n, diag);
        if (st != GEOM_OK) {
            cli_diag_locate(diag, lines->source, lines->lineno);
            return st;
        }
        double l[3];
        if (n == 12) {
            st = geom_bary_tri3(v, v + 3, v + 6, v + 9, l);
        } else if (n == 8) {
            st = geom_bary_tri2(v, v + 2, v + 4, v + 6, l);
        } else {
            return cli_diag_set(diag, GEOM_ERR_PARSE, lines->source, lines->lineno, len + 1,
                                "expected 8 (2D) or 12 (3D) numbers, found %zu", n);
        }
        if (st == GEOM_OK && !(isfinite(l[0]) && isfinite(l[1]) && isfinite(l[2])))
            return cli_diag_set(diag, GEOM_ERR_LIMIT, lines->source, lines->lineno, 1,
                                "barycentric coordinates overflow the range of double");
        if (st != GEOM_OK && st != GEOM_ERR_DEGENERATE)
            return cli_diag_set(diag, st, lines->source, lines->lineno, 1, "%s",
                                geom_status_str(st));
        print_result(out, json, lines->lineno, st, l);
    }
    return r < 0 ? (geom_status)r : GEOM_OK;
}

int main(int argc, char **argv)
{
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, NULL, NULL, NULL, NULL, &common, &first);
    if (rc != CLI_CONTINUE)
        return rc;
    rc = cli_operands(&tool, argc, argv, first, 0, 1);
    if (rc != CLI_CONTINUE)
        return rc;

    geom_diag diag;
    geom_diag_clear(&diag);
    cli_input in;
    if (cli_input_open(&in, first < argc ? argv[first] : NULL, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    cli_output out;
    if (cli_output_open(&out, common.output, &diag) != GEOM_OK) {
        cli_input_close(&in);
        return cli_print_diag(&tool, &diag);
    }

    cli_lines lines;
    cli_lines_init(&lines, in.fp, in.name);
    geom_status st = run(&lines, out.fp, common.json, &diag);
    cli_lines_free(&lines);
    cli_input_close(&in);

    if (st != GEOM_OK) {
        cli_output_abort(&out);
        return cli_print_diag(&tool, &diag);
    }
    if (cli_output_commit(&out, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    return CLI_EXIT_OK;
}
