#!/usr/bin/env bash
# Builds DSO (Engel et al., Direct Sparse Odometry; GPL-3.0) as a peer for the VO study, outside
# this tree: DSO is never vendored, copied into or linked with bolo; only its dso_dataset binary is
# run on the study's frames (scripts/study/dso-run.sh). Prints the binary's path on stdout.
#
#   scripts/study/dso-build.sh [SOURCE]
#
# SOURCE: a git repository of DSO (a URL or a local clone; checked out at DSO_COMMIT) or a plain
# source tree (copied as it is); default the public repository. Everything goes to BOLO_DSO_DIR
# (default ~/.cache/bolo-dso): src/ (the checkout, with scripts/study/dso-build.patch applied: builds
# with today's compilers and Boost, dso_dataset without Pangolin, `allposes=1` to log every frame's
# pose), build/ (build/bin/dso_dataset). A finished build is reused. Installs the Debian packages it
# needs when run as root (else names them). JOBS (1) parallel compile jobs; it takes ~15 min at one.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
source_spec=${1:-https://github.com/JakobEngel/dso.git}
DSO_COMMIT=${DSO_COMMIT:-7b0c99f01d238f801c625beaff90240bcb007198}  # master of 2021-03-08
dir=${BOLO_DSO_DIR:-$HOME/.cache/bolo-dso}
patch_file="$here/dso-build.patch"
binary="$dir/build/bin/dso_dataset"
case "$(realpath -m "$dir")/" in
  "$(cd "$here/../.." && pwd)"/*) echo "dso-build: BOLO_DSO_DIR=$dir is inside the bolo tree; DSO stays outside it" >&2; exit 2 ;;
esac

packages=(cmake g++ make patch git libsuitesparse-dev libeigen3-dev libboost-system-dev libboost-thread-dev
          libopencv-dev libzip-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "dso-build: missing Debian packages; run: sudo apt-get install --no-install-recommends ${missing[*]}" >&2
    exit 2
  fi
  echo "dso-build: installing ${missing[*]}" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

mkdir -p "$dir"
if [ ! -f "$dir/src/CMakeLists.txt" ]; then
  rm -rf "$dir/src"
  if [ -d "$source_spec" ] && ! git -C "$source_spec" rev-parse --git-dir > /dev/null 2>&1; then
    echo "dso-build: copying the source tree $source_spec (not a git repository: DSO_COMMIT not checked)" >&2
    cp -a "$source_spec" "$dir/src"
  else
    echo "dso-build: cloning $source_spec at $DSO_COMMIT" >&2
    git clone -q "$source_spec" "$dir/src" >&2
    git -C "$dir/src" -c advice.detachedHead=false checkout -q "$DSO_COMMIT" >&2
  fi
  [ -f "$dir/src/src/FullSystem/FullSystem.cpp" ] || { echo "dso-build: $source_spec is not DSO's source" >&2; exit 2; }
fi
if patch -d "$dir/src" -p1 -R --dry-run -s -f < "$patch_file" > /dev/null 2>&1; then
  echo "dso-build: $patch_file already applied" >&2
else
  patch -d "$dir/src" -p1 -s -f < "$patch_file" >&2 || { echo "dso-build: $patch_file does not apply to $dir/src" >&2; exit 2; }
fi

cmake -S "$dir/src" -B "$dir/build" -DCMAKE_BUILD_TYPE=Release > "$dir/cmake.log" 2>&1 ||
  { echo "dso-build: cmake failed, see $dir/cmake.log" >&2; exit 1; }
make -C "$dir/build" -j"${JOBS:-1}" dso_dataset > "$dir/make.log" 2>&1 ||
  { echo "dso-build: build failed, see $dir/make.log" >&2; exit 1; }
[ -x "$binary" ] || { echo "dso-build: $binary missing after the build, see $dir/make.log" >&2; exit 1; }
echo "$binary"
