/*
 * The command-line layer shared by every geom-<verb> tool.
 *
 * Conventions every tool follows (and gets from this file):
 *  - options are parsed with getopt_long; every tool accepts
 *      -h, --help       usage on stdout, exit 0
 *      -V, --version    "geom-<verb> (libgeom) X.Y.Z" on stdout, exit 0
 *      -o, --output=FILE  write the result to FILE ("-": standard output,
 *                       the default); FILE is written through a temporary
 *                       file in the same directory and renamed into place
 *                       only when the run succeeds, so a failed run never
 *                       leaves a partial (or clobbers an existing) FILE
 *      --json           machine-readable output on stdout (or FILE)
 *  - an input operand FILE or "-" (standard input, the default);
 *  - exit status CLI_EXIT_OK (0) on success, CLI_EXIT_ERROR (1) on an error
 *    (a message on stderr prefixed with the tool name, e.g.
 *    "geom-bary: in.txt:3:7: invalid number 'x'"), CLI_EXIT_USAGE (2) on a
 *    usage error (bad option or operand);
 *  - doubles are printed with 17 significant digits ("%.17g") so that they
 *    read back exactly;
 *  - text input is read line by line with no length limit; CRLF line ends and
 *    a missing final newline are accepted, a NUL byte is an error;
 *  - numbers are parsed strictly (the whole token must be a number, NaN and
 *    infinities are rejected unless a tool opts in) and an error names the
 *    1-based line and column.
 *
 * Everything is reentrant: no global state besides what getopt_long itself
 * keeps (optind, opterr, optarg, optopt) and the list of open temporary
 * output files that the SIGINT/SIGTERM/SIGHUP handler removes. Functions that can fail return a
 * geom_status and fill an optional geom_diag (NULL allowed) with the message;
 * cli_print_diag() prints it. Nothing here calls exit().
 *
 * The build defines _POSIX_C_SOURCE=200809L for every user of this header
 * (getline, mkstemp, fdopen, clock_gettime).
 *
 * A minimal tool:
 *
 *     static const cli_tool tool = { "geom-foo", "[OPTION]... [FILE]",
 *                                    "Does foo to FILE.", NULL, NULL };
 *     int main(int argc, char **argv) {
 *         cli_common common; int first;
 *         int rc = cli_parse_args(&tool, argc, argv, NULL, NULL, NULL, NULL,
 *                                 &common, &first);
 *         if (rc != CLI_CONTINUE) return rc;
 *         ... cli_input_open / cli_output_open / cli_lines_next ...
 *     }
 */
#ifndef GEOM_TOOLS_CLI_H
#define GEOM_TOOLS_CLI_H

#include <getopt.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "geom/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) || defined(__clang__)
#define CLI_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define CLI_PRINTF(fmt, args)
#endif

/* ------------------------------------------------------------ exit statuses */

#define CLI_EXIT_OK 0    /**< success */
#define CLI_EXIT_ERROR 1 /**< bad input, I/O error, out of memory, ... */
#define CLI_EXIT_USAGE 2 /**< unknown option, missing argument, extra operand */
/** Returned by cli_parse_args when the tool should go on running. */
#define CLI_CONTINUE (-1)

/* ---------------------------------------------------------- tool and options */

/** Static description of a tool, used for --help, --version and messages. */
typedef struct cli_tool {
    const char *name;         /**< "geom-<verb>": message prefix and --version */
    const char *synopsis;     /**< after the name on the Usage line: "[OPTION]... [FILE]" */
    const char *description;  /**< what the tool does (may span lines) */
    const char *options_help; /**< the tool's own option lines, "  -x, --xx   ...\n", or NULL */
    const char *details;      /**< text after the option list (input format, ...), or NULL */
    const char *examples;     /**< two example command lines, "  geom-x ...\n" each, or NULL */
} cli_tool;

/** Values of the options every tool has, filled by cli_parse_args. */
typedef struct cli_common {
    const char *output; /**< -o/--output argument; NULL when not given (stdout) */
    bool json;          /**< --json was given */
    bool quiet;         /**< --quiet was given: no progress display */
    bool up_z;          /**< --up z: the data is Z-up (GLB output is rotated to Y-up,
                             GLB input from Y-up: cli_up_z) */
} cli_common;

/** The last cli_parse_args' --up z, for the mesh readers of tools/cli_mesh.c
 *  (and scene files' mesh objects): a .glb read while it is set is rotated
 *  from glTF's Y-up frame back to Z-up, undoing a write with --up z. */
bool cli_up_z(void);

/** getopt_long values of the common options. A tool's own short options must
 *  not use h, V or o; its long-only options should use values from
 *  CLI_OPT_TOOL_BASE upwards. */
enum {
    CLI_OPT_HELP = 'h',
    CLI_OPT_VERSION = 'V',
    CLI_OPT_OUTPUT = 'o',
    CLI_OPT_JSON = 0x1000,
    CLI_OPT_QUIET = 0x1001,
    CLI_OPT_UP = 0x1002,
    CLI_OPT_MAX_TRIANGLES = 0x1100, /**< see CLI_LIMIT_LONGOPTS */
    CLI_OPT_MAX_MEMORY = 0x1101,
    CLI_OPT_TOOL_BASE = 0x2000
};

/**
 * Called by cli_parse_args for every option that is not a common one: `opt`
 * is getopt_long's return value, `arg` its argument (NULL if none). Return
 * CLI_CONTINUE to go on, or an exit status (normally CLI_EXIT_USAGE after
 * cli_usage_error()) to stop.
 */
typedef int (*cli_option_fn)(const cli_tool *tool, void *user, int opt, const char *arg);

/**
 * Parse argv with getopt_long: the common options plus the tool's own
 * (`shortopts` in getopt syntax without the leading ':' and `longopts`
 * terminated by a zero entry; either may be NULL). Operands may come before
 * or after options (GNU permutation); "--" ends the options.
 *
 * On --help prints the usage to stdout and returns CLI_EXIT_OK; on --version
 * prints the version line and returns CLI_EXIT_OK; on an unknown option or a
 * missing argument prints a message and a hint to stderr and returns
 * CLI_EXIT_USAGE; on an allocation failure returns CLI_EXIT_ERROR. Otherwise
 * fills *common, sets *first_operand to the index in argv of the first
 * operand (argc if none) and returns CLI_CONTINUE.
 * Resets getopt (optind) before parsing, so it may be called more than once.
 */
int cli_parse_args(const cli_tool *tool, int argc, char **argv, const char *shortopts,
                   const struct option *longopts, cli_option_fn on_option, void *user,
                   cli_common *common, int *first_operand);

/**
 * Check the operands cli_parse_args left in argv[first..argc): at least min
 * and at most max of them. Fewer prints "missing input operand", more
 * prints "extra operand 'X'" (X the first one past max), both as usage
 * errors (CLI_EXIT_USAGE). Returns CLI_CONTINUE when the count fits.
 */
int cli_operands(const cli_tool *tool, int argc, char **argv, int first, int min, int max);

/**
 * The value of an option that takes a finite number > 0 (geom-render's and
 * geom-scene's --tol and --pixel-error): *out and CLI_CONTINUE, else the
 * usage error "NAME: expected a number > 0, not 'ARG'" (CLI_EXIT_USAGE).
 */
int cli_positive_option(const cli_tool *tool, const char *name, const char *arg, double *out);

/** Print the full --help text of `tool` to fp. */
void cli_print_usage(const cli_tool *tool, FILE *fp);

/** Print "geom-<verb> (libgeom) X.Y.Z" (the linked library's version) to fp. */
void cli_print_version(const cli_tool *tool, FILE *fp);

/** Print "tool: <message>" and a "Try 'tool --help'" hint to stderr; returns
 *  CLI_EXIT_USAGE so callers can `return cli_usage_error(...)`. */
int cli_usage_error(const cli_tool *tool, const char *fmt, ...) CLI_PRINTF(2, 3);

/** Print "tool: <message>" to stderr; returns CLI_EXIT_ERROR. */
int cli_error(const cli_tool *tool, const char *fmt, ...) CLI_PRINTF(2, 3);

/* -------------------------------------------------------------- diagnostics */

/** Fill d (if not NULL): clear it, then set status, source (NULL: ""),
 *  line, column (0: unknown) and a printf-style message. Returns status. */
geom_status cli_diag_set(geom_diag *d, geom_status status, const char *source, size_t line,
                         size_t column, const char *fmt, ...) CLI_PRINTF(6, 7);

/** Set the source and line of a diagnostic filled by a function that only
 *  knows the column (cli_parse_numbers). NULL d is a no-op. */
void cli_diag_locate(geom_diag *d, const char *source, size_t line);

/** Print s to fp with control bytes, DEL and bytes that are not valid
 *  UTF-8 written as \xNN: text copied from input can then neither drive the
 *  terminal (clear it, set its title) nor break UTF-8. */
void cli_print_escaped(FILE *fp, const char *s);

/** Print d as "tool: source:line:col: message" (parts omitted when unknown,
 *  see geom_diag_format) to stderr. Returns CLI_EXIT_ERROR. */
int cli_print_diag(const cli_tool *tool, const geom_diag *d);

/* -------------------------------------------------------------------- input */

/** An open input: a file, or standard input. */
typedef struct cli_input {
    FILE *fp;
    const char *name; /**< the path, or "<stdin>": the source of diagnostics */
    bool is_stdin;
} cli_input;

/** Open `path` for reading in binary mode; NULL or "-" means standard input
 *  (named "<stdin>"). GEOM_ERR_IO (with the system's reason) on failure. */
geom_status cli_input_open(cli_input *in, const char *path, geom_diag *diag);

/** Close an input opened by cli_input_open (standard input is left open).
 *  Safe on a zeroed or already closed cli_input. */
void cli_input_close(cli_input *in);

/**
 * All of fp (a file or a pipe, nothing read from it yet) through
 * geom_file_map_fd: mapped when it is a regular file, else read. Release
 * with geom_file_unmap. GEOM_ERR_NOMEM or GEOM_ERR_IO (diag names `name`).
 */
geom_status cli_read_all(FILE *fp, const char *name, geom_file *out, geom_diag *diag);

/** True if s ends with suffix, ASCII letters of s compared case-blind
 *  (suffix given in lower case: ".json" matches "A.JSON"): how tools tell a
 *  file's format from its extension. */
bool cli_ends_with(const char *s, const char *suffix);

/**
 * All of the input `path` (NULL or "-": standard input) through
 * cli_input_open and cli_read_all into *file (release with
 * geom_file_unmap), and a malloc'd copy of its name (the path or
 * "<stdin>") into *name for diagnostics made after the input is closed
 * (free it). On failure there is nothing to release: GEOM_ERR_IO or
 * GEOM_ERR_NOMEM ("out of memory" when the name could not be copied) in
 * diag.
 */
geom_status cli_read_input(const char *path, geom_file *file, char **name, geom_diag *diag);

/* -------------------------------------------------------------------- lines */

/** Reads lines of any length from a FILE, counting them. Zero-initialise or
 *  use cli_lines_init; release with cli_lines_free. */
typedef struct cli_lines {
    FILE *fp;
    const char *source; /**< name for diagnostics */
    char *buf;
    size_t cap;
    size_t lineno; /**< 1-based number of the line last returned */
} cli_lines;

void cli_lines_init(cli_lines *r, FILE *fp, const char *source);
void cli_lines_free(cli_lines *r);

/**
 * Read the next line. Returns 1 with *line pointing at its text (without the
 * line end: "\n", "\r\n", or a final "\r"; NUL-terminated, valid until the
 * next call, writable) and *len its length; 0 at end of input (a last line
 * without a newline is returned first); or a negative status: GEOM_ERR_PARSE
 * for a NUL byte in the line (diag has line and column), GEOM_ERR_IO for a
 * read error, GEOM_ERR_NOMEM.
 */
int cli_lines_next(cli_lines *r, char **line, size_t *len, geom_diag *diag);

/** True if the line is empty, only whitespace, or its first non-whitespace
 *  character is '#' (a comment). */
bool cli_line_is_blank_or_comment(const char *line, size_t len);

/* ------------------------------------------------------------------ numbers */

/** cli_parse_numbers / cli_parse_double flag: accept "nan", "inf",
 *  "infinity" (any case, signed) instead of rejecting them. */
#define CLI_NUM_ALLOW_NONFINITE 1u

/**
 * Parse one number: the whole of text[0..len) must be a number that
 * geom_parse_double reads (decimal or hexadecimal floating point, "inf",
 * "infinity", "nan"; '.' as the decimal point whatever the locale; correctly
 * rounded). Rejects an empty
 * token, trailing garbage, a value that overflows to infinity, and NaN/Inf
 * unless `flags` has CLI_NUM_ALLOW_NONFINITE. Values that underflow are
 * accepted (rounded to a subnormal or zero, as strtod does).
 * `text` need not be NUL-terminated and is never read beyond len bytes.
 * Returns GEOM_OK or GEOM_ERR_PARSE (diag: column 1, message naming the
 * token), GEOM_ERR_NOMEM.
 */
geom_status cli_parse_double(const char *text, size_t len, unsigned flags, double *out,
                             geom_diag *diag);

/**
 * Parse a line of numbers separated by whitespace (space, tab, CR, VT, FF)
 * and/or single commas: "1 2 3", "1,2,3" and "1, 2 ,3" are the same; an empty
 * field ("1,,2"), a leading or a trailing comma is an error. Each number
 * follows cli_parse_double's rules.
 *
 * text: len bytes, need not be NUL-terminated, never read beyond len; a NUL
 * byte in it is an error. out: room for `max` doubles (may be NULL if max is
 * 0). On GEOM_OK *count is the number of values stored (0 for a blank line).
 * On error *count is the number parsed before the error and diag gets the
 * 1-based column (the first byte of the bad token) and a message, without
 * source or line (see cli_diag_locate). Statuses: GEOM_OK; GEOM_ERR_PARSE
 * for a malformed number, NaN/Inf, overflow, a misplaced comma or a NUL byte;
 * GEOM_ERR_LIMIT when there are more than `max` numbers (the column is the
 * first one too many); GEOM_ERR_INVALID_ARG for NULL text/count; GEOM_ERR_NOMEM.
 */
geom_status cli_parse_numbers(const char *text, size_t len, unsigned flags, double *out,
                              size_t max, size_t *count, geom_diag *diag);

/* ------------------------------------------------------------------- output */

/** Print v with 17 significant digits, as "%.17g" in the C locale
 *  (geom_format_double_digits): reads back exactly. */
void cli_print_double(FILE *fp, double v);

/** Print v as a JSON number (cli_print_double), or null when v is NaN or
 *  infinite. */
void cli_json_number(FILE *fp, double v);

/** Print r as the JSON object every approximating tool writes under the key
 *  "error": {"max", "mean", "method" ("bound", "sampled", "estimate" or
 *  "none"), "measure" (what max and mean are, e.g. "chordal distance"),
 *  "tolerance" (null when none), "evaluations", "pieces", "seconds"}. */
void cli_json_error_report(FILE *fp, const geom_error_report *r, const char *measure);

/** Print s as a JSON string literal with quotes and escapes (control
 *  characters and DEL as \u00XX; valid UTF-8 sequences are passed through,
 *  any other byte >= 0x80 becomes \ufffd, so the output is valid UTF-8). */
void cli_json_string(FILE *fp, const char *s);

/** Print `,"warnings":[w]` (w as cli_json_string) when w is neither NULL
 *  nor empty, else nothing: the warnings member of a tool's JSON summary. */
void cli_json_warning(FILE *fp, const char *w);

/** A destination for a tool's output: standard output, a device or FIFO
 *  written through, or a regular file replaced through a temporary file. */
typedef struct cli_output {
    FILE *fp;         /**< write here */
    const char *path; /**< the destination as named (NULL: standard output) */
    geom_output o;    /**< the library's cp-like output (geom_output_open) */
} cli_output;

/**
 * Open the output. NULL or "-" means standard output; anything else goes
 * through the library's geom_output_open (core.h), whose rules are cp's
 * (nothing of the user's is ever destroyed):
 *  - not there, or a regular file: a temporary file ".NAME.XXXXXXXX.geomtmp"
 *    (NAME shortened so that it fits NAME_MAX) is created in its directory,
 *    with the mode of the file it will replace (and its owner where the
 *    system allows) or 0666 less the umask; cli_output_commit renames it
 *    over the destination. A symbolic link to a regular file stays a link:
 *    the file it points to is replaced. A file we may not write is refused
 *    (permission denied), as cp refuses it;
 *  - a device (/dev/null, /dev/full), a FIFO, or a symbolic link to one: it
 *    is opened and written through, never replaced;
 *  - a directory or a dangling symbolic link: refused.
 * SIGINT, SIGTERM and SIGHUP (unless ignored) remove the temporary files of
 * open outputs before the process dies of the signal; a temporary file of a
 * SIGKILLed run keeps the ".geomtmp" name and is never taken for output.
 * GEOM_ERR_IO (with the system's reason), GEOM_ERR_NOMEM.
 */
geom_status cli_output_open(cli_output *out, const char *path, geom_diag *diag);

/**
 * Finish a successful run: flush, check for write errors (ENOSPC on
 * /dev/full is one), fsync, close, and rename the temporary file onto the
 * destination (atomically replacing any existing file). For standard output
 * or a destination written through, flushes and checks for write errors. On
 * any failure removes the temporary file (the destination is untouched) and
 * returns GEOM_ERR_IO. The output is closed afterwards either way.
 */
geom_status cli_output_commit(cli_output *out, geom_diag *diag);

/** Abandon a failed run: close and remove the temporary file (standard output
 *  is only flushed). Safe on a zeroed or already finished cli_output. */
void cli_output_abort(cli_output *out);

/* ------------------------------------------------------------ decompression */

/**
 * Decompress a zlib or gzip stream (concatenated gzip members included) of
 * in_size bytes into out (out_cap bytes): a geom_implicit_inflate_fn for the
 * volume readers. GEOM_OK with *out_size; GEOM_ERR_LIMIT when out is too
 * small; GEOM_ERR_PARSE for corrupt or truncated data, or always when the
 * tools were built without zlib (cli_have_inflate() is then false).
 */
geom_status cli_inflate(void *user, const void *in, size_t in_size, void *out, size_t out_cap,
                        size_t *out_size);

/** Whether cli_inflate works (the build found zlib). */
bool cli_have_inflate(void);

/**
 * Decompress a bzip2 stream (concatenated streams included) as cli_inflate
 * does gzip: a geom_implicit_inflate_fn for the volume readers' bunzip2
 * option (cli_bunzip2.c). Without libbz2 at build time cli_have_bunzip2()
 * is false: pass NULL then, so that the reader names the missing library.
 */
geom_status cli_bunzip2(void *user, const void *in, size_t in_size, void *out, size_t out_cap,
                        size_t *out_size);

/** Whether cli_bunzip2 works (the build found libbz2, Debian libbz2-dev). */
bool cli_have_bunzip2(void);

/** What cli_inflate and cli_bunzip2 are when their library was not found:
 *  *out_size = 0 and GEOM_ERR_PARSE, whatever the input (cli_inflate.c). */
geom_status cli_decompress_missing(void *user, const void *in, size_t in_size, void *out,
                                   size_t out_cap, size_t *out_size);

/* ------------------------------------------------------------------- limits */

/*
 * Output limits: tools whose output can explode estimate it before the work
 * and stop past a limit, with the estimate in the message. A tool opts in by
 * adding CLI_LIMIT_LONGOPTS to its long options, CLI_LIMIT_HELP to its help
 * text, calling cli_limits_option() first in its option callback, and
 * cli_limits_check() with its estimate before the heavy work.
 */

/** Default --max-triangles (50 million). */
#define CLI_MAX_TRIANGLES_DEFAULT ((size_t)50000000)
/** Default --max-memory in bytes (4 GiB). */
#define CLI_MAX_MEMORY_DEFAULT ((size_t)4 << 30)

/** The long options of cli_limits (put them in a tool's option table). */
#define CLI_LIMIT_LONGOPTS                                                     \
    {"max-triangles", required_argument, NULL, CLI_OPT_MAX_TRIANGLES},        \
    {"max-memory", required_argument, NULL, CLI_OPT_MAX_MEMORY}

/** Help lines of the limit options. */
#define CLI_LIMIT_HELP                                                               \
    "      --max-triangles=N  stop before making more than N triangles (estimated\n" \
    "                       before the work; default 50M; suffixes k, M, G)\n"    \
    "      --max-memory=SIZE  stop before the output would need more than SIZE\n"  \
    "                       bytes (default 4G; suffixes K, M, G, T: powers of 1024)\n"

/** Values of the limit options; zero-initialised fields mean the defaults. */
typedef struct cli_limits {
    size_t max_triangles; /**< 0: CLI_MAX_TRIANGLES_DEFAULT */
    size_t max_memory;    /**< bytes; 0: CLI_MAX_MEMORY_DEFAULT */
} cli_limits;

/** cli_limits_option's result for an option that is not a limit option. */
#define CLI_NOT_HANDLED (-2)

/**
 * Handle a limit option inside a tool's cli_option_fn: returns CLI_CONTINUE
 * when `opt` was --max-triangles or --max-memory and its value was stored in
 * *lim, CLI_EXIT_USAGE (after a message) for a bad value, CLI_NOT_HANDLED for
 * any other option.
 */
int cli_limits_option(const cli_tool *tool, cli_limits *lim, int opt, const char *arg);

/**
 * Parse a count or size with an optional suffix: k/K, M, G, T multiply by
 * 1000^n (binary == false) or 1024^n (binary == true). The number may have
 * a fraction or exponent ("1.5G", "5e7"); the result is rounded down and
 * must fit a size_t and be >= 1. Returns 0 on success, -1 otherwise.
 */
int cli_parse_size(const char *text, bool binary, size_t *out);

/**
 * Check an estimate against the limits: `triangles` (the estimated output
 * triangle count; a negative value skips the check) and `bytes` (the
 * estimated memory; negative skips). Past a limit prints "tool: <what> would
 * make about N triangles (estimate), more than --max-triangles M; ..." and
 * returns CLI_EXIT_ERROR; otherwise CLI_CONTINUE.
 */
int cli_limits_check(const cli_tool *tool, const cli_limits *lim, const char *what,
                     double triangles, double bytes);

/* ----------------------------------------------------------------- progress */

/**
 * A progress display on standard error: "tool: label  42%  ETA 3s", redrawn
 * in place at most ten times a second. It is shown only when standard error
 * is a terminal and --quiet was not given, and only once the work has run
 * for half a second (short runs print nothing; the environment variable
 * GEOM_PROGRESS_AFTER=S, S seconds from 0 to 3600, changes that delay: the
 * tests use 0 so that the display does not depend on the machine's speed);
 * cli_progress_done erases it.
 */
typedef struct cli_progress {
    bool enabled;
    bool shown;
    const char *prefix; /**< the tool's name */
    const char *label;
    double start, last; /**< seconds (monotonic) */
    double after;       /**< seconds before the first display */
} cli_progress;

/** Start a progress display (disabled when quiet or stderr is not a tty). */
void cli_progress_start(cli_progress *p, const cli_tool *tool, const char *label, bool quiet);

/** Report that `fraction` (0..1) of the work is done. */
void cli_progress_update(cli_progress *p, double fraction);

/** Erase the display (if it was shown). Safe to call more than once. */
void cli_progress_done(cli_progress *p);

/* -------------------------------------------------------------------- timer */

/** Monotonic wall-clock timer for the time reports tools print. */
typedef struct cli_timer {
    double start; /**< seconds, CLOCK_MONOTONIC */
} cli_timer;

/** Start (or restart) the timer. */
void cli_timer_start(cli_timer *t);

/** Seconds elapsed since cli_timer_start. */
double cli_timer_elapsed(const cli_timer *t);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_TOOLS_CLI_H */
