/* The report's template engine (runtime/io/template.c, compiled in: it is
 * internal) is linear in its input: a false branch or an empty
 * array is parsed once, its nested {{#each}} bodies once, not once per
 * element (22 elements nested 8 deep under a false {{#if}} took 8 s per 176
 * bytes and grows 22x per level); {{@row}} counts written rows only; and
 * what is written is unchanged. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <jansson.h>

#include "check.h"
#include "template.h"
#include "usm.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* tpl rendered with data (JSON text) into a malloc'd string, or NULL. */
static char *render(const char *tpl, const char *json, int *rc, char msg[USM_IO_MSG_LEN])
{
    json_error_t jerr;
    json_t *data = json_loads(json, 0, &jerr);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!data || !f) {
        *rc = -1;
        return NULL;
    }
    *rc = usm_template_render(tpl, "t", data, f, msg);
    fclose(f);
    json_decref(data);
    return text;
}

int main(void)
{
    char msg[USM_IO_MSG_LEN], tpl[4096], data[1024];
    int rc;
    char *s;

    /* what is written */
    s = render("{{#each a}}[{{#each a}}{{.}}{{/each}}]{{/each}}", "{\"a\": [1, 2]}", &rc, msg);
    CHECK(rc == USM_OK && s && strcmp(s, "[12][12]") == 0, "nested each: \"%s\" (%s)", s, msg);
    free(s);
    s = render("{{#each e}}| {{@row}} |{{/each}}{{#if no}}{{@row}}{{/if}}| {{@row}} |",
               "{\"e\": [], \"no\": false}", &rc, msg);
    CHECK(rc == USM_OK && s && strcmp(s, "| 1 |") == 0, "@row after skipped rows: \"%s\"", s);
    free(s);
    s = render("{{#each a}}{{@row}}{{/each}}", "{\"a\": [0, 0, 0]}", &rc, msg);
    CHECK(rc == USM_OK && s && strcmp(s, "123") == 0, "@row: \"%s\"", s);
    free(s);
    /* errors are still found in a skipped body */
    s = render("{{#if no}}{{#each a}}{{#bogus}}{{/each}}{{/if}}", "{\"a\": [1], \"no\": 0}", &rc,
               msg);
    CHECK(rc != USM_OK && strstr(msg, "#bogus"), "an error in a skipped body: %d %s", rc, msg);
    free(s);

    /* 22 elements nested 8 deep under a false #if, 7 under an empty array
     * (MAX_DEPTH is 8): parsed once, in well under a second (was 22^8 and
     * 22^7 passes) */
    snprintf(data, sizeof data, "{\"no\": false, \"e\": [], \"a\": [");
    for (int i = 0; i < 22; ++i)
        snprintf(data + strlen(data), sizeof data - strlen(data), "%s%d", i ? "," : "", i);
    snprintf(data + strlen(data), sizeof data - strlen(data), "]}");
    for (int variant = 0; variant < 2; ++variant) {
        strcpy(tpl, variant ? "{{#each e}}" : "{{#if no}}");
        for (int k = 0; k < 8 - variant; ++k)
            strcat(tpl, "{{#each a}}x");
        for (int k = 0; k < 8 - variant; ++k)
            strcat(tpl, "{{/each}}");
        strcat(tpl, variant ? "{{/each}}" : "{{/if}}");
        const double t0 = now();
        s = render(tpl, data, &rc, msg);
        const double dt = now() - t0;
        CHECK(rc == USM_OK && s && s[0] == '\0', "%s: rc %d \"%s\"", variant ? "empty" : "false",
              rc, msg);
        CHECK(dt < 0.5, "%s, %d nested #each of 22 elements: %.3g s (not linear)",
              variant ? "an empty array" : "a false branch", 8 - variant, dt);
        free(s);
    }
    /* written, the cost is the output's: 22^3 x's */
    strcpy(tpl, "{{#each a}}{{#each a}}{{#each a}}x{{/each}}{{/each}}{{/each}}");
    s = render(tpl, data, &rc, msg);
    CHECK(rc == USM_OK && s && strlen(s) == 22 * 22 * 22, "written nested: %zu", s ? strlen(s) : 0);
    free(s);
    printf("test_template: %d failures\n", failures);
    return failures != 0;
}
