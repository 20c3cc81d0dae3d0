/* json_out.h: JSON output of the usm command (jansson).
 *
 * Builders return a new reference, or NULL when out of memory.  Doubles are
 * printed in the shortest form that reads back bit for bit (0.005, not
 * 0.0050000000000000001): usm_json_dumpf.
 */
#ifndef USM_JSON_OUT_H
#define USM_JSON_OUT_H

#include <stdio.h>

#include <jansson.h>

#include "usm.h"
#include "usm_periodic.h"

/* The end of a builder that put with usm_json_put: obj when every put
 * succeeded, else NULL after releasing obj (the builders' "out of memory"). */
json_t *usm_json_finish(json_t *obj, int ok);

/* A JSON number, or null for a non-finite value (JSON has no NaN/inf). */
json_t *usm_json_real(double v);

/* Add `value` to `obj` under `key`, taking the reference.  Once anything
 * failed *ok is 0 and stays 0, so a builder can check once at the end. */
void usm_json_put(json_t *obj, const char *key, json_t *value, int *ok);

/* {"m0": ..., ...}: every parameter, in the table's order. */
json_t *usm_json_params(const usm_params *p);

/* One stationary root: theta, alpha, beta, rotor_speed, F_n, F_t, v_rel,
 * stick_admissible, mu_used, v_c, R_star, Z, residual_norm. */
json_t *usm_json_root(const usm_steady_solution *s);

/* {"t0", "multipliers": [[re, im], ...], "cyclic": [bool, ...],
 *  "max_modulus", "stable"}. */
json_t *usm_json_floquet(const usm_floquet_result *r);

/* The dominant complex pair of r for a motion of frequency f (usm.h,
 * usm_floquet_squeal) as keys of obj: squeal_frequency [Hz] (null when
 * there is no complex pair), squeal_multiplier ([re, im], im > 0, or null),
 * squeal_reason (null, or why there is none). */
void usm_json_put_squeal(json_t *obj, const usm_floquet_result *r, double f, int *ok);

/* The keys of `usm periodic --json` for one orbit (all but model, parameters,
   converged): shared by `usm periodic` and the periodic sweep's points. */
json_t *usm_json_periodic_result(const usm_periodic_result *r);
/* The keys of an orbit with separation (usm periodic --json on a unilateral
 * model, docs/unilateral.md); slip: the model's (its impacts may slide). */
json_t *usm_json_hybrid_result(const usm_hybrid_result *r);

/* Print `value` and a newline, then release it (NULL, a builder's "out of
 * memory", gives -1).  0, or -1. */
int usm_json_write(json_t *value, FILE *out);

/* json_dumpf with every real number in the shortest text that reads back to
 * the same double (usm_shortest; "1.0" keeps its ".0", exponents as jansson
 * writes them: 1e-5).  0, or -1 on a write error. */
int usm_json_dumpf(const json_t *value, FILE *out, size_t flags);

/* Print `value` and a newline.  0, or -1 on a write error. */
int usm_json_print(const json_t *value, FILE *out);

#endif /* USM_JSON_OUT_H */
