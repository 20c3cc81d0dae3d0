/* usm equations: the derived equations of a model, as Markdown or LaTeX.
 * The documents are emitted by derive/ together with the kernels (also in
 * generated/usm_<model>_equations.{md,tex}), so they show exactly what the
 * C code computes. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "diag.h"
#include "options.h"
#include "usm.h"
#include "usm_equations.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: usm equations [--model 3dof|4dof] [--variant NAME] [--format markdown|latex]\n"
            "                     [--diff]\n"
            "\n"
            "Print the derived equations of a model in the paper's notation, with the\n"
            "paper's equation numbers: the model in words, its parameters (unit, value,\n"
            "source), the notation, the departures from the paper; kinematics, contact\n"
            "geometry, contact and rotor laws, torques, Euler's equations in frame A,\n"
            "M(x) x' = f(x, t) row by row, the stationary residuals (3.5), beta (3.6), the\n"
            "linearisation (4.9), the Floquet problem and the validity checks.  Lines that\n"
            "differ from the paper's model are highlighted.  --diff prints only those, each\n"
            "after the paper's model's version it replaces.\n"
            "The LaTeX output is a complete document (pdflatex builds it).\n");
}

typedef struct eq_args {
    cli_common common;
    const char *format;
    int diff;
} eq_args;

static int init(void *p, char msg[CLI_MSG_LEN])
{
    eq_args *a = p;
    (void)msg;
    a->format = "markdown";
    return USM_OK;
}

static int option(void *p, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    eq_args *a = p;
    int r = cli_option_value(argc, argv, i, "--format", &a->format, msg);
    if (r == CLI_OPT_TAKEN && strcmp(a->format, "markdown") != 0 &&
        strcmp(a->format, "latex") != 0) {
        cli_msg(msg, "--format: \"%s\" is not markdown or latex", a->format);
        return CLI_OPT_ERROR;
    }
    if (r != CLI_OPT_NOT_MINE)
        return r;
    CLI_TRY(cli_flag_option(argv, i, "--diff", &a->diff));
    if (strncmp(argv[*i], "--model", 7) == 0 || strncmp(argv[*i], "--variant", 9) == 0)
        CLI_TRY(cli_common_option(&a->common, argc, argv, i, msg));
    cli_msg(msg, "%s: unknown option (usm equations --help lists them)", argv[*i]);
    return CLI_OPT_ERROR;
}

static int run(void *p)
{
    const eq_args *a = p;
    char key[32];
    snprintf(key, sizeof key, "%s%s", a->format, a->diff ? "-diff" : "");
    for (int k = 0; k < USM_NEQUATION_DOCS; ++k) {
        const usm_equation_doc *d = &usm_equation_docs[k];
        if (strcmp(d->model, a->common.model->name) == 0 && strcmp(d->format, key) == 0) {
            for (const char *const *line = d->lines; *line; ++line)
                puts(*line);
            return USM_OK;
        }
    }
    cli_error("--model: no %s equations generated for %s", key, a->common.model->name);
    return USM_EFAILED;
}

const cli_command cli_equations = {sizeof(eq_args), usage, init, option, NULL, run, 0, 0};
