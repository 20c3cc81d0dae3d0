/* usm_progress.h: how a long study says how far it is.
 *
 * A study whose options hold a usm_progress with fn != NULL calls
 * fn(ctx, done, total, what) while it runs: done units of work out of total
 * ("points", "samples", ...; `what` names the unit and stays valid for the
 * call only).  The calls come one at a time (never two at once, whichever
 * thread makes them), done never decreases, the first call may report work
 * already done (a resumed checkpoint) and the last one has done == total when
 * the study completes.  Calls are rate-limited (about ten a second, plus the
 * first and the last), so a callback that prints costs nothing measurable.
 * fn == NULL (the default of every options struct): no calls.  The callback
 * must not call back into the study; the results do not depend on it.
 */
#ifndef USM_PROGRESS_H
#define USM_PROGRESS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef void (*usm_progress_fn)(void *ctx, long done, long total, const char *what);

typedef struct usm_progress {
    usm_progress_fn fn; /* NULL: silent */
    void *ctx;          /* passed to fn */
} usm_progress;

#ifdef __cplusplus
}
#endif

#endif /* USM_PROGRESS_H */
