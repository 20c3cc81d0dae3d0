#!/usr/bin/env bash
# `usm equations`: every equation a document lists is in it, for every generated
# model, in both formats; and the LaTeX compiles (pdflatex, when installed).
# Usage: equations_check.sh PATH/TO/usm
set -euo pipefail
usm=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
models=$("$usm" variants | awk '{split($2, b, ","); for (i in b) print b[i] ($1 == "paper" ? "" : "_" $1)}')
for model in $models; do
    base=${model%%_*}
    variant=${model#"$base"}; variant=${variant#_}; variant=${variant:-paper}
    "$usm" equations --model "$base" --variant "$variant" > "$tmp/$model.md"
    "$usm" equations --model "$base" --variant "$variant" --format latex > "$tmp/$model.tex"
    tags=$(sed -n 's/^Equations: //p' "$tmp/$model.md" | tr -d '()' | tr ',' '\n' | tr -d ' ')
    [ -n "$tags" ] || { echo "FAIL $model: no equation list"; fail=1; continue; }
    n=0
    for tag in $tags; do
        n=$((n + 1))
        grep -qF "\\tag{$tag}" "$tmp/$model.md" || { echo "FAIL $model.md lacks ($tag)"; fail=1; }
        grep -qF "number={$tag}" "$tmp/$model.tex" || { echo "FAIL $model.tex lacks ($tag)"; fail=1; }
    done
    # the paper's numbered equations that every model must state
    for tag in 2.1 2.2 2.3 2.8 2.9 2.10 2.11 3.1a 3.1b 3.1c 3.5a 3.5b 3.6; do
        grep -qx "$tag" <<< "$tags" || { echo "FAIL $model: equation ($tag) missing"; fail=1; }
    done
    if command -v pdflatex > /dev/null; then
        if (cd "$tmp" && pdflatex -interaction=nonstopmode -halt-on-error "$model.tex" > "$model.out" 2>&1); then
            echo "ok   $model: $n equations, LaTeX compiles"
        else
            echo "FAIL $model: pdflatex failed"; grep -A3 '^!' "$tmp/$model.out" | head; fail=1
        fi
    else
        echo "ok   $model: $n equations (pdflatex not installed: LaTeX not compiled)"
    fi
done
exit $fail
