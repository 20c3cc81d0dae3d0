/* data_dir.h (internal): the files installed with the library (share/usm/): the paper's
 * published values, the report's templates and the static gnuplot scripts. */
#ifndef USM_DATA_DIR_H
#define USM_DATA_DIR_H

#include <stddef.h>

/* The path of data file `name` (e.g. "paper_values.json", "plots/speed.gp")
 * into buf: the first that exists of $USM_DATA_DIR/NAME, EXE/../share/usm/NAME
 * (an installed tree, wherever it was moved), the install prefix's share/usm/NAME
 * and the source tree's data/NAME
 * (a build tree).  0, or -1 when none exists (buf then names the last tried). */
int usm_data_path(const char *name, char *buf, size_t len);

#endif /* USM_DATA_DIR_H */
