/* usm variants: the generated modelling variants, one a line, name first. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "usm.h"

int cli_variants_main(int argc, char **argv)
{
    if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        printf("usage: usm variants\n\n"
               "Lists the modelling variants: name, the base models it is generated for,\n"
               "and what it assumes.  Select one with --variant NAME in steady, sweep,\n"
               "map, simulate, periodic, sensitivity, optimize, tolerance and equations;\n"
               "the paper's (\"paper\") is the default (periodic: imperfect).\n");
        return USM_OK;
    }
    if (argc > 1) {
        fprintf(stderr, "usm: variants: unexpected argument \"%s\"\n", argv[1]);
        return USM_EINPUT;
    }
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
