#!/usr/bin/env bash
# Installs the Debian packages svr builds and tests with. Does nothing when all are present.
# Usage: ./setup.sh            (as root, or a user with sudo)
#        ./setup.sh --peers    also VTK and Xvfb for bench/peers/run: ~30 MB to download, ~200 MB
#                              installed, ~40 s; left out of the default (and CI) for that cost
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libomp-dev libglm-dev
  libosmesa6-dev libopenimageio-dev openimageio-tools
  libegl-dev libegl-mesa0  # the gl backend's EGL platform: libglvnd's libEGL and Mesa's vendor library
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev
  zlib1g-dev libteem-dev libssl-dev
  libnifti2-dev libgdcm-dev libtiff-dev  # volume readers: NIfTI, DICOM series, TIFF stacks
  python3-matplotlib python3-numpy
  clang libclang-rt-14-dev time  # the fuzz preset: clang++ and libFuzzer; CPU seconds (tests/fuzz)
  libvolpack1-dev  # bench/peers: VolPack, the shear-warp peer (small, static)
  libcpp-httplib-dev chromium  # svr view: its HTTP server; its page's tests in a real browser
  libopenmpi-dev openmpi-bin  # svr-mpi: brick-distributed rendering (docs/distributed.md)
  dpkg-dev  # cpack -G DEB's dpkg-shlibdeps (tests/install, docs/api.md)
  universal-ctags  # tests/code_rules.py: every function's length
  pybind11-dev python3-dev python3-pytest python3-pil  # `import svr` (python/, docs/python.md) and its tests
)
case "${1:-}" in
  "") ;;
  --peers) PACKAGES+=(python3-vtk9 xvfb xauth) ;;  # bench/peers: VTK's ray caster under Xvfb
  *) echo "setup: unknown argument '$1' (expected --peers or nothing)" >&2; exit 2 ;;
esac

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# The page's tests drive chromium with puppeteer-core from npm (tests/browser/package.json),
# installed into tests/browser/node_modules. Node comes from Debian's nodejs (with npm) unless
# the machine already has a node and npm of its own.
need_node=()
command -v node >/dev/null || need_node+=(nodejs)
command -v npm >/dev/null || need_node+=(npm)

browser_deps() {
  local dir
  dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/tests/browser"
  if [ ! -f "$dir/node_modules/puppeteer-core/package.json" ]; then
    echo "setup: npm ci in tests/browser (puppeteer-core, pngjs)"
    (cd "$dir" && PUPPETEER_SKIP_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  fi
}

if [ ${#missing[@]} -eq 0 ] && [ ${#need_node[@]} -eq 0 ]; then
  browser_deps
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi
missing+=("${need_node[@]}")

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
browser_deps
echo "setup: done"
