/* usm variants: the generated modelling variants, one a line, name first. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "options.h"
#include "usm.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: usm variants\n\n"
                 "Lists the modelling variants: name, the base models it is generated for,\n"
                 "and what it assumes.  Select one with --variant NAME in steady, sweep,\n"
                 "map, simulate, periodic, sensitivity, optimize, tolerance and equations;\n"
                 "the paper's (\"paper\") is the default (periodic: imperfect).\n");
}

static int option(void *a, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    (void)a, (void)argc;
    cli_msg(msg, "variants: unexpected argument \"%s\"", argv[*i]);
    return CLI_OPT_ERROR;
}

static int finish(void *a, char msg[CLI_MSG_LEN])
{
    (void)a, (void)msg;
    return USM_OK;
}

static int run(void *a)
{
    (void)a;
    for (int v = 0; v < USM_NVARIANTS; ++v) {
        char models[64] = "";
        size_t used = 0;
        for (int k = 0; k < USM_NMODELS; ++k)
            if (strcmp(usm_models[k]->variant, usm_variants[v].name) == 0 && used < sizeof models) {
                int n = snprintf(models + used, sizeof models - used, "%s%s", used ? "," : "",
                                 usm_models[k]->base);
                if (n > 0)
                    used += (size_t)n;
            }
        printf("%-18s %-10s %s\n", usm_variants[v].name, models, usm_variants[v].description);
    }
    return USM_OK;
}

const cli_command cli_variants = {sizeof(cli_common), usage, NULL, option, finish, run, 0, 0};
