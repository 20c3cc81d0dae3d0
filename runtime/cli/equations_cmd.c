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

int cli_equations_main(int argc, char **argv)
{
    cli_common c;
    char msg[CLI_MSG_LEN];
    const char *format = "markdown";
    char key[32];
    int diff = 0;
    cli_common_init(&c);
    for (int i = 1; i < argc; ++i) {
        const char *value;
        int r;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return USM_OK;
        }
        if ((r = cli_option_value(argc, argv, &i, "--format", &value, msg)) != CLI_OPT_NOT_MINE) {
            if (r == CLI_OPT_ERROR) {
                cli_error("%s", msg);
                return USM_EINPUT;
            }
            if (strcmp(value, "markdown") != 0 && strcmp(value, "latex") != 0) {
                cli_error("--format: \"%s\" is not markdown or latex", value);
                return USM_EINPUT;
            }
            format = value;
            continue;
        }
        if (strcmp(argv[i], "--diff") == 0) {
            diff = 1;
            continue;
        }
        if (strncmp(argv[i], "--model", 7) == 0 || strncmp(argv[i], "--variant", 9) == 0) {
            if (cli_common_option(&c, argc, argv, &i, msg) != CLI_OPT_TAKEN) {
                cli_error("%s", msg);
                return USM_EINPUT;
            }
            continue;
        }
        cli_error("%s: unknown option (usm equations --help lists them)", argv[i]);
        return USM_EINPUT;
    }
    if (cli_common_finish(&c, msg) != USM_OK) {
        cli_error("%s", msg);
        return USM_EINPUT;
    }
    snprintf(key, sizeof key, "%s%s", format, diff ? "-diff" : "");
    for (int k = 0; k < USM_NEQUATION_DOCS; ++k) {
        const usm_equation_doc *d = &usm_equation_docs[k];
        if (strcmp(d->model, c.model->name) == 0 && strcmp(d->format, key) == 0) {
            for (const char *const *line = d->lines; *line; ++line)
                puts(*line);
            return USM_OK;
        }
    }
    cli_error("--model: no %s equations generated for %s", key, c.model->name);
    return USM_EFAILED;
}
