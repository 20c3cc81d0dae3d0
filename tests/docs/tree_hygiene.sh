#!/bin/sh
# The tree reads on its own: README.md stays a guide a newcomer reads in ten
# minutes (at most 300 lines), and no file refers to a tracker's numbered
# issues, which a reader of the repository cannot see.
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
[ $fail -eq 0 ] && echo "tree_hygiene: README.md $n lines; no numbered-issue references"
exit $fail
