#!/usr/bin/env bash
# svr as others get it (issue 50): installed, moved, its source out of sight, and linked.
#
#   tests/install/run.sh BUILD_DIR        (ctest install.prefix_example_deb; exit 77: skipped)
#
# 1. `cmake --install BUILD_DIR` into a temporary prefix, which is then moved elsewhere (an
#    installed svr finds its data relative to itself).
# 2. With the source tree and the build hidden under an empty tmpfs (a private mount namespace,
#    `unshare -m`, as if both were deleted): `svr --version`, `svr demo --quick`, and `svr render`
#    of the engine with factor:6.
# 3. examples/cpp built against the prefix with find_package(svr), and the same source built with
#    `pkg-config --cflags --libs svr`: each renders the engine with factor:6 under D65, and its
#    PNG must equal svr render's D65.png pixel for pixel (idiff -fail 0).
# 4. `cpack -G DEB`: the package's contents are listed, it is unpacked with `dpkg -x` into a
#    temporary root (the machine's own packages are not touched), and the example is built and
#    run against that root, with the same check.
set -euo pipefail
if ! unshare -m true 2> /dev/null; then
  echo "skipped: a private mount namespace (unshare -m) needs root"
  exit 77
fi
build=$(realpath "$1")
source_dir=$(realpath "$(dirname "$0")/../..")
work=$(mktemp -d /tmp/svr_install_test.XXXXXX)
trap 'rm -rf "$work"' EXIT
say() { printf 'install test: %s\n' "$*"; }

say "cmake --install into $work/staging, moved to $work/prefix"
cmake --install "$build" --prefix "$work/staging" > "$work/install.log"
mv "$work/staging" "$work/prefix"
prefix=$work/prefix
cp -r "$source_dir/examples/cpp" "$work/example"
test -f "$prefix/include/svr/svr.h" && test -f "$prefix/share/svr/spectra/cie1931_2deg_xyz_cmf_1nm.csv"
libdir=$(dirname "$(find "$prefix" -name 'libsvr.so' -print -quit)")
readelf -d "$libdir/libsvr.so" | grep -q 'SONAME.*libsvr.so.0.1' || { echo "libsvr.so has no SONAME libsvr.so.0.1"; exit 1; }
# Only the public headers: svr.h and error.h.
ls "$prefix/include/svr"

# Runs "$@" with the source tree and the build folder hidden.
without_source() {
  unshare -m bash -c 'mount -t tmpfs none "$1" && shift && "$@"' _ "$source_dir" "$@"
}

say "the installed svr, its source hidden"
without_source "$prefix/bin/svr" --version | tee "$work/version.txt"
grep -q "^data: $prefix/share/svr$" "$work/version.txt" || { echo "svr --version names no installed data folder"; exit 1; }
# Found through PATH, from a folder that holds something named svr: the installed data still.
mkdir -p "$work/elsewhere/svr"
(cd "$work/elsewhere" && PATH="$prefix/bin:$PATH" without_source svr --version) | grep -q "^data: $prefix/share/svr$" \
  || { echo "svr from PATH, run beside a folder named svr, does not find its installed data"; exit 1; }
without_source "$prefix/bin/svr" demo --quick --out "$work/demo" > "$work/demo.log" 2>&1 || { tail -30 "$work/demo.log"; exit 1; }
test -s "$work/demo/report.html"
scene=$prefix/share/svr/scenes/engine.json
without_source "$prefix/bin/svr" render "$scene" --model factor:6 --out "$work/render" -q
reference=$work/render/D65.png

# check NAME PNG: the example's PNG is svr render's, pixel for pixel.
check() {
  idiff -fail 0 -warn 0 "$2" "$reference" > "$work/idiff.log" || { cat "$work/idiff.log"; echo "$1: differs from svr render"; exit 1; }
  say "$1: equals svr render's D65.png"
}

# docs/api.md shows the example whole: the copy there is the file built here.
python3 - "$source_dir/docs/api.md" "$work/example/render_d65.cpp" <<'PY'
import sys
doc, example = open(sys.argv[1]).read(), open(sys.argv[2]).read()
block = doc.split("<!-- examples/cpp/render_d65.cpp -->\n```cpp\n", 1)[1].split("```", 1)[0]
sys.exit(0 if block == example else "docs/api.md's copy of examples/cpp/render_d65.cpp differs from the file")
PY

say "examples/cpp with find_package(svr)"
cmake -S "$work/example" -B "$work/example-build" -DCMAKE_PREFIX_PATH="$prefix" > "$work/example.log"
cmake --build "$work/example-build" >> "$work/example.log"
without_source "$work/example-build/render_d65" "$scene" "$work/find_package.png"
check "find_package" "$work/find_package.png"

say "examples/cpp with pkg-config"
flags=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --cflags --libs svr)
g++ -std=c++17 "$work/example/render_d65.cpp" -o "$work/render_d65_pc" $flags -Wl,-rpath,"$libdir"
without_source "$work/render_d65_pc" "$scene" "$work/pkg_config.png"
check "pkg-config" "$work/pkg_config.png"

say "cpack -G DEB"
(cd "$build" && cpack -G DEB -B "$work/deb" > "$work/cpack.log") || { tail -20 "$work/cpack.log"; exit 1; }
deb=$(find "$work/deb" -maxdepth 1 -name 'svr_*.deb' -print -quit)
dpkg-deb -I "$deb" | grep -E 'Package|Version|Depends'
dpkg -c "$deb" | awk '{print $6}' | grep -E '/(bin/svr|libsvr\.so.*|svr\.h|svrConfig\.cmake|svr\.pc|engine\.json)$'
dpkg -x "$deb" "$work/root"
cmake -S "$work/example" -B "$work/example-deb" -DCMAKE_PREFIX_PATH="$work/root/usr" > "$work/example-deb.log"
cmake --build "$work/example-deb" >> "$work/example-deb.log"
without_source "$work/example-deb/render_d65" "$scene" "$work/deb.png"
check "the .deb, unpacked" "$work/deb.png"
say "passed"
