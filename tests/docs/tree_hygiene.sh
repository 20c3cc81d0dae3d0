#!/bin/sh
# The tree reads on its own: README.md stays a guide a newcomer reads in ten
# minutes (at most 300 lines), no file refers to a tracker's numbered
# issues, which a reader of the repository cannot see, and the rooms stay
# as docs/architecture.md draws them: a folder a newcomer takes in at a
# glance (at most 25 files), and no file written by the rooms that compute.
# usage: tree_hygiene.sh SOURCE_DIR
set -eu
src=$1
fail=0
n=$(wc -l < "$src/README.md")
if [ "$n" -gt 300 ]; then
    echo "README.md has $n lines, more than 300: move reference material to docs/" >&2
    fail=1
fi
# Every file of the tree but git's own and build trees (build*/ at the top).
hits=$(cd "$src" && grep -rIn -i -E '\b(issue|task)s? [0-9]+' \
        --exclude-dir=.git --exclude-dir='build*' --exclude-dir=.cache . \
        | grep -v -E 'samples per task' || true)
if [ -n "$hits" ]; then
    echo "references to numbered issues (say what and why in words instead):" >&2
    echo "$hits" >&2
    fail=1
fi
# At most 25 files a folder of the code and its documents (tests/ and
# generated/ are laid out by their own rules).
for d in $(cd "$src" && find runtime derive python bench examples docs data -type d \
        -name __pycache__ -prune -o -type d -print); do
    k=$(find "$src/$d" -maxdepth 1 -type f ! -name '*.pyc' | wc -l)
    if [ "$k" -gt 25 ]; then
        echo "$d/ holds $k files, more than 25: split it into rooms (docs/architecture.md)" >&2
        fail=1
    fi
done
# The rooms that compute (and run/) open, create, rename or remove no file:
# a result's files are written above them (write/), through core/outfile.c,
# the one mechanism of whole-or-nothing files.
hits=$(cd "$src/runtime" && grep -n -E \
        '(^|[^_[:alnum:]])(fopen|fdopen|open|mkdir|rename|unlink|unlinkat|MPI_File_open)\(|usm_io_create|usm_io_dir_create|usm_outfile_(open|lock|place|remove_dir|clean_stages)' \
        core/*.c solve/*.c study/*.c design/*.c run/*.c | grep -v '^core/outfile\.c:' \
        | grep -v -E '^[^:]*:[0-9]+:[[:space:]]*(/?\*|//)' || true)
if [ -n "$hits" ]; then
    echo "files opened, written or removed in core/, solve/, study/, design/ or run/" \
        "(a writer belongs in write/):" >&2
    echo "$hits" >&2
    fail=1
fi
[ $fail -eq 0 ] && echo "tree_hygiene: README.md $n lines; no numbered-issue references;" \
    "folders of at most 25 files; none written where results are computed"
exit $fail
