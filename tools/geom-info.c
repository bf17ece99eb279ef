/* geom-module: meshio */
/*
 * geom-info: topology and attribute summary of a mesh file.
 *
 * Reads FILE (OBJ, OFF, PLY or STL; "-" or no FILE: standard input, whose
 * format comes from --format or from its content) with geom_meshio_read and
 * prints, from geom_mesh_topology_summary and the mesh's channels:
 *   vertices, faces, edges, boundary_loops, components, euler, genus (summed
 *   over components), manifold, closed, degenerate_faces, bbox, attributes
 * one "key: value" per line, or with --json one JSON object with exactly
 * those keys plus "file", "format", "isolated_vertices", "repairs" (the
 * build report: what geom_mesh_build changed) and "skipped" (what the reader
 * skipped). Without --json the repairs, when there are any, go to standard
 * error as "geom-info: FILE: repaired: ..." lines.
 *
 * Exit status 0 on success, 1 on a read or parse error (the message names
 * FILE:LINE:COL or the byte offset), 2 on a usage error.
 */
#include "cli.h"
#include "cli_mesh.h"

#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

static const cli_tool tool = {
    "geom-info",
    "[OPTION]... [FILE]",
    "Print the topology (counts, Euler characteristic, genus, boundary loops,\n"
    "components, manifoldness) and the attributes of the mesh in FILE (OBJ, OFF,\n"
    "PLY or STL; standard input when FILE is '-' or absent).",
    "  -f, --format=FMT     input format (obj, off, ply, stl); default: from the\n"
    "                       file name's extension, else from the content\n"
    "      --skip-invalid   skip faces with repeated or missing vertices instead of\n"
    "                       failing (they are counted under repairs)\n",
    "Keys printed: vertices, faces, edges, boundary_loops, components, euler,\n"
    "genus (sum over components), manifold, closed, degenerate_faces, bbox\n"
    "(min x y z, max x y z), attributes (name, domain, components, values).\n"
    "With --json the same keys in one JSON object, plus file, format,\n"
    "isolated_vertices, repairs and skipped. Without --json, repairs made while\n"
    "building the mesh are reported on standard error.\n",
    "  geom-info bunny.off\n"
    "  geom-info --json mesh.ply > report.json\n",
};

enum { OPT_SKIP_INVALID = CLI_OPT_TOOL_BASE };

typedef struct info_opts {
    geom_meshio_format format;
    int skip_invalid;
} info_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    info_opts *o = user;
    if (opt == 'f') {
        return cli_mesh_format_option(t, arg, 1, &o->format);
    }
    if (opt == OPT_SKIP_INVALID) {
        o->skip_invalid = 1;
        return CLI_CONTINUE;
    }
    return CLI_EXIT_USAGE;
}

/* Read all of fp into a malloc'd buffer. */
static const char *domain_name(geom_mesh_domain d)
{
    switch (d) {
    case GEOM_MESH_DOMAIN_VERTEX: return "vertex";
    case GEOM_MESH_DOMAIN_FACE: return "face";
    case GEOM_MESH_DOMAIN_EDGE: return "edge";
    case GEOM_MESH_DOMAIN_CORNER: return "corner";
    }
    return "unknown";
}

typedef struct repair_item {
    const char *key;
    size_t n;
} repair_item;

static size_t repairs_list(const geom_mesh_build_report *r, repair_item *items)
{
    size_t k = 0;
    items[k++] = (repair_item){"invalid_faces", r->invalid_faces};
    items[k++] = (repair_item){"flipped_faces", r->flipped_faces};
    items[k++] = (repair_item){"nonmanifold_edges", r->nonmanifold_edges};
    items[k++] = (repair_item){"detached_faces", r->detached_faces};
    items[k++] = (repair_item){"split_vertices", r->split_vertices};
    items[k++] = (repair_item){"added_vertices", r->added_vertices};
    items[k++] = (repair_item){"isolated_vertices", r->isolated_vertices};
    items[k++] = (repair_item){"nonorientable_components", r->nonorientable_components};
    return k;
}

static void print_text(FILE *fp, const geom_mesh *m, const geom_mesh_topology *t)
{
    fprintf(fp, "vertices: %zu\nfaces: %zu\nedges: %zu\nboundary_loops: %zu\ncomponents: %zu\n",
            t->vertices, t->faces, t->edges, t->boundary_loops, t->components);
    fprintf(fp, "euler: %ld\ngenus: %ld\nmanifold: %s\nclosed: %s\ndegenerate_faces: %zu\n",
            t->euler, t->genus, t->manifold ? "true" : "false", t->closed ? "true" : "false",
            t->degenerate_faces);
    geom_aabb b = geom_mesh_bbox(m);
    fputs("bbox:", fp);
    if (geom_aabb_is_empty(b)) {
        fputs(" empty", fp);
    } else {
        const double v[6] = {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
        for (int i = 0; i < 6; i++) {
            fputc(' ', fp);
            cli_print_double(fp, v[i]);
        }
    }
    fputs("\nattributes:", fp);
    size_t nc = geom_mesh_channel_count(m), shown = 0;
    for (uint32_t c = 0; c < nc; c++) {
        fprintf(fp, "%s %s (%s, %zu, %zu)", shown ? "," : "", geom_mesh_channel_name(m, c),
                domain_name(geom_mesh_channel_domain(m, c)), geom_mesh_channel_ncomp(m, c),
                geom_mesh_channel_size(m, c));
        shown++;
    }
    fputc('\n', fp);
}

static void print_json(FILE *fp, const char *file, geom_meshio_format fmt, const geom_mesh *m,
                       const geom_mesh_topology *t, const geom_mesh_build_report *r,
                       const geom_meshio_read_stats *st, const char *warning)
{
    fputs("{\"file\":", fp);
    cli_json_string(fp, file);
    if (warning) {
        fputs(",\"warnings\":[", fp);
        cli_json_string(fp, warning);
        fputs("]", fp);
    }
    fprintf(fp, ",\"format\":\"%s\"", geom_meshio_format_name(fmt));
    fprintf(fp, ",\"vertices\":%zu,\"faces\":%zu,\"edges\":%zu,\"boundary_loops\":%zu", t->vertices,
            t->faces, t->edges, t->boundary_loops);
    fprintf(fp, ",\"components\":%zu,\"euler\":%ld,\"genus\":%ld,\"manifold\":%s,\"closed\":%s",
            t->components, t->euler, t->genus, t->manifold ? "true" : "false",
            t->closed ? "true" : "false");
    fprintf(fp, ",\"degenerate_faces\":%zu,\"isolated_vertices\":%zu,\"bbox\":",
            t->degenerate_faces, t->isolated_vertices);
    geom_aabb b = geom_mesh_bbox(m);
    if (geom_aabb_is_empty(b)) {
        fputs("null", fp);
    } else {
        const double v[6] = {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
        fputs("{\"min\":[", fp);
        for (int i = 0; i < 6; i++) {
            if (i == 3)
                fputs("],\"max\":[", fp);
            else if (i)
                fputc(',', fp);
            cli_json_number(fp, v[i]);
        }
        fputs("]}", fp);
    }
    fputs(",\"attributes\":[", fp);
    size_t nc = geom_mesh_channel_count(m);
    for (uint32_t c = 0; c < nc; c++) {
        fputs(c ? ",{\"name\":" : "{\"name\":", fp);
        cli_json_string(fp, geom_mesh_channel_name(m, c));
        fprintf(fp, ",\"domain\":\"%s\",\"ncomp\":%zu,\"size\":%zu}",
                domain_name(geom_mesh_channel_domain(m, c)), geom_mesh_channel_ncomp(m, c),
                geom_mesh_channel_size(m, c));
    }
    fputs("],\"repairs\":{", fp);
    repair_item items[8];
    size_t n = repairs_list(r, items);
    for (size_t i = 0; i < n; i++)
        fprintf(fp, "%s\"%s\":%zu", i ? "," : "", items[i].key, items[i].n);
    fprintf(fp, "},\"skipped\":{\"statements\":%zu,\"elements\":%zu,\"properties\":%zu}",
            st->skipped_statements, st->skipped_elements, st->skipped_properties);
    fprintf(fp, ",\"tags\":%zu,\"groups\":%zu,\"polylines\":%zu}\n", geom_mesh_tag_count(m),
            geom_mesh_group_count(m), geom_mesh_polyline_count(m));
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"format", required_argument, NULL, 'f'},
                                             {"skip-invalid", no_argument, NULL, OPT_SKIP_INVALID},
                                             {NULL, 0, NULL, 0}};
    info_opts io = {GEOM_MESHIO_FORMAT_AUTO, 0};
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "f:", longopts, on_option, &io, &common, &first);
    if (rc != CLI_CONTINUE)
        return rc;
    rc = cli_operands(&tool, argc, argv, first, 0, 1);
    if (rc != CLI_CONTINUE)
        return rc;

    geom_diag diag;
    geom_diag_clear(&diag);
    char *name;
    geom_meshio_read_stats stats;
    geom_mesh *m;
    geom_mesh_build_report report;
    geom_status st = cli_mesh_read_input(first < argc ? argv[first] : NULL, io.format,
                                         io.skip_invalid, &m, &report, &stats, &name, &diag);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    /* Nothing read: a file of another kind (every statement unrecognised)
     * is an error; a truly empty mesh is a warning. */
    const char *warning = NULL;
    if (geom_mesh_n_vertices(m) == 0 && geom_mesh_n_faces(m) == 0) {
        if (stats.skipped_statements || stats.skipped_elements) {
            cli_diag_set(&diag, GEOM_ERR_PARSE, name, 0, 0,
                         "not a mesh (read as %s): no vertices or faces, %zu unrecognised %s (first: '%s')",
                         geom_meshio_format_name(stats.format),
                         stats.skipped_statements ? stats.skipped_statements
                                                  : stats.skipped_elements,
                         stats.skipped_statements ? "statements" : "elements",
                         stats.first_skipped);
            geom_mesh_destroy(m);
            free(name);
            return cli_print_diag(&tool, &diag);
        }
        warning = "empty mesh: no vertices or faces";
        fprintf(stderr, "%s: %s: warning: %s\n", tool.name, name, warning);
    }
    geom_mesh_topology topo;
    st = geom_mesh_topology_summary(m, &topo);
    if (st != GEOM_OK) {
        cli_diag_set(&diag, st, name, 0, 0, "topology summary failed: %s", geom_status_str(st));
        geom_mesh_destroy(m);
        free(name);
        return cli_print_diag(&tool, &diag);
    }
    cli_output out;
    if (cli_output_open(&out, common.output, &diag) != GEOM_OK) {
        geom_mesh_destroy(m);
        free(name);
        return cli_print_diag(&tool, &diag);
    }
    if (common.json) {
        print_json(out.fp, name, stats.format, m, &topo, &report, &stats, warning);
    } else {
        print_text(out.fp, m, &topo);
        repair_item items[8];
        size_t n = repairs_list(&report, items);
        for (size_t i = 0; i < n; i++)
            if (items[i].n)
                fprintf(stderr, "%s: %s: repaired: %zu %s\n", tool.name, name, items[i].n,
                        items[i].key);
        if (stats.skipped_statements)
            fprintf(stderr, "%s: %s: skipped %zu unsupported statements (first: '%s')\n",
                    tool.name, name, stats.skipped_statements, stats.first_skipped);
    }
    geom_mesh_destroy(m);
    free(name);
    if (cli_output_commit(&out, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    return CLI_EXIT_OK;
}
