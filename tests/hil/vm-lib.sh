# vm-lib.sh: the pieces of the HIL virtual machine, sourced by run-vm.sh and hil-tests.sh.
# hil_prepare: make sure qemu, busybox-static, Debian's kernel, udevd and the initramfs are there.
# hil_boot GUEST_SCRIPT TIMEOUT CONSOLE_LOG QUIET: boot, run the guest script, power off.
# HIL_QEMU_EXTRA (an array, optional): more qemu arguments for hil_boot (power-cut.sh adds a disk
# and a -pidfile through which it kills the VM).
# shellcheck shell=bash

HIL_CACHE=${EMBOSS_HIL_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/emboss-hil}
HIL_LIB_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

hil_log() { echo "hil: $*" >&2; }

# Installs Debian packages when a tool is missing; fails (77) when that cannot be done.
hil_apt_install() {
  if [ "$(id -u)" != 0 ]; then
    hil_log "need $* but not root, so cannot install it (apt-get install $*)"
    return 77
  fi
  hil_log "installing $* with apt-get"
  if ! DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null 2>&1; then
    apt-get update -qq >/dev/null 2>&1
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null 2>&1 || {
      hil_log "apt-get install $* failed"
      return 77
    }
  fi
}

hil_busybox() {
  # The initramfs needs a static busybox (busybox-static provides /bin/busybox).
  local b
  for b in /bin/busybox /usr/bin/busybox; do
    if [ -x "$b" ] && ! ldd "$b" >/dev/null 2>&1; then echo "$b"; return 0; fi
  done
  return 1
}

hil_ensure_tools() {
  local missing=()
  command -v qemu-system-x86_64 >/dev/null || missing+=(qemu-system-x86)
  hil_busybox >/dev/null || missing+=(busybox-static)
  command -v apt-get >/dev/null || { [ ${#missing[@]} -eq 0 ] || { hil_log "no apt-get to install ${missing[*]}"; return 77; }; }
  if [ ${#missing[@]} -gt 0 ]; then hil_apt_install "${missing[@]}" || return 77; fi
  command -v qemu-system-x86_64 >/dev/null && hil_busybox >/dev/null || { hil_log "qemu or busybox-static still missing"; return 77; }
}

# The Debian kernel package linux-image-amd64 points at, downloaded once, unpacked and depmod'ed.
hil_ensure_kernel() {
  mkdir -p "$HIL_CACHE" || return 77
  if [ -z "${EMBOSS_HIL_REFRESH:-}" ] && [ -e "$HIL_CACHE/current-kernel/ready" ]; then
    HIL_KDIR=$(readlink -f "$HIL_CACHE/current-kernel")
    HIL_KVER=$(cat "$HIL_KDIR/ready")
    return 0
  fi
  local pkg
  pkg=$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')
  if [ -z "$pkg" ]; then
    [ "$(id -u)" = 0 ] && apt-get update -qq >/dev/null 2>&1
    pkg=$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')
  fi
  if [ -z "$pkg" ]; then
    if [ -e "$HIL_CACHE/current-kernel/ready" ]; then
      HIL_KDIR=$(readlink -f "$HIL_CACHE/current-kernel"); HIL_KVER=$(cat "$HIL_KDIR/ready"); return 0
    fi
    hil_log "apt cannot tell which kernel linux-image-amd64 is (no apt lists?)"
    return 77
  fi
  local kver=${pkg#linux-image-}
  local kdir="$HIL_CACHE/kernel-$kver-kms"  # -kms: the DRM core and the small display drivers are kept
  if [ ! -e "$kdir/ready" ]; then
    hil_log "fetching $pkg"
    local tmp; tmp=$(mktemp -d "$HIL_CACHE/dl.XXXXXX")
    (cd "$tmp" && apt-get download "$pkg" >/dev/null 2>&1) || { rm -rf "$tmp"; hil_log "apt-get download $pkg failed"; return 77; }
    local part="$kdir.part.$$"
    rm -rf "$part" && mkdir -p "$part"
    dpkg -x "$tmp"/*.deb "$part" || { rm -rf "$tmp" "$part"; return 77; }
    rm -rf "$tmp"
    # Modules a test never needs: sound, the big GPU drivers (the DRM core and bochs stay, for the
    # kms test), wireless, storage controllers (saves ~250 MB).
    local m="$part/lib/modules/$kver/kernel" g="$part/lib/modules/$kver/kernel/drivers/gpu/drm"
    rm -rf "$m/sound" "$g/amd" "$g/i915" "$g/nouveau" "$g/radeon" "$g/vmwgfx" "$g/gma500" "$g/xen" "$g/hyperv" "$m/drivers/net/wireless" "$m/drivers/infiniband" "$m/drivers/scsi" \
      "$m/drivers/staging" "$m/net/wireless" "$m/net/mac80211" "$m/drivers/net/ethernet" "$m/drivers/isdn" \
      "$m/drivers/md" "$m/fs/xfs" "$m/fs/btrfs" "$m/fs/ocfs2" "$m/fs/ceph" "$m/fs/nfs" "$m/fs/nfsd" "$m/fs/f2fs" \
      "$m/fs/gfs2" "$m/fs/cifs" "$m/fs/smb" "$m/drivers/media/dvb-frontends" "$m/drivers/media/tuners" \
      "$m/drivers/media/pci" "$m/drivers/bluetooth" "$m/net/bluetooth" "$m/drivers/iio" "$m/drivers/net/can" \
      "$m/drivers/hwmon" "$m/drivers/mtd" "$m/drivers/target" "$m/drivers/nvme" "$m/drivers/ata" 2>/dev/null
    if command -v depmod >/dev/null; then
      depmod -b "$part" "$kver" || { rm -rf "$part"; return 77; }
    else
      "$(hil_busybox)" depmod -b "$part" "$kver" || { rm -rf "$part"; return 77; }
    fi
    echo "$kver" > "$part/ready"
    if [ -e "$kdir/ready" ]; then rm -rf "$part"; else rm -rf "$kdir" && mv "$part" "$kdir"; fi
  fi
  ln -sfn "kernel-$kver-kms" "$HIL_CACHE/current-kernel"
  HIL_KDIR=$(readlink -f "$HIL_CACHE/current-kernel")
  HIL_KVER=$kver
}

# systemd-udevd from Debian's udev package of the same version as this machine's systemd (it uses
# the machine's libsystemd-shared). Unpacked into the cache, not installed. Optional: without it the
# tests that need udev events (libusb hotplug) are skipped.
hil_ensure_udevd() {
  HIL_UDEVD=""
  local b
  for b in /bin/udevadm /usr/bin/udevadm; do
    [ -x "$b" ] && { HIL_UDEVD=$b; return 0; }
  done
  local ver
  ver=$(dpkg-query -W -f='${Version}' systemd 2>/dev/null) || return 0
  [ -n "$ver" ] || return 0
  local dir="$HIL_CACHE/udev-$ver"
  if [ ! -e "$dir/ready" ]; then
    local tmp; tmp=$(mktemp -d "$HIL_CACHE/dl.XXXXXX")
    if (cd "$tmp" && apt-get download "udev=$ver" >/dev/null 2>&1) && dpkg -x "$tmp"/udev_*.deb "$dir"; then
      touch "$dir/ready"
    else
      hil_log "cannot fetch udev $ver: tests needing udevd will be skipped"
    fi
    rm -rf "$tmp"
  fi
  # /lib/systemd/systemd-udevd is a symlink to /bin/udevadm, which acts as udevd when called by that
  # name: the guest links it under that name (the host's /bin/udevadm may not exist).
  for b in bin/udevadm usr/bin/udevadm; do
    [ -x "$dir/$b" ] && HIL_UDEVD="$dir/$b"
  done
  return 0
}

# The modules a name needs, dependencies first (from modules.dep).
hil_moddeps() {
  local dep="$HIL_KDIR/lib/modules/$HIL_KVER/modules.dep" name
  for name in "$@"; do
    awk -v want="$name" -F': *' '
      function base(p) { sub(/.*\//, "", p); sub(/\.ko.*$/, "", p); gsub(/-/, "_", p); return p }
      { m = base($1); deps[m] = $2; path[m] = $1 }
      END {
        w = want; gsub(/-/, "_", w)
        visit(w)
      }
      function visit(m,   n, i, parts) {
        if (m in seen) return; seen[m] = 1
        n = split(deps[m], parts, " ")
        for (i = n; i >= 1; i--) visit(base(parts[i]))
        if (m in path) print path[m]
      }' "$dep"
  done | awk '!seen[$0]++'
}

hil_ensure_initramfs() {
  local init="$HIL_LIB_DIR/guest-init.sh"
  local key
  key=$( { cat "$init"; echo "$HIL_KVER"; } | sha1sum | cut -c1-12)
  HIL_INITRD="$HIL_CACHE/initramfs-$HIL_KVER-$key.cpio.gz"
  [ -s "$HIL_INITRD" ] && return 0
  local root; root=$(mktemp -d)
  mkdir -p "$root"/{bin,sbin,proc,sys,dev,host,tmp,lib/boot-modules,lib/modules,etc}
  cp "$(hil_busybox)" "$root/bin/busybox"
  cp "$init" "$root/init" && chmod +x "$root/init"
  local f order=()
  while read -r f; do
    cp "$HIL_KDIR/lib/modules/$HIL_KVER/$f" "$root/lib/boot-modules/"
    order+=("$(basename "$f")")
  done < <(hil_moddeps virtio_pci 9p 9pnet_virtio)
  printf '%s\n' "${order[@]}" > "$root/etc/boot-modules"
  (cd "$root" && find . | "$(hil_busybox)" cpio -o -H newc 2>/dev/null | gzip -1) > "$HIL_INITRD.part.$$" &&
    mv "$HIL_INITRD.part.$$" "$HIL_INITRD"
  # Older ones (another guest-init.sh or kernel) are of no use any more.
  find "$HIL_CACHE" -maxdepth 1 -name 'initramfs-*.cpio.gz' ! -newer "$HIL_INITRD" ! -name "$(basename "$HIL_INITRD")" -delete 2>/dev/null
  rm -rf "$root"
  [ -s "$HIL_INITRD" ] || { hil_log "cannot build the initramfs"; return 77; }
}

hil_prepare() {
  hil_ensure_tools || return 77
  hil_ensure_kernel || return 77
  hil_ensure_udevd
  hil_ensure_initramfs || return 77
}

hil_accel() {
  # KVM only when asked: on the machines this was written on /dev/kvm exists but a guest cannot run
  # under it (nested virtualisation without the CPU features qemu needs), so software emulation is the default.
  case "${EMBOSS_HIL_ACCEL:-tcg}" in kvm) echo kvm ;; *) echo tcg ;; esac
}

# hil_boot GUEST_SCRIPT TIMEOUT CONSOLE_LOG QUIET
hil_boot() {
  local script=$1 timeout_s=$2 console=$3 quiet=$4
  local jobs="$HIL_CACHE/jobs"
  mkdir -p "$jobs"
  local job; job=$(mktemp -d "$jobs/job.XXXXXX")
  {
    echo "HIL_CWD=$(printf %q "$PWD")"
    echo "HIL_UDEVD=$(printf %q "${HIL_UDEVD:-}")"
    echo "HIL_KDIR=$(printf %q "$HIL_KDIR")"
    cat "$script"
  } > "$job/job.sh"
  local accel cpu
  accel=$(hil_accel)
  case "$accel" in kvm*) cpu=host ;; *) cpu=max ;; esac
  local mem=${EMBOSS_HIL_MEM:-1536}
  local -a qemu=(qemu-system-x86_64 -nodefaults -no-user-config -display none -monitor none -no-reboot
    -machine q35 -cpu "$cpu" -smp "${EMBOSS_HIL_SMP:-2}" -m "$mem"
    -kernel "$HIL_KDIR/boot/vmlinuz-$HIL_KVER" -initrd "$HIL_INITRD"
    -append "console=ttyS0 quiet loglevel=3 panic=-1 hil.job=$job/job.sh hil.modules=$HIL_KDIR/lib/modules"
    -virtfs "local,path=/,mount_tag=host,security_model=none,readonly=on,multidevs=remap"
    -serial stdio
    -device bochs-display)  # a display for the kms test (bochs DRM driver); idle unless its module is loaded
  if [ "$accel" = tcg ]; then qemu+=(-accel tcg,thread=multi,tb-size=256); else qemu+=(-accel kvm); fi
  qemu+=(${HIL_QEMU_EXTRA[@]+"${HIL_QEMU_EXTRA[@]}"})
  local t0=$SECONDS rc
  # tr unbuffered: the log follows the console as it comes (power-cut.sh reads it while the VM runs).
  if [ "$quiet" = 1 ]; then
    timeout -k 5 "$timeout_s" "${qemu[@]}" < /dev/null 2>&1 | stdbuf -o0 tr -d '\r' > "$console"
  else
    timeout -k 5 "$timeout_s" "${qemu[@]}" < /dev/null 2>&1 | stdbuf -o0 tr -d '\r' | tee "$console"
  fi
  rc=${PIPESTATUS[0]}
  rm -rf "$job"
  HIL_BOOT_SECONDS=$((SECONDS - t0))
  [ "$rc" = 124 ] || [ "$rc" = 137 ] && return 124
  grep -qa '^EMBOSS-HIL-DONE' "$console" && return 0
  return 125
}
