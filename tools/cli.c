/* The command-line layer shared by the geom-<verb> tools: see cli.h. */
/* realpath (the build defines _POSIX_C_SOURCE=200809L for the rest) */
#define _XOPEN_SOURCE 700
#include "cli.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

/* ------------------------------------------------------------ tool and options */

static const char common_shortopts[] = "hVo:";

static const struct option common_longopts[] = {
    {"help", no_argument, NULL, CLI_OPT_HELP},
    {"version", no_argument, NULL, CLI_OPT_VERSION},
    {"output", required_argument, NULL, CLI_OPT_OUTPUT},
    {"json", no_argument, NULL, CLI_OPT_JSON},
    {"quiet", no_argument, NULL, CLI_OPT_QUIET},
    {"up", required_argument, NULL, CLI_OPT_UP},
};
#define N_COMMON_LONGOPTS (sizeof common_longopts / sizeof common_longopts[0])

/* --up of this process (one cli_parse_args per tool run), for the readers. */
static bool process_up_z;

bool cli_up_z(void)
{
    return process_up_z;
}

void cli_print_usage(const cli_tool *tool, FILE *fp)
{
    fprintf(fp, "Usage: %s %s\n", tool->name, tool->synopsis ? tool->synopsis : "[OPTION]...");
    if (tool->description)
        fprintf(fp, "%s\n", tool->description);
    fputs("\nOptions:\n"
          "  -o, --output=FILE  write the output to FILE ('-', the default: standard\n"
          "                     output); FILE is written to a temporary file and\n"
          "                     renamed on success, so a failed run leaves no FILE\n"
          "      --json         machine-readable JSON output\n"
          "      --quiet        no progress display on standard error\n"
          "      --up=y|z       the data's up axis for .glb files (default y: as\n"
          "                     stored; z: .glb output is rotated into glTF's Y-up\n"
          "                     frame and .glb input back from it to Z-up)\n",
          fp);
    if (tool->options_help)
        fputs(tool->options_help, fp);
    fputs("  -h, --help         show this help and exit\n"
          "  -V, --version      show the version and exit\n",
          fp);
    if (tool->details)
        fprintf(fp, "\n%s", tool->details);
    fputs("\nExit status: 0 on success, 1 on an error (message on stderr), 2 on a usage\n"
          "error.\n",
          fp);
    if (tool->examples)
        fprintf(fp, "\nExamples:\n%s", tool->examples);
    fputs("\nFile formats, with a worked example each: docs/formats.md (installed as\n"
          "share/doc/libgeom/formats.md).\n",
          fp);
}

void cli_print_version(const cli_tool *tool, FILE *fp)
{
    fprintf(fp, "%s (libgeom) %s\n", tool->name, geom_version_string());
}

static void vreport(const cli_tool *tool, const char *fmt, va_list ap)
{
    fprintf(stderr, "%s: ", tool->name);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

static void usage_hint(const cli_tool *tool)
{
    fprintf(stderr, "Try '%s --help' for more information.\n", tool->name);
}

int cli_usage_error(const cli_tool *tool, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vreport(tool, fmt, ap);
    va_end(ap);
    usage_hint(tool);
    return CLI_EXIT_USAGE;
}

int cli_error(const cli_tool *tool, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vreport(tool, fmt, ap);
    va_end(ap);
    return CLI_EXIT_ERROR;
}

int cli_operands(const cli_tool *tool, int argc, char **argv, int first, int min, int max)
{
    if (argc - first < min)
        return cli_usage_error(tool, "missing input operand");
    if (argc - first > max)
        return cli_usage_error(tool, "extra operand '%s'", argv[first + max]);
    return CLI_CONTINUE;
}

int cli_positive_option(const cli_tool *tool, const char *name, const char *arg, double *out)
{
    char *end;
    double v = strtod(arg, &end);
    if (*end || !(v > 0) || !isfinite(v))
        return cli_usage_error(tool, "%s: expected a number > 0, not '%s'", name, arg);
    *out = v;
    return CLI_CONTINUE;
}

int cli_parse_args(const cli_tool *tool, int argc, char **argv, const char *shortopts,
                   const struct option *longopts, cli_option_fn on_option, void *user,
                   cli_common *common, int *first_operand)
{
    size_t n_long = 0;
    if (longopts)
        while (longopts[n_long].name)
            n_long++;
    size_t short_len = shortopts ? strlen(shortopts) : 0;

    char *all_short = malloc(sizeof common_shortopts + short_len);
    struct option *all_long = calloc(N_COMMON_LONGOPTS + n_long + 1, sizeof *all_long);
    if (!all_short || !all_long) {
        free(all_short);
        free(all_long);
        return cli_error(tool, "out of memory");
    }
    memcpy(all_short, common_shortopts, sizeof common_shortopts - 1);
    if (short_len)
        memcpy(all_short + sizeof common_shortopts - 1, shortopts, short_len);
    all_short[sizeof common_shortopts - 1 + short_len] = '\0';
    memcpy(all_long, common_longopts, sizeof common_longopts);
    if (n_long)
        memcpy(all_long + N_COMMON_LONGOPTS, longopts, n_long * sizeof *longopts);

    common->output = NULL;
    common->json = false;
    common->quiet = false;
    common->up_z = false;
    process_up_z = false;

    /* getopt reports unknown options itself, prefixed with argv[0]; show the
     * tool's name there rather than however it was invoked. */
    char *argv0 = argc > 0 ? argv[0] : NULL;
    if (argc > 0)
        argv[0] = (char *)tool->name;
    optind = 0; /* full re-initialisation (glibc, musl, BSD) */
    opterr = 1;

    int rc = CLI_CONTINUE;
    int opt;
    while (rc == CLI_CONTINUE && (opt = getopt_long(argc, argv, all_short, all_long, NULL)) != -1) {
        switch (opt) {
        case CLI_OPT_HELP:
            cli_print_usage(tool, stdout);
            rc = fflush(stdout) == 0 ? CLI_EXIT_OK : CLI_EXIT_ERROR;
            break;
        case CLI_OPT_VERSION:
            cli_print_version(tool, stdout);
            rc = fflush(stdout) == 0 ? CLI_EXIT_OK : CLI_EXIT_ERROR;
            break;
        case CLI_OPT_OUTPUT:
            if (optarg[0] == '\0')
                rc = cli_usage_error(tool, "empty output file name");
            else
                common->output = optarg;
            break;
        case CLI_OPT_JSON:
            common->json = true;
            break;
        case CLI_OPT_QUIET:
            common->quiet = true;
            break;
        case CLI_OPT_UP:
            if (strcmp(optarg, "y") == 0 || strcmp(optarg, "Y") == 0)
                common->up_z = false;
            else if (strcmp(optarg, "z") == 0 || strcmp(optarg, "Z") == 0)
                common->up_z = true;
            else
                rc = cli_usage_error(tool, "--up takes y or z, not '%s'", optarg);
            process_up_z = common->up_z;
            break;
        case '?':
            usage_hint(tool);
            rc = CLI_EXIT_USAGE;
            break;
        default:
            if (on_option)
                rc = on_option(tool, user, opt, optarg);
            else
                rc = cli_usage_error(tool, "unhandled option");
            break;
        }
    }
    if (argc > 0)
        argv[0] = argv0;
    free(all_short);
    free(all_long);
    *first_operand = optind < argc ? optind : argc;
    return rc;
}

/* -------------------------------------------------------------- diagnostics */

geom_status cli_diag_set(geom_diag *d, geom_status status, const char *source, size_t line,
                         size_t column, const char *fmt, ...)
{
    if (!d)
        return status;
    memset(d, 0, sizeof *d);
    d->status = status;
    if (source)
        snprintf(d->source, sizeof d->source, "%s", source);
    d->line = line;
    d->column = column;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, sizeof d->message, fmt, ap);
    va_end(ap);
    return status;
}

void cli_diag_locate(geom_diag *d, const char *source, size_t line)
{
    if (!d)
        return;
    snprintf(d->source, sizeof d->source, "%s", source ? source : "");
    d->line = line;
}

/* Length of the valid UTF-8 sequence at p (1..4), 0 if not valid. */
static size_t cli_utf8_len(const unsigned char *p)
{
    unsigned char c = p[0];
    size_t len;
    uint32_t cp;
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        len = 2, cp = c & 0x1F;
    else if (c >= 0xE0 && c <= 0xEF)
        len = 3, cp = c & 0x0F;
    else if (c >= 0xF0 && c <= 0xF4)
        len = 4, cp = c & 0x07;
    else
        return 0;
    for (size_t i = 1; i < len; i++) { /* stops at the NUL: 0x00 is no continuation */
        if ((p[i] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (p[i] & 0x3F);
    }
    if ((len == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
        (len == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
        return 0;
    return len;
}

void cli_print_escaped(FILE *fp, const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    while (*p) {
        size_t u = cli_utf8_len(p);
        if (u == 0 || (u == 1 && (*p < 0x20 || *p == 0x7F))) {
            fprintf(fp, "\\x%02x", *p);
            p++;
        } else {
            fwrite(p, 1, u, fp);
            p += u;
        }
    }
}

/* The tool's own words for a library hint (geom_diag.hint): the option that
 * does it, when this tool has that option, or else geom-convert's. */
static const struct {
    geom_diag_hint hint;
    const char *option, *text, *elsewhere;
} cli_hints[] = {
    {GEOM_DIAG_HINT_SKIP_INVALID_FACES, "--skip-invalid", "(--skip-invalid skips such faces)",
     "(geom-convert --skip-invalid can drop such faces first)"},
};

static void cli_print_hint(const cli_tool *tool, geom_diag_hint h)
{
    for (size_t i = 0; i < sizeof cli_hints / sizeof cli_hints[0]; i++) {
        if (cli_hints[i].hint != h)
            continue;
        const char *opts = tool->options_help ? tool->options_help : "";
        fprintf(stderr, " %s",
                strstr(opts, cli_hints[i].option) ? cli_hints[i].text : cli_hints[i].elsewhere);
    }
}

int cli_print_diag(const cli_tool *tool, const geom_diag *d)
{
    if (!d || (d->status == GEOM_OK && !d->message[0])) {
        /* a failure the library did not describe: never print "ok" */
        fprintf(stderr, "%s: failed (no diagnostic)\n", tool->name);
        return CLI_EXIT_ERROR;
    }
    char small[512];
    size_t need = geom_diag_format(d, small, sizeof small);
    char *big = need < sizeof small ? NULL : malloc(need + 1);
    if (big)
        geom_diag_format(d, big, need + 1);
    /* Text from the input may be part of the message: escape what could
     * drive the terminal. */
    fprintf(stderr, "%s: ", tool->name);
    cli_print_escaped(stderr, big ? big : small); /* small is truncated if big failed */
    cli_print_hint(tool, d->hint);
    fputc('\n', stderr);
    free(big);
    return CLI_EXIT_ERROR;
}

/* -------------------------------------------------------------------- input */

geom_status cli_input_open(cli_input *in, const char *path, geom_diag *diag)
{
    memset(in, 0, sizeof *in);
    if (!path || strcmp(path, "-") == 0) {
        in->fp = stdin;
        in->name = "<stdin>";
        in->is_stdin = true;
        return GEOM_OK;
    }
    in->fp = fopen(path, "rb");
    if (!in->fp)
        return cli_diag_set(diag, GEOM_ERR_IO, path, 0, 0, "%s", strerror(errno));
    struct stat st; /* fopen opens a directory for reading: say what it is */
    if (fstat(fileno(in->fp), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(in->fp);
        in->fp = NULL;
        return cli_diag_set(diag, GEOM_ERR_IO, path, 0, 0,
                            "is a directory, not a file (expected an input file)");
    }
    in->name = path;
    return GEOM_OK;
}

void cli_input_close(cli_input *in)
{
    if (in->fp && !in->is_stdin)
        fclose(in->fp);
    in->fp = NULL;
}

geom_status cli_read_all(FILE *fp, const char *name, geom_file *out, geom_diag *diag)
{
    return geom_file_map_fd(fileno(fp), name, NULL, out, diag);
}

geom_status cli_read_input(const char *path, geom_file *file, char **name, geom_diag *diag)
{
    cli_input in;
    *name = NULL;
    geom_status st = cli_input_open(&in, path, diag);
    if (st != GEOM_OK)
        return st;
    st = cli_read_all(in.fp, in.name, file, diag);
    *name = strdup(in.name);
    cli_input_close(&in);
    if (st != GEOM_OK || !*name) {
        geom_file_unmap(file);
        free(*name);
        *name = NULL;
        if (st == GEOM_OK)
            st = cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
        return st;
    }
    return GEOM_OK;
}

bool cli_ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    if (a < b)
        return false;
    for (size_t i = 0; i < b; ++i) {
        char c = s[a - b + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != suffix[i])
            return false;
    }
    return true;
}

/* -------------------------------------------------------------------- lines */

void cli_lines_init(cli_lines *r, FILE *fp, const char *source)
{
    memset(r, 0, sizeof *r);
    r->fp = fp;
    r->source = source;
}

void cli_lines_free(cli_lines *r)
{
    free(r->buf);
    r->buf = NULL;
    r->cap = 0;
}

int cli_lines_next(cli_lines *r, char **line, size_t *len, geom_diag *diag)
{
    errno = 0;
    ssize_t n = getline(&r->buf, &r->cap, r->fp);
    if (n < 0) {
        if (ferror(r->fp))
            return cli_diag_set(diag, GEOM_ERR_IO, r->source, r->lineno + 1, 0, "read error: %s",
                                strerror(errno ? errno : EIO));
        if (errno == ENOMEM || errno == EOVERFLOW)
            return cli_diag_set(diag, GEOM_ERR_NOMEM, r->source, r->lineno + 1, 0,
                                "line too long: %s", strerror(errno));
        return 0;
    }
    r->lineno++;
    size_t m = (size_t)n;
    const char *nul = memchr(r->buf, '\0', m);
    if (nul)
        return cli_diag_set(diag, GEOM_ERR_PARSE, r->source, r->lineno,
                            (size_t)(nul - r->buf) + 1, "NUL byte in input");
    if (m > 0 && r->buf[m - 1] == '\n')
        m--;
    if (m > 0 && r->buf[m - 1] == '\r')
        m--;
    r->buf[m] = '\0';
    *line = r->buf;
    *len = m;
    return 1;
}

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

bool cli_line_is_blank_or_comment(const char *line, size_t len)
{
    size_t i = 0;
    while (i < len && is_space(line[i]))
        i++;
    return i == len || line[i] == '#';
}

/* ------------------------------------------------------------------ numbers */

/* Quote at most 40 bytes of a token for a message, escaping non-printables. */
static void quote_token(const char *s, size_t len, char *out, size_t size)
{
    static const char hex[] = "0123456789abcdef";
    size_t o = 0, i = 0;
    const size_t show = 40;
    for (; i < len && i < show && o + 5 < size; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out[o++] = (char)c;
        } else {
            out[o++] = '\\';
            out[o++] = 'x';
            out[o++] = hex[c >> 4];
            out[o++] = hex[c & 15];
        }
    }
    if (i < len && o + 4 < size) {
        memcpy(out + o, "...", 3);
        o += 3;
    }
    out[o] = '\0';
}

geom_status cli_parse_double(const char *text, size_t len, unsigned flags, double *out,
                             geom_diag *diag)
{
    char q[192];
    *out = 0.0;
    if (len == 0)
        return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, 1, "empty number");
    const char *stop;
    double v;
    geom_status st = geom_parse_double(text, text + len, &v, &stop);
    if (stop != text + len || st == GEOM_ERR_PARSE) {
        quote_token(text, len, q, sizeof q);
        return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, 1, "invalid number '%s'", q);
    }
    if (st == GEOM_ERR_DOMAIN) {
        quote_token(text, len, q, sizeof q);
        return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, 1, "number out of range '%s'", q);
    }
    if (!isfinite(v) && !(flags & CLI_NUM_ALLOW_NONFINITE)) {
        quote_token(text, len, q, sizeof q);
        return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, 1, "%s not allowed '%s'",
                            isnan(v) ? "NaN" : "infinity", q);
    }
    *out = v;
    return GEOM_OK;
}

static size_t skip_space(const char *s, size_t i, size_t len)
{
    while (i < len && is_space(s[i]))
        i++;
    return i;
}

geom_status cli_parse_numbers(const char *text, size_t len, unsigned flags, double *out,
                              size_t max, size_t *count, geom_diag *diag)
{
    if (count)
        *count = 0;
    if (!text || !count || (max > 0 && !out))
        return cli_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                            "cli_parse_numbers: NULL argument");
    const char *nul = memchr(text, '\0', len);
    if (nul)
        return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, (size_t)(nul - text) + 1,
                            "NUL byte in input");

    size_t n = 0;
    size_t i = skip_space(text, 0, len);
    while (i < len) {
        if (text[i] == ',')
            return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, i + 1,
                                n == 0 ? "unexpected comma before the first number"
                                       : "empty field between commas");
        size_t start = i;
        while (i < len && !is_space(text[i]) && text[i] != ',')
            i++;
        if (n == max)
            return cli_diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, start + 1,
                                "too many numbers (expected at most %zu)", max);
        double v;
        geom_status st = cli_parse_double(text + start, i - start, flags, &v, diag);
        if (st != GEOM_OK) {
            if (diag)
                diag->column = start + 1;
            return st;
        }
        out[n++] = v;
        *count = n;
        i = skip_space(text, i, len);
        if (i < len && text[i] == ',') {
            size_t comma = i;
            i = skip_space(text, i + 1, len);
            if (i == len)
                return cli_diag_set(diag, GEOM_ERR_PARSE, NULL, 0, comma + 1,
                                    "trailing comma after the last number");
        }
    }
    return GEOM_OK;
}

/* ------------------------------------------------------------------- output */

void cli_print_double(FILE *fp, double v)
{
    char buf[GEOM_DOUBLE_CHARS];
    fwrite(buf, 1, geom_format_double_digits(v, 17, buf), fp);
}

void cli_json_number(FILE *fp, double v)
{
    if (isfinite(v))
        cli_print_double(fp, v);
    else
        fputs("null", fp);
}

void cli_json_error_report(FILE *fp, const geom_error_report *r, const char *measure)
{
    static const char *const methods[4] = {"none", "bound", "sampled", "estimate"};
    int m = r->method >= 0 && r->method < 4 ? r->method : 0;
    fputs("{\"max\":", fp);
    cli_json_number(fp, m ? r->max_error : NAN);
    fputs(",\"mean\":", fp);
    cli_json_number(fp, m ? r->mean_error : NAN);
    fprintf(fp, ",\"method\":\"%s\",\"measure\":", methods[m]);
    cli_json_string(fp, measure ? measure : "");
    fputs(",\"tolerance\":", fp);
    cli_json_number(fp, r->tolerance > 0 ? r->tolerance : NAN);
    fprintf(fp, ",\"evaluations\":%zu,\"pieces\":%zu,\"seconds\":", r->evaluations, r->pieces);
    cli_json_number(fp, r->seconds);
    fputc('}', fp);
}

void cli_json_warning(FILE *fp, const char *w)
{
    if (!w || !w[0])
        return;
    fputs(",\"warnings\":[", fp);
    cli_json_string(fp, w);
    fputc(']', fp);
}

void cli_json_string(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        switch (c) {
        case '"': fputs("\\\"", fp); break;
        case '\\': fputs("\\\\", fp); break;
        case '\b': fputs("\\b", fp); break;
        case '\f': fputs("\\f", fp); break;
        case '\n': fputs("\\n", fp); break;
        case '\r': fputs("\\r", fp); break;
        case '\t': fputs("\\t", fp); break;
        default:
            if (c < 0x20 || c == 0x7F) {
                fprintf(fp, "\\u%04x", c);
            } else if (c >= 0x80) { /* valid UTF-8 passes, anything else is U+FFFD */
                size_t u = cli_utf8_len((const unsigned char *)s);
                if (u == 0) {
                    fputs("\\ufffd", fp);
                } else {
                    fwrite(s, 1, u, fp);
                    s += u - 1;
                }
            } else {
                fputc(c, fp);
            }
        }
    }
    fputc('"', fp);
}

/* Temporary files of open outputs, removed by the signal handler. The only
 * mutable global state of this file besides getopt's: a handler cannot be
 * given a context. Slots are set and cleared by the main thread only. */
#define CLI_MAX_TEMPS 8
static char *volatile cli_temps[CLI_MAX_TEMPS];
static volatile sig_atomic_t cli_handlers_installed;

static void cli_on_signal(int sig)
{
    for (int i = 0; i < CLI_MAX_TEMPS; i++) {
        char *p = cli_temps[i];
        if (p)
            unlink(p); /* async-signal-safe */
    }
    /* SA_RESETHAND restored the default action: die of the same signal. */
    raise(sig);
}

static void cli_install_handlers(void)
{
    if (cli_handlers_installed)
        return;
    cli_handlers_installed = 1;
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction old, sa;
        if (sigaction(sigs[i], NULL, &old) != 0 || old.sa_handler == SIG_IGN)
            continue; /* nohup and friends: keep ignoring it */
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = cli_on_signal;
        sigemptyset(&sa.sa_mask);
        for (size_t j = 0; j < sizeof sigs / sizeof sigs[0]; j++)
            sigaddset(&sa.sa_mask, sigs[j]);
        sa.sa_flags = SA_RESETHAND;
        sigaction(sigs[i], &sa, NULL);
    }
}

static void cli_register_temp(char *tmp, bool on)
{
    for (int i = 0; i < CLI_MAX_TEMPS; i++) {
        if (on && !cli_temps[i]) {
            cli_temps[i] = tmp;
            return;
        }
        if (!on && cli_temps[i] == tmp) {
            cli_temps[i] = NULL;
            return;
        }
    }
}

static void output_release(cli_output *out)
{
    if (out->o.temporary)
        cli_register_temp(out->o.temporary, false);
    memset(out, 0, sizeof *out);
    out->o.fd = -1;
}

/* The destination rules (cp's) are the library's: geom_output_open. The tool
 * layer adds standard output, a FILE stream over a duplicate of the output's
 * descriptor, and the signal handler that removes the temporary file. */
geom_status cli_output_open(cli_output *out, const char *path, geom_diag *diag)
{
    memset(out, 0, sizeof *out);
    out->o.fd = -1;
    if (!path || strcmp(path, "-") == 0) {
        out->fp = stdout;
        return GEOM_OK;
    }
    cli_install_handlers();
    geom_status st = geom_output_open(path, NULL, &out->o, diag);
    if (st != GEOM_OK)
        return st;
    if (out->o.temporary)
        cli_register_temp(out->o.temporary, true);
    out->path = path;
    int fd = dup(out->o.fd);
    out->fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!out->fp) {
        int e = errno;
        if (fd >= 0)
            close(fd);
        cli_output_abort(out);
        return cli_diag_set(diag, e == ENOMEM ? GEOM_ERR_NOMEM : GEOM_ERR_IO, path, 0, 0,
                            "cannot open for writing: %s", strerror(e));
    }
    return GEOM_OK;
}

geom_status cli_output_commit(cli_output *out, geom_diag *diag)
{
    if (!out->fp)
        return cli_diag_set(diag, GEOM_ERR_IO, NULL, 0, 0, "output is not open");
    int e = 0;
    errno = 0;
    if (fflush(out->fp) != 0 || ferror(out->fp))
        e = errno ? errno : EIO;
    if (!out->path) { /* standard output */
        out->fp = NULL;
        if (e)
            return cli_diag_set(diag, GEOM_ERR_IO, "<stdout>", 0, 0, "write error: %s",
                                strerror(e));
        return GEOM_OK;
    }
    if (fclose(out->fp) != 0 && !e && errno != EINTR)
        e = errno ? errno : EIO;
    out->fp = NULL;
    if (e) {
        const char *path = out->path;
        cli_output_abort(out);
        return cli_diag_set(diag, GEOM_ERR_IO, path, 0, 0, "write error: %s", strerror(e));
    }
    char *tmp = out->o.temporary;
    geom_status st = geom_output_commit(&out->o, diag);
    if (tmp)
        cli_register_temp(tmp, false);
    output_release(out);
    return st;
}

void cli_output_abort(cli_output *out)
{
    if (out->fp && !out->path) {
        fflush(out->fp); /* keep what was already streamed to stdout */
        out->fp = NULL;
        return;
    }
    if (out->fp)
        fclose(out->fp);
    out->fp = NULL;
    if (out->o.temporary)
        cli_register_temp(out->o.temporary, false);
    geom_output_abort(&out->o);
    output_release(out);
}

/* -------------------------------------------------------------------- timer */

static double monotonic_seconds(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_timer_start(cli_timer *t)
{
    t->start = monotonic_seconds();
}

double cli_timer_elapsed(const cli_timer *t)
{
    return monotonic_seconds() - t->start;
}

/* ------------------------------------------------------------------- limits */

int cli_parse_size(const char *text, bool binary, size_t *out)
{
    if (!text || !*text)
        return -1;
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || errno == ERANGE || !isfinite(v) || v < 0.0)
        return -1;
    double unit = binary ? 1024.0 : 1000.0, mul = 1.0;
    switch (*end) {
    case 'k': case 'K': mul = unit; end++; break;
    case 'M': mul = unit * unit; end++; break;
    case 'G': mul = unit * unit * unit; end++; break;
    case 'T': mul = unit * unit * unit * unit; end++; break;
    default: break;
    }
    if (binary && (*end == 'B' || *end == 'b'))
        end++;
    if (*end != '\0')
        return -1;
    v = floor(v * mul);
    if (!(v >= 1.0) || v >= 18446744073709551615.0 || v > (double)SIZE_MAX)
        return -1;
    *out = (size_t)v;
    return 0;
}

int cli_limits_option(const cli_tool *tool, cli_limits *lim, int opt, const char *arg)
{
    if (opt == CLI_OPT_MAX_TRIANGLES) {
        if (cli_parse_size(arg, false, &lim->max_triangles) != 0)
            return cli_usage_error(tool, "--max-triangles: '%s' is not a count >= 1 (e.g. 2000000, 50M)", arg);
        return CLI_CONTINUE;
    }
    if (opt == CLI_OPT_MAX_MEMORY) {
        if (cli_parse_size(arg, true, &lim->max_memory) != 0)
            return cli_usage_error(tool, "--max-memory: '%s' is not a size >= 1 (e.g. 512M, 8G)", arg);
        return CLI_CONTINUE;
    }
    return CLI_NOT_HANDLED;
}

int cli_limits_check(const cli_tool *tool, const cli_limits *lim, const char *what,
                     double triangles, double bytes)
{
    size_t mt = lim && lim->max_triangles ? lim->max_triangles : CLI_MAX_TRIANGLES_DEFAULT;
    size_t mm = lim && lim->max_memory ? lim->max_memory : CLI_MAX_MEMORY_DEFAULT;
    if (!what)
        what = "the output";
    if (triangles >= 0.0 && triangles > (double)mt)
        return cli_error(tool,
                         "%s would have about %.0f triangles (estimate), more than "
                         "--max-triangles %zu; raise --max-triangles or coarsen the request",
                         what, triangles, mt);
    if (bytes >= 0.0 && bytes > (double)mm)
        return cli_error(tool,
                         "%s would need about %.0f MiB (estimate), more than --max-memory "
                         "%.0f MiB; raise --max-memory or coarsen the request",
                         what, bytes / 1048576.0, (double)mm / 1048576.0);
    return CLI_CONTINUE;
}

/* ----------------------------------------------------------------- progress */

static double mono_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_start(cli_progress *p, const cli_tool *tool, const char *label, bool quiet)
{
    memset(p, 0, sizeof *p);
    p->enabled = !quiet && isatty(STDERR_FILENO);
    p->prefix = tool ? tool->name : "";
    p->label = label ? label : "";
    p->start = mono_now();
    p->last = 0.0;
    p->after = 0.5;
    const char *env = getenv("GEOM_PROGRESS_AFTER");
    if (env && *env) {
        char *end;
        double v = strtod(env, &end);
        if (*end == '\0' && v >= 0.0 && v <= 3600.0)
            p->after = v;
    }
}

void cli_progress_update(cli_progress *p, double fraction)
{
    if (!p || !p->enabled)
        return;
    double now = mono_now(), el = now - p->start;
    if (el < p->after || now - p->last < 0.1)
        return;
    p->last = now;
    if (!(fraction > 0.0))
        fraction = 0.0;
    if (fraction > 1.0)
        fraction = 1.0;
    char eta[32] = "";
    if (fraction > 0.01) {
        double rem = el * (1.0 - fraction) / fraction;
        if (rem < 60.0)
            snprintf(eta, sizeof eta, "  ETA %.0fs", rem);
        else if (rem < 3600.0)
            snprintf(eta, sizeof eta, "  ETA %dm%02ds", (int)(rem / 60.0), (int)fmod(rem, 60.0));
        else
            snprintf(eta, sizeof eta, "  ETA %.1fh", rem / 3600.0);
    }
    fprintf(stderr, "\r%s: %s %3d%%%s\033[K", p->prefix, p->label, (int)(fraction * 100.0), eta);
    fflush(stderr);
    p->shown = true;
}

void cli_progress_done(cli_progress *p)
{
    if (!p || !p->shown)
        return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    p->shown = false;
}
