/* grid.h: the values of an equally spaced grid (internal; not installed).
 * One implementation for the sweeps (study/sweep.c, study/periodic_sweep.c),
 * the map's axes (study/map.c, usm_map_axis_value) and the report. */
#ifndef USM_CORE_GRID_H
#define USM_CORE_GRID_H

/* Value i of n (>= 2) equally spaced from `from` to `to`: the ends exactly,
 * the others (from (n-1-i) + to i) / (n-1), then the shortest decimal within
 * that computation's rounding error (2.5 eps max(|from|, |to|), at most a
 * quarter step), so that a decimal grid has the values as typed: 0.001 to
 * 0.005 in 9 points gives 0.0035, not 0.0035000000000000005.  Increasing in i
 * when from < to. */
double usm_grid_value(double from, double to, long i, long n);

/* The n values usm_grid_value gives, into out[0..n-1]: the same values for
 * about half the decimal conversions (each value's search starts from its
 * neighbour's precision). */
void usm_grid_fill(double from, double to, long n, double *out);

#endif /* USM_CORE_GRID_H */
