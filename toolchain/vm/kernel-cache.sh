# Sourced by hil-vm.sh: Debian's kernel, busybox and runtime libraries for the VM, fetched with
# `apt-get download` and unpacked into the cache (never installed into the system).

hil_triplet() {
  case "$1" in
    x86_64) echo x86_64-linux-gnu ;;
    aarch64) echo aarch64-linux-gnu ;;
  esac
}

hil_debarch() {
  case "$1" in
    x86_64) echo amd64 ;;
    aarch64) echo arm64 ;;
  esac
}

# Downloads PACKAGE (with :arch qualifier when foreign) into $cache/deb and unpacks it into DEST.
hil_fetch_deb() {
  local package="$1" dest="$2" cache="$3"
  mkdir -p "$cache/deb" "$dest"
  local name="${package%%:*}"
  local deb
  deb="$(ls "$cache/deb/${name}_"*.deb 2>/dev/null | head -1 || true)"
  if [ -z "$deb" ]; then
    echo "hil-vm: downloading $package" >&2
    (cd "$cache/deb" && apt-get download -qq "$package" 2>&1 | grep -v 'unsandboxed' >&2) || true
    deb="$(ls "$cache/deb/${name}_"*.deb 2>/dev/null | head -1 || true)"
    [ -n "$deb" ] || { echo "hil-vm: apt-get download $package failed" >&2; return 1; }
  fi
  dpkg-deb -x "$deb" "$dest"
}

# Prints the name of Debian's current kernel package for ARCH (linux-image-<version>-<flavour>).
# apt-cache takes seconds per call without a binary package cache, and every HIL test asks several
# times: the answer is kept in the cache until apt's package lists change.
hil_kernel_package() {
  local arch="$1" cache="$2" debarch meta image memo
  memo="$cache/$arch/kernel-package"
  if [ -s "$memo" ] && [ -z "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -newer "$memo" -print -quit 2>/dev/null)" ]; then
    cat "$memo"
    return
  fi
  debarch="$(hil_debarch "$arch")"
  meta="linux-image-$debarch"
  [ "$arch" = x86_64 ] || meta="$meta:$debarch"
  image="$(apt-cache depends "$meta" 2>/dev/null | awk '/Depends: linux-image-/ { print $2; exit }')"
  image="${image%%:*}"
  [ -n "$image" ] || { echo "hil-vm: apt-cache knows no $meta (for arm64: dpkg --add-architecture arm64; apt-get update)" >&2; return 1; }
  mkdir -p "$cache/$arch"
  echo "$image" >"$memo.$$" && mv "$memo.$$" "$memo"
  echo "$image"
}

# Prints the folder holding boot/vmlinuz, lib/modules/<version> (with modules.dep) and a version
# file for ARCH; Debian's current 6.1 kernel for that architecture.
hil_kernel_dir() {
  local arch="$1" cache="$2" debarch image dir
  debarch="$(hil_debarch "$arch")"
  image="$(hil_kernel_package "$arch" "$cache")" || return 1
  dir="$cache/$arch/$image"
  if [ ! -f "$dir/version" ]; then
    rm -rf "$dir"
    local qualified="$image"
    [ "$arch" = x86_64 ] || qualified="$image:$debarch"
    hil_fetch_deb "$qualified" "$dir" "$cache" || return 1
    local kver
    kver="$(ls "$dir/lib/modules" | head -1)"
    depmod -b "$dir" "$kver"
    ln -sf "vmlinuz-$kver" "$dir/boot/vmlinuz"
    echo "$kver" >"$dir/version"
  fi
  echo "$dir"
}

hil_busybox() {
  local arch="$1" cache="$2"
  if [ "$arch" = x86_64 ]; then
    command -v busybox >/dev/null && file_is_static /bin/busybox && { echo /bin/busybox; return; }
  fi
  local dir="$cache/$arch/busybox"
  [ -x "$dir/bin/busybox" ] || hil_fetch_deb "busybox-static:$(hil_debarch "$arch")" "$dir" "$cache" >&2
  echo "$dir/bin/busybox"
}

file_is_static() {
  ! readelf -l "$1" 2>/dev/null | grep -q 'program interpreter'
}

# Copies every shared library the ELF files among FILES need (recursively) into ROOT/lib, and
# their program interpreter to the path it is requested at. SYSROOT (may be empty) holds
# extracted foreign-architecture packages.
hil_copy_libraries() {
  local arch="$1" root="$2" sysroot="$3"
  shift 3
  local triplet dirs=() queue=() done_libs=" " f
  triplet="$(hil_triplet "$arch")"
  if [ "$arch" = x86_64 ]; then
    dirs=("/lib/$triplet" "/usr/lib/$triplet")
  else
    dirs=("/usr/$triplet/lib")
  fi
  [ -n "$sysroot" ] && dirs=("$sysroot/lib/$triplet" "$sysroot/usr/lib/$triplet" "${dirs[@]}")
  for f in "$@"; do
    [ -f "$f" ] && readelf -h "$f" >/dev/null 2>&1 && queue+=("$f")
  done
  while [ ${#queue[@]} -gt 0 ]; do
    f="${queue[0]}"
    queue=("${queue[@]:1}")
    local interp
    interp="$(readelf -l "$f" 2>/dev/null | sed -n 's/.*Requesting program interpreter: \(.*\)]/\1/p')"
    if [ -n "$interp" ] && [ ! -e "$root$interp" ]; then
      local src=""
      for d in "${dirs[@]}"; do [ -e "$d/$(basename "$interp")" ] && { src="$d/$(basename "$interp")"; break; }; done
      [ -n "$src" ] || { echo "hil-vm: no interpreter $interp" >&2; return 1; }
      mkdir -p "$root$(dirname "$interp")"
      cp -L "$src" "$root$interp"
    fi
    local lib
    for lib in $(readelf -d "$f" 2>/dev/null | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
      case "$done_libs" in *" $lib "*) continue ;; esac
      done_libs="$done_libs$lib "
      local found=""
      for d in "${dirs[@]}"; do [ -e "$d/$lib" ] && { found="$d/$lib"; break; }; done
      [ -n "$found" ] || { echo "hil-vm: $f needs $lib, not found in ${dirs[*]}" >&2; return 1; }
      cp -L "$found" "$root/lib/$lib"
      queue+=("$found")
    done
  done
}

# For out-of-tree modules of the VM's kernel (gpio-sim.sh, uvc-gadget.sh, v4l2loopback.sh): sets HIL_MAKE_ARGS to
# what kbuild needs for ARCH (for aarch64 a cross build: the arm64 headers with the host's amd64
# kbuild tools and Debian's aarch64-linux-gnu-gcc, the GCC 12 the kernel was built with).
hil_module_make_args() {
  case "$1" in
    x86_64) HIL_MAKE_ARGS=() ;;
    aarch64)
      command -v aarch64-linux-gnu-gcc >/dev/null ||
        { echo "hil-vm: no aarch64-linux-gnu-gcc (scripts/deps.sh installs the cross compilers)" >&2; return 2; }
      HIL_MAKE_ARGS=(ARCH=arm64 CROSS_COMPILE=aarch64-linux-gnu-) ;;
    *) echo "hil-vm: unknown architecture '$1' (x86_64 or aarch64)" >&2; return 2 ;;
  esac
}

# The common start of an out-of-tree module script (gpio-sim.sh, uvc-gadget.sh, v4l2loopback.sh)
# for ARCH: sets cache (BOLO_HIL_CACHE), HIL_MAKE_ARGS, kver (the VM kernel's version), out
# ($cache/ARCH/NAME, the module's folder), stamp (kver, then EXTRA if given: what a cached
# module must have been built for) and series (6.1). Called as a plain command, so that set -e stops on its errors.
hil_module_start() {
  local arch="$1" name="$2" extra="${3:-}"
  cache="${BOLO_HIL_CACHE:-$HOME/.cache/bolo-hil}"
  hil_module_make_args "$arch" || exit 2
  local kernel_dir
  kernel_dir="$(hil_kernel_dir "$arch" "$cache")"
  kver="$(cat "$kernel_dir/version")"  # e.g. 6.1.0-56-amd64
  out="$cache/$arch/$name"
  stamp="$kver${extra:+ $extra}"
  series="${kver%%.*}.$(echo "$kver" | cut -d. -f2)"  # 6.1
  module_arch="$arch"
  module_root="$cache/$arch/kbuild-$name-$kver"
}

# After hil_module_start, for a module that is not cached: empties out, unpacks the kbuild tree
# into module_root (the script removes it when done: ~300 MB) and sets headers to build against.
hil_module_kbuild() {
  rm -rf "$module_root" "$out"
  mkdir -p "$module_root" "$out"
  headers="$(hil_kbuild_tree "$module_arch" "$cache" "$kver" "$module_root")"
}

# Prints out/MODULE and succeeds when it is cached with hil_module_start's stamp in out/STAMP_FILE.
hil_module_cached() {
  [ -f "$out/$1" ] && [ "$(cat "$out/$2" 2>/dev/null)" = "$stamp" ] && echo "$out/$1"
}

# Prints a folder holding the kernel sources the out-of-tree modules build from (drivers/gpio,
# drivers/usb/gadget, kernel/irq/irq_sim.c of Debian's linux-source-SERIES), extracted once per
# series and shared by every architecture and module script: decompressing the 140 MB tarball is
# most of a module's build time.
hil_kernel_sources() {
  local cache="$1" series="$2"
  local dir="$cache/linux-source-$series"
  if [ ! -f "$dir/.complete" ]; then
    local tmp
    tmp="$(mktemp -d "$cache/.linux-source-XXXXXX")"
    hil_fetch_deb "linux-source-$series" "$tmp/deb" "$cache" >&2 || { rm -rf "$tmp"; return 1; }
    tar -xJf "$tmp/deb/usr/src/linux-source-$series.tar.xz" -C "$tmp" --strip-components=1 --wildcards \
      "linux-source-$series/drivers/gpio/*" "linux-source-$series/drivers/usb/gadget/*" \
      "linux-source-$series/kernel/irq/irq_sim.c" || { rm -rf "$tmp"; return 1; }
    rm -rf "$tmp/deb"
    touch "$tmp/.complete"
    # Another build may have finished first: its folder stands, ours goes.
    mv -T "$tmp" "$dir" 2>/dev/null || rm -rf "$tmp"
  fi
  echo "$dir"
}

# Unpacks the kbuild tree for kernel KVER of ARCH into ROOT (the flavour's headers, the common
# headers, the host's linux-kbuild, fetched with apt-get download, nothing installed) and prints
# the headers folder to build against.
hil_kbuild_tree() {
  local arch="$1" cache="$2" kver="$3" root="$4"
  local flavour="${kver##*-}"                                # amd64
  local abi="${kver%-"$flavour"}"                            # 6.1.0-56
  local series="${kver%%.*}.$(echo "$kver" | cut -d. -f2)"   # 6.1
  local flavour_headers="linux-headers-$kver" p
  [ "$arch" = x86_64 ] || flavour_headers="$flavour_headers:$(hil_debarch "$arch")"
  for p in "$flavour_headers" "linux-headers-$abi-common" "linux-kbuild-$series"; do
    hil_fetch_deb "$p" "$root" "$cache" >&2 || return 1
  done
  local headers="$root/usr/src/linux-headers-$kver"
  # The flavour's Makefile includes the common tree by absolute path.
  sed -i "s|^include /usr/src/|include $root/usr/src/|" "$headers/Makefile"
  echo "$headers"
}
