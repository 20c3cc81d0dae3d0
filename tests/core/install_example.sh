#!/usr/bin/env bash
# The installed library works for a program outside usm's build.
#   install_example.sh BUILD_DIR SOURCE_DIR C_COMPILER
# Installs BUILD_DIR into a temporary prefix, checks the installed tree
# (headers, shared and static library, usm command, CMake package, usm.pc),
# builds examples/usm_example.c from the installed tree
#   - with CMake (find_package(usm)): usm::usm and usm::usm_static,
#   - with pkg-config: the documented command lines, shared and static
#     (docs/library.md), and examples/Makefile,
#   - at -O0, and at -O0 with AddressSanitizer and UBSan (a kernel writing
#     past an array the example passes it fails here),
# runs every build and compares its numbers with the installed
# `usm steady --json`: theta, alpha, rotor speed and the Floquet multipliers
# to 1e-12 relative, and the versions with `usm --version`.
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
cc=$3
python=/usr/bin/python3
[ -x "$python" ] || python=python3

tmp=$(mktemp -d "${TMPDIR:-/tmp}/usm-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
fail() { echo "FAIL: $*" >&2; exit 1; }

echo "== cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "install"; }

# The installed tree.
pc=$(find "$prefix" -name usm.pc -path '*/pkgconfig/*' | head -n 1)
[ -n "$pc" ] || fail "no usm.pc installed"
libdir=$(dirname "$(dirname "$pc")")
for f in bin/usm include/usm/usm.h include/usm/usm_sweep.h include/usm/usm_kernels.h \
         share/doc/usm/library.md share/doc/usm/examples/usm_example.c \
         share/doc/usm/examples/Makefile share/doc/usm/examples/CMakeLists.txt; do
    [ -e "$prefix/$f" ] || fail "$f not installed"
done
for f in libusm.a libusm.so; do
    [ -e "$libdir/$f" ] || fail "$libdir/$f not installed"
done
[ -n "$(find "$libdir" -name 'libusm.so.*' -print -quit)" ] || fail "no versioned libusm.so.* installed"
for f in usmConfig.cmake usmConfigVersion.cmake usmTargets.cmake; do
    [ -e "$libdir/cmake/usm/$f" ] || fail "$libdir/cmake/usm/$f not installed"
done
# Every public header of the source and build trees is installed.
for h in "$src"/runtime/include/usm/*.h; do
    [ -e "$prefix/include/usm/$(basename "$h")" ] || fail "$(basename "$h") not installed"
done

usm=$prefix/bin/usm
"$usm" --version > "$tmp/version.txt"
"$usm" steady --json > "$tmp/usm.json"

export PKG_CONFIG_PATH=$libdir/pkgconfig
echo "== pkg-config: $(pkg-config --cflags --libs usm)"
[ "$(pkg-config --modversion usm)" = "$(sed -n 's/^usm \([^ ]*\)$/\1/p' "$tmp/version.txt")" ] ||
    fail "pkg-config --modversion usm differs from usm --version"

echo "== CMake: find_package(usm) with CMAKE_PREFIX_PATH=$prefix"
cmake -S "$src/examples" -B "$tmp/build-cmake" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_C_COMPILER="$cc" -DCMAKE_BUILD_TYPE=Release > "$tmp/cmake.log" ||
    { cat "$tmp/cmake.log"; fail "configure examples/"; }
cmake --build "$tmp/build-cmake" > "$tmp/cmake-build.log" 2>&1 ||
    { cat "$tmp/cmake-build.log"; fail "build examples/ with CMake"; }

echo "== pkg-config: cc usm_example.c \$(pkg-config --cflags --libs usm)"
# shellcheck disable=SC2046
"$cc" -O2 -Wall -Wextra -Werror -o "$tmp/usm_example_pc" "$src/examples/usm_example.c" \
      $(pkg-config --cflags --libs usm) || fail "build with pkg-config"
echo "== pkg-config, static: ... -Wl,--as-needed -Wl,-Bstatic -lusm -Wl,-Bdynamic \$(pkg-config --static --libs usm)"
# shellcheck disable=SC2046
"$cc" -O2 -Wall -Wextra -Werror -o "$tmp/usm_example_pc_static" "$src/examples/usm_example.c" \
      $(pkg-config --cflags usm) -L"$(pkg-config --variable=libdir usm)" -Wl,--as-needed \
      -Wl,-Bstatic -lusm -Wl,-Bdynamic $(pkg-config --static --libs usm) || fail "static build with pkg-config"
# the same line with AddressSanitizer (whose link drops the default --as-needed): no libusm.so
# shellcheck disable=SC2046
"$cc" -O0 -g -fsanitize=address -Wall -Wextra -Werror -o "$tmp/usm_example_pc_static_asan" \
      "$src/examples/usm_example.c" $(pkg-config --cflags usm) -L"$(pkg-config --variable=libdir usm)" \
      -Wl,--as-needed -Wl,-Bstatic -lusm -Wl,-Bdynamic $(pkg-config --static --libs usm) ||
    fail "static ASan build with pkg-config"
if readelf -d "$tmp/usm_example_pc_static_asan" | grep -q 'NEEDED.*libusm'; then
    fail "the static pkg-config line with ASan still needs libusm.so"
fi
# -O0: an array the example hands a kernel too short overwrites its
# neighbours on the stack (the kernels, in the uninstrumented library, write
# past it unseen by ASan; an earlier example lost its Floquet multipliers so),
# and the numbers compared below differ; ASan and UBSan check the example's
# own accesses.
echo "== pkg-config, -O0, and -O0 with AddressSanitizer and UBSan"
# shellcheck disable=SC2046
"$cc" -O0 -g -Wall -Wextra -Werror -o "$tmp/usm_example_O0" "$src/examples/usm_example.c" \
      $(pkg-config --cflags --libs usm) || fail "build with -O0"
# shellcheck disable=SC2046
"$cc" -O0 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all \
      -Wall -Wextra -Werror -o "$tmp/usm_example_asan" "$src/examples/usm_example.c" \
      $(pkg-config --cflags --libs usm) || fail "build with -O0 -fsanitize=address"
echo "== pkg-config: examples/Makefile"
cp "$src/examples/Makefile" "$src/examples/usm_example.c" "$tmp/"
make -s -C "$tmp" CC="$cc" usm_example > "$tmp/make.log" 2>&1 || { cat "$tmp/make.log"; fail "make"; }

run() {  # run NAME COMMAND...: the example's JSON into $tmp/NAME.json
    local name=$1; shift
    "$@" > "$tmp/$name.json" || fail "$name exited with status $?"
}
run cmake_shared "$tmp/build-cmake/usm_example"
run cmake_static "$tmp/build-cmake/usm_example_static"
LD_LIBRARY_PATH=$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} run pkgconfig "$tmp/usm_example_pc"
run makefile "$tmp/usm_example"   # run path set by the Makefile
run pkgconfig_static "$tmp/usm_example_pc_static"
LD_LIBRARY_PATH=$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} run O0 "$tmp/usm_example_O0"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 LD_LIBRARY_PATH=$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} \
    run asan_O0 "$tmp/usm_example_asan"
# The shared builds use the installed libusm.so, the static ones do not.
ldd "$tmp/build-cmake/usm_example" > "$tmp/ldd.txt" 2>&1
grep -q "$libdir/libusm.so" "$tmp/ldd.txt" || { cat "$tmp/ldd.txt"; fail "CMake build does not use $libdir/libusm.so"; }
for exe in "$tmp/build-cmake/usm_example_static" "$tmp/usm_example_pc_static"; do
    # (no `ldd | grep -q` under pipefail: grep's early exit would make ldd's SIGPIPE the status)
    ldd "$exe" > "$tmp/ldd.txt" 2>&1
    if grep -q libusm "$tmp/ldd.txt"; then fail "$exe is linked with libusm.so"; fi
done

"$python" - "$tmp" <<'EOF'
import json, math, sys
tmp = sys.argv[1]
ref = json.load(open(f"{tmp}/usm.json"))
version = open(f"{tmp}/version.txt").read().split("\n")
def close(a, b, rel=1e-12):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)
bad = []
for name in ("cmake_shared", "cmake_static", "pkgconfig", "pkgconfig_static", "makefile", "O0", "asan_O0"):
    ex = json.load(open(f"{tmp}/{name}.json"))
    if version[0] != f"usm {ex['usm_version']}":
        bad.append(f"{name}: usm_version() {ex['usm_version']} but `usm --version`: {version[0]}")
    if not version[1].startswith(f"usm generator {ex['generator_version']} "):
        bad.append(f"{name}: usm_generator_version() {ex['generator_version']} but `usm --version`: {version[1]}")
    for key in ("theta", "alpha", "rotor_speed"):
        if not close(ex[key], ref[key]):
            bad.append(f"{name}: {key} {ex[key]!r} != usm steady {ref[key]!r}")
    mult, refm = ex["multipliers"], ref["floquet"]["multipliers"]
    if len(mult) != len(refm):
        bad.append(f"{name}: {len(mult)} multipliers, usm steady {len(refm)}")
    else:
        scale = max(math.hypot(*m) for m in refm)
        for (a, b), (c, d) in zip(mult, refm):
            if abs(a - c) > 1e-12 * scale or abs(b - d) > 1e-12 * scale:
                bad.append(f"{name}: multiplier {a!r}{b:+}i != usm steady {c!r}{d:+}i")
    # The stationary orbit solves M(x) x' = f(x, t) (the kernels, called directly).
    # (rounding: c_t (phi + psi cos theta) with c_t = 1e4 N m and phi ~ 5 rad
    # leaves ~1e-12 N m; the excitation torque m0 is 5e-3 N m)
    if not ex["orbit_residual_max"] <= 1e-6 * ex["m0"]:
        bad.append(f"{name}: orbit residual {ex['orbit_residual_max']} N m (m0 {ex['m0']} N m)")
    print(f"{name}: theta {ex['theta']:.17g}, alpha {ex['alpha']:.17g}, "
          f"rotor speed {ex['rotor_speed']:.17g}, {len(mult)} multipliers, "
          f"orbit residual {ex['orbit_residual_max']:.3g}")
for b in bad:
    print("FAIL:", b)
sys.exit(1 if bad else 0)
EOF

# The Python package (built when python3-dev, python3-numpy and cython3 are
# there): installed under PREFIX/lib/python3.X/dist-packages (lib/python3/
# dist-packages for the prefix /usr), it imports from there, outside the
# build tree, and gives the installed `usm steady --json` bit for bit.
if grep -qx 'USM_PYTHON_PACKAGE:BOOL=ON' "$build/CMakeCache.txt"; then
    pydir=$(find "$prefix/lib" -maxdepth 3 -type d -name dist-packages | head -n 1)
    [ -n "$pydir" ] && [ -e "$pydir/usm/__init__.py" ] || fail "the Python package usm is not installed"
    echo "== Python: PYTHONPATH=$pydir"
    (cd "$tmp" && PYTHONPATH=$pydir "$python" -c "
import json, sys, usm
assert usm.__file__.startswith('$pydir'), usm.__file__
sys.exit(0 if usm.Model().steady().to_dict() == json.load(open('usm.json')) else 1)") ||
        fail "the installed Python package differs from usm steady --json"
fi
echo "install and examples: ok"
