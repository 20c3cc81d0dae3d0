/* options.h: command-line options shared by the usm subcommands.
 *
 * Every subcommand that works on one parameter set accepts
 *   --model NAME  --variant NAME  --params FILE.json  --set NAME=VALUE (repeatable)  --json
 * A subcommand parses its own argv and offers each argument to
 * cli_common_option() before its own options; cli_common_finish() then builds
 * the parameters: defaults, then the file, then the --set values (whatever
 * their position on the command line), then usm_params_check().
 * Options take their value as "--opt VALUE" or "--opt=VALUE".
 */
#ifndef USM_CLI_OPTIONS_H
#define USM_CLI_OPTIONS_H

#include <stdio.h>

#include "diag.h"
#include "usm.h"
#include "usm_io.h"
#include "usm_operating_point.h"

typedef struct cli_common {
    const usm_model *model;      /* --model + --variant, resolved by cli_common_finish() */
    const char *base;            /* --model (default 3dof) */
    const char *variant;         /* --variant (default paper) */
    usm_params params;           /* valid after cli_common_finish() */
    int json;                    /* --json */
    const char *params_file;     /* --params, or NULL */
    /* --set values, already parsed; applied after the file. */
    double set_value[USM_NPARAMS];
    unsigned char is_set[USM_NPARAMS];
    int rank, size;              /* this MPI rank and the ranks (0, 1 without mpirun) */
    int units_ok;                /* the command shows tables and CSV: --units applies */
    usm_display display;         /* --units (all zero: SI) */
} cli_common;

/* Outcome of offering an argument to an option parser. */
enum {
    CLI_OPT_ERROR = -1, /* the argument is this parser's but is wrong: msg says why */
    CLI_OPT_NOT_MINE = 0,
    CLI_OPT_TAKEN = 1   /* consumed; *i points at the last argument used */
};

void cli_common_init(cli_common *c);

/* Offer argv[*i] to the shared options.  CLI_OPT_TAKEN, CLI_OPT_NOT_MINE, or
 * CLI_OPT_ERROR with "FIELD: reason" in msg. */
int cli_common_option(cli_common *c, int argc, char **argv, int *i, char msg[CLI_MSG_LEN]);

/* Read the params file, apply the --set values and check the result for the
 * model.  USM_OK, or USM_EINPUT with "FIELD: reason" in msg. */
int cli_common_finish(cli_common *c, char msg[CLI_MSG_LEN]);

/* Print the shared options' lines of a usage text (--variant's default:
 * paper). */
void cli_common_usage(FILE *out);

/* The same with --variant's default stated as `variant_default`, for a
 * command whose default is not paper: the help states each default once. */
/* The --units line of a command's usage (the commands with units_ok). */
void cli_units_usage(FILE *out);

/* The output of a writer in the display units: cli_shown_open returns the
 * FILE to write to (out itself when nothing is converted), cli_shown_close
 * converts what was written (usm_display_csv) into out.  0, or -1 on a
 * write error or when out of memory. */
typedef struct cli_shown {
    const usm_display *d;
    FILE *out, *mem;
    char *buf;
    size_t len;
} cli_shown;
FILE *cli_shown_open(cli_shown *s, const usm_display *d, FILE *out);
int cli_shown_close(cli_shown *s);

void cli_common_usage_variant(FILE *out, const char *variant_default);

/* If argv[*i] is option `name` ("--name VALUE" or "--name=VALUE"), store its
 * value and return CLI_OPT_TAKEN; CLI_OPT_ERROR when the value is missing. */
int cli_option_value(int argc, char **argv, int *i, const char *name, const char **value,
                     char msg[CLI_MSG_LEN]);

/* usm_parse_number() on a NUL-terminated text (see number.h): a finite,
 * normal (or zero) double, the whole text used.  On failure returns USM_EINPUT
 * with "FIELD: \"text\" reason" in msg. */
int cli_parse_double(const char *field, const char *text, double *out, char msg[CLI_MSG_LEN]);

/* usm_parse_quantity() on a NUL-terminated text: a value in SI unit `unit`
 * (a contract's spelling, e.g. usm_param_table[k].unit), typed in it or with
 * one of the units of the table ("37.5kHz", "10deg"); NULL unit: a plain
 * number.  USM_EINPUT with the units accepted in msg. */
int cli_parse_quantity(const char *field, const char *unit, const char *text, double *out,
                       char msg[CLI_MSG_LEN]);

/* cli_parse_double() of a whole number that fits an int (its range is the
 * library's to check).  USM_EINPUT with "FIELD: \"text\" reason" in msg. */
int cli_parse_int(const char *field, const char *text, int *out, char msg[CLI_MSG_LEN]);

/* The Floquet options of steady, sweep and map: --floquet-method NAME
 * (usm_floquet_method_name) and --rtol R (the integrators' relative
 * tolerance; atol = 1e-4 R).  Offer argv[*i] as to cli_common_option. */
int cli_floquet_option(usm_floquet_options *o, int argc, char **argv, int *i,
                       char msg[CLI_MSG_LEN]);

/* Print the Floquet options' lines of a usage text. */
void cli_floquet_usage(FILE *out);

/* If argv[*i] is "--plot PREFIX" (or --plot=PREFIX), store PREFIX: returns
 * CLI_OPT_TAKEN, CLI_OPT_NOT_MINE or CLI_OPT_ERROR (missing, empty). */
int cli_plot_option(int argc, char **argv, int *i, const char **prefix, char msg[CLI_MSG_LEN]);

/* The operating point's options of map, sweep, tolerance and optimize
 * (usm_operating_point.h): --from-rest (simulate the start-up from rest
 * where several roots exist) and --from-rest-periods N (in [1, 1e7]).
 * Offer argv[*i] as to cli_common_option. */
int cli_from_rest_option(usm_op_options *o, int argc, char **argv, int *i,
                         char msg[CLI_MSG_LEN]);

/* Print the lines of those options in a usage text. */
void cli_from_rest_usage(FILE *out);

/* The small parsers of a command's option function, each CLI_OPT_TAKEN,
 * CLI_OPT_NOT_MINE or CLI_OPT_ERROR with msg; CLI_TRY returns from the
 * option function unless the argument was not the parser's. */
#define CLI_TRY(expr)                      \
    do {                                   \
        const int cli_r_ = (expr);         \
        if (cli_r_ != CLI_OPT_NOT_MINE)    \
            return cli_r_;                 \
    } while (0)

/* argv[*i] is exactly `name`: *flag = 1. */
int cli_flag_option(char **argv, const int *i, const char *name, int *flag);

/* "--name N": a whole number (cli_parse_int). */
int cli_int_option(int argc, char **argv, int *i, const char *name, int *out,
                   char msg[CLI_MSG_LEN]);

/* "--name Q": a quantity in `unit` (cli_parse_quantity). */
int cli_quantity_option(int argc, char **argv, int *i, const char *name, const char *unit,
                        double *out, char msg[CLI_MSG_LEN]);

/* "--name PATH": a path, refused when empty ("--name: empty WHAT"). */
int cli_path_option(int argc, char **argv, int *i, const char *name, const char *what,
                    const char **out, char msg[CLI_MSG_LEN]);

#endif /* USM_CLI_OPTIONS_H */
