#!/usr/bin/env bash
# `usm equations`: for every generated model, in both formats, every equation
# number of the paper's sections 2-5 that the model uses is in the document
# (the lists below, from the paper), no ASCII names stand in for symbols in
# the prose, the LaTeX compiles without overfull boxes (pdflatex log, when
# pdflatex is installed), and --diff prints exactly the highlighted lines.
# Usage: equations_cli.sh PATH/TO/usm
set -euo pipefail
usm=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
# the paper's numbered equations every model states (kinematics, forces,
# torques, Euler's equations, stationary solution, linearisation) ...
common="2.1 2.2 2.3 2.5 2.6 2.7 2.8 2.9 2.10 2.11 3.1a 3.1b 3.1c 3.2 3.3 3.4 3.5a 3.5b 4.9"
# ... (3.6), beta from the twisting balance, where the twist angle is the paper's
# phi + psi cos(theta) (under the integrated twist law psi is cyclic and beta free) ...
# ... and those of the stick model (sections 2-4) and of the slip model (section 5)
stick="2.4 3.7 4.6"
slip="5.1 5.2 5.3"
models=$("$usm" variants | awk '{split($2, b, ","); for (i in b) print b[i] ($1 == "paper" ? "" : "_" $1)}')
for model in $models; do
    base=${model%%_*}
    variant=${model#"$base"}; variant=${variant#_}; variant=${variant:-paper}
    md="$tmp/$model.md"; tex="$tmp/$model.tex"
    "$usm" equations --model "$base" --variant "$variant" > "$md"
    "$usm" equations --model "$base" --variant "$variant" --format latex > "$tex"
    "$usm" equations --model "$base" --variant "$variant" --diff > "$tmp/$model.diff.md"
    "$usm" equations --model "$base" --variant "$variant" --diff --format latex > "$tmp/$model.diff.tex"
    if [ "$base" = 3dof ]; then tags="$common $stick"; else tags="$common $slip 3.5c"; fi
    if grep -q '^Assumptions as derive/variants.py.*`twist = integrated`' "$md"; then
        if grep -qF '\tag{3.6}' "$md"; then echo "FAIL $model.md: (3.6) under the integrated twist"; fail=1; fi
    else
        tags="$tags 3.6"
    fi
    # a model in the tilt-vector coordinates (docs/coordinates.md) states the
    # paper's physics in other variables: Z (2.3), M and f through subexpressions, and the
    # stationary problem ((3.1) its orbit, (3.5), (3.7)); the force laws and torques
    # are named in its prose, not tagged line by line (the numbers are the paper's
    # Euler-angle equations); equations_proof checks its lines against the kernels
    if grep -q '^Assumptions.*`coordinates = tilt_vector`' "$md"; then
        tags="2.3 3.1 3.5"; [ "$base" = 3dof ] && tags="$tags 3.7"
    fi
    n=0
    for tag in $tags; do
        n=$((n + 1))
        grep -qF "\\tag{$tag}" "$md" || { echo "FAIL $model.md lacks ($tag)"; fail=1; }
        grep -qF "\\tag{$tag}" "$tex" || { echo "FAIL $model.tex lacks ($tag)"; fail=1; }
    done
    # an imperfect motor: the stationary section (checked above) holds at zero imperfection
    # only, and says so (tests/derive/equations_proof.py checks its lines against the kernels)
    if grep -q '^Assumptions as derive/variants.py.*`imperfection = ' "$md"; then
        grep -qxF '\varepsilon = \delta = s = 0' "$md" || { echo "FAIL $model.md: no condition varepsilon = delta = s = 0 on the stationary solution"; fail=1; }
    fi
    # page 1 is the model in words and its parameters, not code flags: the flags are in the appendix
    first=$(grep -n -m1 '`contact = ' "$md" | cut -d: -f1)
    params=$(grep -n -m1 '^## Parameters' "$md" | cut -d: -f1)
    appendix=$(grep -n -m1 '^## Appendix' "$md" | cut -d: -f1)
    if [ -z "$params" ] || [ -z "$appendix" ] || [ "${first:-0}" -lt "$appendix" ]; then
        echo "FAIL $model.md: the parameters come first and the code flags in the appendix"; fail=1
    fi
    if grep -q 'Highlighted' "$tmp/$model.diff.md"; then echo "FAIL $model: --diff says Highlighted"; fail=1; fi
    # prose: outside $...$ no symbol is spelled in ASCII (phi_Rddot, omega_A x L)
    bad=$(awk '/^\$\$$/ {m = !m; next} !m' "$md" | sed 's/\$[^$]*\$//g; s/`[^`]*`//g' \
          | grep -nE 'dot|ddot|omega|theta|phi|psi|R_star| x L' || true)
    [ -z "$bad" ] || { echo "FAIL $model.md: ASCII names in prose: $bad"; fail=1; }
    # --diff: the highlighted equations, no others, each after the paper's version it replaces
    nmark=$(grep -c '^> \*\*Changed by the variant\*\*' "$md" || true)
    ndiff=$(grep -c '^\*\*This model:\*\*$' "$tmp/$model.diff.md" || true)
    nold=$(grep -c "^\*\*Paper's model:\*\*" "$tmp/$model.diff.md" || true)
    if [ "$nold" -lt "$ndiff" ]; then
        echo "FAIL $model: --diff shows $ndiff new lines but $nold old ones"; fail=1
    fi
    if [ "$variant" = paper ]; then
        grep -q "no differences" "$tmp/$model.diff.md" && [ "$nmark" = 0 ] && [ "$ndiff" = 0 ] \
            || { echo "FAIL $model: the paper's model has differences"; fail=1; }
    elif [ "$nmark" = 0 ] || [ "$nmark" != "$ndiff" ]; then
        echo "FAIL $model: $nmark highlighted equations, --diff prints $ndiff"; fail=1
    fi
    if command -v pdflatex > /dev/null; then
        if (cd "$tmp" && pdflatex -interaction=nonstopmode -halt-on-error "$model.tex" > "$model.out" 2>&1 \
                && pdflatex -interaction=nonstopmode -halt-on-error "$model.diff.tex" > "$model.diff.out" 2>&1); then
            if grep -q '^Overfull' "$tmp/$model.log" "$tmp/$model.diff.log"; then
                echo "FAIL $model: overfull boxes:"; grep -A2 '^Overfull' "$tmp/$model.log" "$tmp/$model.diff.log" | head; fail=1
            else
                echo "ok   $model: $n paper equations, $nmark highlighted, LaTeX (full and --diff) compiles, no overfull box"
            fi
        else
            echo "FAIL $model: pdflatex failed"; grep -A3 '^!' "$tmp/$model.out" "$tmp/$model.diff.out" | head; fail=1
        fi
    else
        echo "ok   $model: $n paper equations, $nmark highlighted (pdflatex not installed: LaTeX not compiled)"
    fi
done
exit $fail
