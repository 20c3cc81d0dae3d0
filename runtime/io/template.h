/* template.h: text with named placeholders filled from a JSON object.
 *
 *   {{path}}            the value at path: a number as %.10g, a string as is,
 *                       true/false as yes/no, null (a value that does not
 *                       exist) as n/a
 *   {{path:FMT}}        a number through printf's %FMT, FMT one of [+ ] then
 *                       [.digits] then g, f or e (".6g", "+.2g", ".4f"); or m
 *                       (".6m"): as g, with more digits where the rounding
 *                       would put the text on the other side of 1 than the
 *                       value, or on 1 (a Floquet modulus 0.9999999 is not
 *                       "1"); or FMT "cell": a string made safe for a
 *                       Markdown table cell
 *   {{#each path}}..{{/each}}       once per element of an array; inside, a
 *                       path is looked up in the element first, then outside
 *   {{#if path}}..{{else}}..{{/if}} (and #unless): true, a nonzero number, a
 *                       non-empty string or array; @first inside #each
 *   {{@row}}            a counter: 1, 2, ... (numbered table rows)
 *   {{.}}               the element itself inside #each (an array of strings)
 * A path is keys and array indices joined by dots: "model.3dof.fl.0.max_modulus".
 * An unknown path or a malformed template is an error naming the line.
 * Cost: linear in the template plus the output -- a false branch or an empty
 * array is parsed once (its #each bodies once, not once per element), and
 * {{@row}} counts written rows only. */
#ifndef USM_TEMPLATE_H
#define USM_TEMPLATE_H

#include <stdio.h>

#include <jansson.h>

#include "io_msg.h"

/* Render template text `tpl` (named `name` in messages) with the values of
 * `data` to out.  USM_OK, or USM_EFAILED with "NAME:LINE: reason" in msg. */
int usm_template_render(const char *tpl, const char *name, json_t *data, FILE *out,
                        char msg[USM_IO_MSG_LEN]);

/* Read the whole file at path into a NUL-terminated string (free() it);
 * NULL with msg on failure. */
char *usm_template_read(const char *path, char msg[USM_IO_MSG_LEN]);

#endif /* USM_TEMPLATE_H */
