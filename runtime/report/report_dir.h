/* report_dir.h: the report's directory, written whole (report_dir.c).  Not
 * installed; not part of the API.
 *
 * usm_report_stage_begin takes the lock PARENT/.NAME.usm-lock (flock; a
 * second run into the same directory fails at once), removes staging
 * directories that interrupted runs left, and creates PARENT/.NAME.usm-new-XXXXXX,
 * where the report is written.  usm_report_stage_publish puts it in place:
 * renamed to DIR when DIR does not exist, swapped with DIR when DIR holds
 * only the report's files, else moved in file by file (outputs last).
 * usm_report_stage_end removes what is left of the staging directory and
 * releases the lock. */
#ifndef USM_REPORT_DIR_H
#define USM_REPORT_DIR_H

#include <limits.h>

#include "usm_io.h" /* USM_IO_MSG_LEN */

typedef struct usm_report_stage {
    char dir[PATH_MAX];    /* the report's directory */
    char parent[PATH_MAX]; /* its parent */
    char stage[PATH_MAX];  /* where the report is written; "" once published */
    int lock_fd;
} usm_report_stage;

/* USM_OK, or USM_EINPUT with "DIR: reason" in msg (then nothing is held). */
int usm_report_stage_begin(usm_report_stage *st, const char *dir, char msg[USM_IO_MSG_LEN]);

/* USM_OK, or USM_EFAILED with msg. */
int usm_report_stage_publish(usm_report_stage *st, char msg[USM_IO_MSG_LEN]);

void usm_report_stage_end(usm_report_stage *st);

#endif /* USM_REPORT_DIR_H */
