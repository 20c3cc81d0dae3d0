/* run.c: the usm_run object of every analysis (usm_run.h): outcome,
 * message, JSON, rows. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"

usm_run *run_new(int kind, const usm_model *m, const usm_params *p, void *data,
                 void (*free_data)(void *data))
{
    usm_run *r = data ? calloc(1, sizeof *r) : NULL;
    if (!r) {
        if (data)
            free_data(data);
        return NULL;
    }
    r->kind = kind;
    r->model = m;
    r->params = *p;
    r->data = data;
    r->free_data = free_data;
    r->status = USM_OK;
    return r;
}

void run_fail(usm_run *r, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->msg, sizeof r->msg, fmt, ap);
    va_end(ap);
    r->status = status;
}

void *run_data(const usm_run *r, int kind)
{
    return r && r->kind == kind ? r->data : NULL;
}

int usm_run_status(const usm_run *r)
{
    return r ? r->status : USM_EFAILED;
}

const char *usm_run_message(const usm_run *r)
{
    return r ? r->msg : "out of memory";
}

int usm_run_has_json(const usm_run *r)
{
    return r && r->has_json && r->write_json;
}

int usm_run_write_json(const usm_run *r, FILE *out)
{
    return usm_run_has_json(r) ? r->write_json(r, out) : -1;
}

char *usm_run_json(const usm_run *r, size_t *len)
{
    char *buf = NULL;
    size_t n = 0;
    if (!usm_run_has_json(r))
        return NULL;
    FILE *f = open_memstream(&buf, &n);
    if (!f)
        return NULL;
    int bad = r->write_json(r, f) != 0 || ferror(f);
    if (fclose(f) != 0 || bad || !buf) {
        free(buf);
        return NULL;
    }
    if (len)
        *len = n;
    return buf;
}

const double *usm_run_rows(usm_run *r, size_t *nrows, size_t *ncols)
{
    if (r && !r->rows && r->make_rows && r->make_rows(r) != 0) {
        free(r->rows);
        r->rows = NULL;
    }
    *nrows = r && r->rows ? r->nrows : 0;
    if (ncols)
        *ncols = r && r->rows ? r->ncols : 0;
    return r ? r->rows : NULL;
}

void usm_run_free(usm_run *r)
{
    if (!r)
        return;
    if (r->free_data)
        r->free_data(r->data);
    free(r->rows);
    free(r);
}
