/* Command-line options shared by the usm subcommands. */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include "options.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "usm_io.h"

void cli_common_init(cli_common *c)
{
    memset(c, 0, sizeof *c);
    c->base = "3dof";
    c->variant = "paper";
    c->size = 1;
    c->model = usm_model_find("3dof");
    usm_params_default(&c->params);
}

int cli_option_value(int argc, char **argv, int *i, const char *name, const char **value,
                     char msg[CLI_MSG_LEN])
{
    const char *arg = argv[*i];
    size_t len = strlen(name);
    if (strncmp(arg, name, len) != 0)
        return CLI_OPT_NOT_MINE;
    if (arg[len] == '=') {
        *value = arg + len + 1;
        return CLI_OPT_TAKEN;
    }
    if (arg[len] != '\0')
        return CLI_OPT_NOT_MINE;
    if (*i + 1 >= argc) {
        cli_msg(msg, "%s: missing argument", name);
        return CLI_OPT_ERROR;
    }
    *value = argv[++*i];
    return CLI_OPT_TAKEN;
}

int cli_parse_double(const char *field, const char *text, double *out, char msg[CLI_MSG_LEN])
{
    return usm_parse_number(field, text, strlen(text), out, msg);
}

int cli_parse_quantity(const char *field, const char *unit, const char *text, double *out,
                       char msg[CLI_MSG_LEN])
{
    return usm_parse_quantity(field, unit, text, strlen(text), out, msg);
}

/* "--set NAME=VALUE": checked at once so that errors name the --set option. */
static int take_set(cli_common *c, const char *arg, char msg[CLI_MSG_LEN])
{
    const char *eq = strchr(arg, '=');
    char name[64];
    char field[96];
    const usm_param_info *info;
    double v;
    if (!eq) {
        cli_msg(msg, "--set %s: expected NAME=VALUE", arg);
        return CLI_OPT_ERROR;
    }
    if ((size_t)(eq - arg) >= sizeof name) {
        cli_msg(msg, "--set %.*s: unknown parameter", (int)(eq - arg), arg);
        return CLI_OPT_ERROR;
    }
    memcpy(name, arg, (size_t)(eq - arg));
    name[eq - arg] = '\0';
    if (name[0] == '\0') {
        cli_msg(msg, "--set %s: expected NAME=VALUE, the name is empty", arg);
        return CLI_OPT_ERROR;
    }
    info = usm_params_find(name);
    if (!info) {
        cli_msg(msg, "--set %s: unknown parameter (see usm steady --help)", name);
        return CLI_OPT_ERROR;
    }
    snprintf(field, sizeof field, "--set %s", name);
    if (cli_parse_quantity(field, info->unit, eq + 1, &v, msg) != USM_OK)
        return CLI_OPT_ERROR;
    c->set_value[info - usm_param_table] = v;
    c->is_set[info - usm_param_table] = 1;
    return CLI_OPT_TAKEN;
}

/* The base models ("3dof", "4dof"), each named once. */
static void list_models(char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < USM_NMODELS && used < len; ++k) {
        if (strcmp(usm_models[k]->variant, "paper") != 0)
            continue;
        int n = snprintf(buf + used, len - used, "%s%s", used ? ", " : "", usm_models[k]->base);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

/* The variants generated for base model `base`. */
static void list_variants(const char *base, char *buf, size_t len)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < USM_NMODELS && used < len; ++k) {
        if (strcmp(usm_models[k]->base, base) != 0)
            continue;
        int n = snprintf(buf + used, len - used, "%s%s", used ? ", " : "", usm_models[k]->variant);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

int cli_common_option(cli_common *c, int argc, char **argv, int *i, char msg[CLI_MSG_LEN])
{
    const char *value;
    int r;
    if (strcmp(argv[*i], "--json") == 0) {
        c->json = 1;
        return CLI_OPT_TAKEN;
    }
    if (c->units_ok && (r = cli_option_value(argc, argv, i, "--units", &value, msg)) != CLI_OPT_NOT_MINE) {
        if (r == CLI_OPT_TAKEN && usm_display_parse("--units", value, &c->display, msg) != USM_OK)
            return CLI_OPT_ERROR;
        return r;
    }
    if ((r = cli_option_value(argc, argv, i, "--model", &value, msg)) != CLI_OPT_NOT_MINE) {
        const usm_model *m = r == CLI_OPT_TAKEN ? usm_model_find(value) : NULL;
        if (r == CLI_OPT_TAKEN && !m) {
            char known[128];
            list_models(known, sizeof known);
            cli_msg(msg, "--model: unknown model \"%s\" (known: %s)", value, known);
            return CLI_OPT_ERROR;
        }
        if (m) {
            /* a full generated name such as 4dof_friction_tanh also selects its variant */
            c->base = m->base;
            if (strcmp(m->variant, "paper") != 0)
                c->variant = m->variant;
        }
        return r;
    }
    if ((r = cli_option_value(argc, argv, i, "--variant", &value, msg)) != CLI_OPT_NOT_MINE) {
        if (r == CLI_OPT_TAKEN && !usm_variant_find(value)) {
            cli_msg(msg, "--variant: unknown variant \"%s\" (usm variants lists them)", value);
            return CLI_OPT_ERROR;
        }
        if (r == CLI_OPT_TAKEN)
            c->variant = value;
        return r;
    }
    if ((r = cli_option_value(argc, argv, i, "--params", &value, msg)) != CLI_OPT_NOT_MINE) {
        if (r == CLI_OPT_TAKEN && value[0] == '\0') {
            cli_msg(msg, "--params: empty file name");
            return CLI_OPT_ERROR;
        }
        if (r == CLI_OPT_TAKEN)
            c->params_file = value;
        return r;
    }
    if ((r = cli_option_value(argc, argv, i, "--set", &value, msg)) != CLI_OPT_NOT_MINE)
        return r == CLI_OPT_TAKEN ? take_set(c, value, msg) : r;
    return CLI_OPT_NOT_MINE;
}

int cli_common_finish(cli_common *c, char msg[CLI_MSG_LEN])
{
    char lib[USM_MSG_LEN];
    if (!(c->model = usm_model_variant(c->base, c->variant))) {
        char known[128];
        list_variants(c->base, known, sizeof known);
        cli_msg(msg, "--variant: variant \"%s\" is not generated for model %s (it has: %s)",
                c->variant, c->base, known);
        return USM_EINPUT;
    }
    usm_params_default(&c->params);
    if (c->params_file && usm_params_read_file(c->params_file, &c->params, msg) != USM_OK)
        return USM_EINPUT;
    for (int k = 0; k < USM_NPARAMS; ++k)
        if (c->is_set[k])
            *usm_params_field(&c->params, &usm_param_table[k]) = c->set_value[k];
    if (usm_params_check(&c->params, c->model, lib) != USM_OK) {
        cli_msg(msg, "%s", lib);
        return USM_EINPUT;
    }
    return USM_OK;
}

void cli_common_usage(FILE *out) { cli_common_usage_variant(out, "paper"); }

void cli_units_usage(FILE *out)
{
    fprintf(out, "  --units LIST        show values in these units in tables, CSV, events and\n"
                 "                      plots: rpm,deg,kHz,mNm,... or si (default); JSON stays SI\n");
}

FILE *cli_shown_open(cli_shown *s, const usm_display *d, FILE *out)
{
    memset(s, 0, sizeof *s);
    s->d = d;
    s->out = out;
    if (!d || d->n == 0)
        return out;
    s->mem = open_memstream(&s->buf, &s->len);
    return s->mem;
}

int cli_shown_close(cli_shown *s)
{
    if (!s->mem)
        return ferror(s->out) ? -1 : 0;
    int rc = fclose(s->mem) != 0 || !s->buf ? -1 : usm_display_csv(s->d, s->buf, s->len, s->out);
    free(s->buf);
    s->mem = NULL;
    s->buf = NULL;
    return rc;
}

void cli_common_usage_variant(FILE *out, const char *variant_default)
{
    char known[128];
    list_models(known, sizeof known);
    fprintf(out,
            "  --model NAME        model to use: %s (default 3dof)\n"
            "  --variant NAME      modelling assumptions (default %s; see usm variants)\n"
            "  --params FILE.json  parameter values, a JSON object {\"NAME\": number, ...}\n"
            "  --set NAME=VALUE    set one parameter (repeatable; applied after --params);\n"
            "                      VALUE in SI or with a unit: f=37.5kHz, T=0.5mNm,\n"
            "                      phase_error=10deg (see usm steady --help)\n"
            "  --json              print one JSON object instead of a table\n",
            known, variant_default);
}

int cli_parse_int(const char *field, const char *text, int *out, char msg[CLI_MSG_LEN])
{
    double v;
    if (cli_parse_double(field, text, &v, msg) != USM_OK)
        return USM_EINPUT;
    if (v != floor(v) || v < INT_MIN || v > INT_MAX) {
        cli_msg(msg, "%s: \"%s\" must be an integer", field, text);
        return USM_EINPUT;
    }
    *out = (int)v;
    return USM_OK;
}

int cli_floquet_option(usm_floquet_options *o, int argc, char **argv, int *i,
                       char msg[CLI_MSG_LEN])
{
    const char *value;
    char lib[USM_MSG_LEN];
    int r;
    if ((r = cli_option_value(argc, argv, i, "--floquet-method", &value, msg)) != CLI_OPT_NOT_MINE) {
        if (r == CLI_OPT_TAKEN && usm_floquet_method_from_name(value, &o->method, lib) != USM_OK) {
            cli_msg(msg, "--floquet-method: %s", lib);
            return CLI_OPT_ERROR;
        }
        return r;
    }
    if ((r = cli_option_value(argc, argv, i, "--rtol", &value, msg)) != CLI_OPT_NOT_MINE) {
        double v;
        if (r != CLI_OPT_TAKEN)
            return r;
        if (cli_parse_double("--rtol", value, &v, msg) != USM_OK)
            return CLI_OPT_ERROR;
        if (!(v >= 1e-14 && v <= 1e-3)) {
            cli_msg(msg, "--rtol: must be in [1e-14, 1e-3], got %g", v);
            return CLI_OPT_ERROR;
        }
        o->rtol = v;
        o->atol = 1e-4 * v; /* the defaults' ratio (1e-8, 1e-12) */
        return CLI_OPT_TAKEN;
    }
    return CLI_OPT_NOT_MINE;
}

void cli_floquet_usage(FILE *out)
{
    fprintf(out,
            "  --floquet-method NAME  monodromy matrix by: auto (default: the fastest with ten\n"
            "                      correct digits, magnus), magnus, exponential, variational\n"
            "                      (CVODES, the independent check)\n"
            "  --rtol R            relative tolerance of the Floquet integration (default 1e-8;\n"
            "                      magnus: multipliers to 1e-2 R)\n");
}

int cli_plot_option(int argc, char **argv, int *i, const char **prefix, char msg[CLI_MSG_LEN])
{
    return cli_path_option(argc, argv, i, "--plot", "file prefix", prefix, msg);
}

int cli_from_rest_option(usm_op_options *o, int argc, char **argv, int *i,
                         char msg[CLI_MSG_LEN])
{
    const char *value;
    int r;
    if (strcmp(argv[*i], "--from-rest") == 0) {
        o->from_rest = 1;
        return CLI_OPT_TAKEN;
    }
    if (strcmp(argv[*i], "--no-from-rest") == 0) {
        o->from_rest = 0;
        return CLI_OPT_TAKEN;
    }
    if ((r = cli_option_value(argc, argv, i, "--from-rest-periods", &value, msg)) !=
        CLI_OPT_TAKEN)
        return r;
    if (cli_parse_double("--from-rest-periods", value, &o->periods, msg) != USM_OK)
        return CLI_OPT_ERROR;
    if (!(o->periods >= 1 && o->periods <= 1e7)) {
        cli_msg(msg, "--from-rest-periods: must be in [1, 1e7]");
        return CLI_OPT_ERROR;
    }
    return CLI_OPT_TAKEN;
}

void cli_from_rest_usage(FILE *out)
{
    fprintf(out,
            "  --from-rest         at the ambiguous points (several roots, or one stable root\n"
            "                      while the preload's moment holds the stator at rest)\n"
            "                      simulate the start-up from rest, below every unstable\n"
            "                      root, to find the operating point (0.1 .. 2 s a point);\n"
            "                      without it (the default here) such points have no\n"
            "                      operating point (unknown); other points are never simulated\n"
            "  --from-rest-periods N  length of that simulation in excitation periods\n"
            "                      (default 400)\n");
}

int cli_flag_option(char **argv, const int *i, const char *name, int *flag)
{
    if (strcmp(argv[*i], name) != 0)
        return CLI_OPT_NOT_MINE;
    *flag = 1;
    return CLI_OPT_TAKEN;
}

int cli_int_option(int argc, char **argv, int *i, const char *name, int *out,
                   char msg[CLI_MSG_LEN])
{
    const char *value;
    int r = cli_option_value(argc, argv, i, name, &value, msg);
    if (r == CLI_OPT_TAKEN && cli_parse_int(name, value, out, msg) != USM_OK)
        return CLI_OPT_ERROR;
    return r;
}

int cli_quantity_option(int argc, char **argv, int *i, const char *name, const char *unit,
                        double *out, char msg[CLI_MSG_LEN])
{
    const char *value;
    int r = cli_option_value(argc, argv, i, name, &value, msg);
    if (r == CLI_OPT_TAKEN && cli_parse_quantity(name, unit, value, out, msg) != USM_OK)
        return CLI_OPT_ERROR;
    return r;
}

int cli_path_option(int argc, char **argv, int *i, const char *name, const char *what,
                    const char **out, char msg[CLI_MSG_LEN])
{
    int r = cli_option_value(argc, argv, i, name, out, msg);
    if (r == CLI_OPT_TAKEN && (*out)[0] == '\0') {
        cli_msg(msg, "%s: empty %s", name, what);
        return CLI_OPT_ERROR;
    }
    return r;
}
