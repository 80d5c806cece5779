#!/bin/bash
# build-image.sh: the kiosk appliance's disk image, from Debian 12's packages and the emboss .deb only.
#
#   platform/image/build-image.sh [--arch amd64|arm64] [--deb FILE | --build-dir DIR] [-o OUT_DIR]
#
#   --deb FILE        the emboss package to install (default: made by platform/debian/make-deb.sh)
#   --build-dir DIR   the build tree make-deb.sh uses for it (its own Release build; default its build-deb)
#   --arch A          amd64 (a PC kiosk; default) or arm64 (Raspberry Pi 4/5, built through qemu-user)
#   -o OUT_DIR        where emboss-ARCH.img (and .bmap) go (default: OUT_DIR=out/image)
#   --data-size SIZE  the sessions partition (default 512M; e.g. 2G)
#   --base-only       build (or find) the cached base root file system and stop
# Prints the image's path on the last line of standard output. Exit codes: 0 ok, 1 failure, 2 bad usage,
# 77 this machine cannot build it (not root and the tools missing, no apt mirror).
#
# Two steps, each cached under ${EMBOSS_IMAGE_CACHE:-${XDG_CACHE_HOME:-~/.cache}/emboss-image}:
#   base   mmdebstrap: Debian 12 with the kernel, systemd, udev, Mesa and every package the .deb depends
#          on, as a tar; keyed by a hash of the package list, the mirror and the base step's code;
#   image  the base unpacked, the .deb installed with dpkg, platform/image/overlay/ copied in, units
#          enabled and masked, then the partitions made without mounting anything (mkfs.ext4 -d,
#          mtools) and put into one GPT disk image; keyed by the .deb's hash, the base's key and this
#          script with its overlay. A rerun with nothing changed copies the cached image out.
#
# The disk: 1 EFI system partition (FAT32: systemd-boot, the kernel, the initrd, the boot entry),
# 2 root (ext4, mounted read-only), 3 emboss-data (ext4, /var/lib/emboss-kiosk: the sessions).
# See platform/image/README.md.
set -u -o pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
src=$(cd "$here/../.." && pwd)
arch=amd64
deb=""
build_dir=""
out_dir=out/image
data_size=512M
base_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --arch) arch=$2; shift 2 ;;
    --deb) deb=$2; shift 2 ;;
    --build-dir) build_dir=$2; shift 2 ;;
    -o) out_dir=$2; shift 2 ;;
    --data-size) data_size=$2; shift 2 ;;
    --base-only) base_only=1; shift ;;
    -h|--help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "build-image.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
case "$arch" in amd64|arm64) ;; *) echo "build-image.sh: --arch amd64 or arm64, not $arch" >&2; exit 2 ;; esac

log() { echo "build-image: $*" >&2; }
die() { log "$*"; exit 1; }
cache=${EMBOSS_IMAGE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/emboss-image}
mkdir -p "$cache" || exit 77
t_start=$SECONDS

# ---- tools: installed with apt-get when missing (root only), else exit 77
need=()
command -v mmdebstrap >/dev/null || need+=(mmdebstrap)
command -v mkfs.ext4 >/dev/null || need+=(e2fsprogs)
command -v mcopy >/dev/null || need+=(mtools)
command -v mkfs.vfat >/dev/null || need+=(dosfstools)
command -v sfdisk >/dev/null || need+=(fdisk)
command -v bmaptool >/dev/null || need+=(bmap-tools)
if [ "$arch" != "$(dpkg --print-architecture)" ]; then
  command -v qemu-aarch64-static >/dev/null || need+=(qemu-user-static)
  command -v update-binfmts >/dev/null || need+=(binfmt-support)
  command -v arch-test >/dev/null || need+=(arch-test)  # mmdebstrap checks the foreign architecture runs
fi
if [ ${#need[@]} -gt 0 ]; then
  [ "$(id -u)" = 0 ] || { log "need ${need[*]} (apt-get install ${need[*]}); not root, so cannot install them"; exit 77; }
  log "installing ${need[*]} with apt-get"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null 2>&1 ||
    { apt-get update -qq >/dev/null 2>&1; DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null 2>&1; } ||
    { log "apt-get install ${need[*]} failed"; exit 77; }
fi
# Unpacking the base with its owners, dpkg in a chroot, device nodes: root (or a root user namespace).
[ "$(id -u)" = 0 ] || { log "run as root: the root file system is unpacked with its owners and the .deb installed in a chroot"; exit 77; }
if [ "$arch" = arm64 ] && [ "$(dpkg --print-architecture)" != arm64 ]; then
  # A foreign architecture runs through qemu-user: binfmt_misc must know qemu-aarch64 (binfmt-support).
  [ -e /proc/sys/fs/binfmt_misc/status ] || mount -t binfmt_misc binfmt_misc /proc/sys/fs/binfmt_misc 2>/dev/null
  [ -e /proc/sys/fs/binfmt_misc/qemu-aarch64 ] || update-binfmts --enable qemu-aarch64 >/dev/null 2>&1
  [ -e /proc/sys/fs/binfmt_misc/qemu-aarch64 ] || { log "binfmt_misc has no qemu-aarch64: cannot run arm64 programs here"; exit 77; }
fi

# ---- the mirror: the one apt on this machine uses for Debian (deb.debian.org unless told)
mirror=${EMBOSS_IMAGE_MIRROR:-}
if [ -z "$mirror" ]; then
  mirror=$(grep -rhv '^[[:space:]]*#' /etc/apt/sources.list /etc/apt/sources.list.d/ 2>/dev/null | grep -oE '(https?://[^ ]*/debian)/?( |$)' | awk '{print $1}' | sed 's:/$::' | grep -v -- '-security' | head -1)
  mirror=${mirror:-http://deb.debian.org/debian}
fi
security=${EMBOSS_IMAGE_SECURITY_MIRROR:-${mirror%/debian}/debian-security}
suite=bookworm

# ---- the .deb (the project's own package; nothing else that is not Debian's goes in)
if [ "$base_only" = 0 ] && [ -z "$deb" ]; then
  [ -x "$src/platform/debian/make-deb.sh" ] || [ -f "$src/platform/debian/make-deb.sh" ] ||
    die "no --deb given and no platform/debian/make-deb.sh to make one"
  log "making the .deb with platform/debian/make-deb.sh ${build_dir}"
  deb=$(bash "$src/platform/debian/make-deb.sh" ${build_dir:+"$build_dir"} | tail -1) || die "make-deb.sh failed"
fi
if [ -n "$deb" ]; then
  [ -f "$deb" ] || die "no such .deb: $deb"
  deb=$(readlink -f "$deb")
  deb_arch=$(dpkg-deb -f "$deb" Architecture)
  [ "$deb_arch" = "$arch" ] || [ "$deb_arch" = all ] || die "$deb is for $deb_arch, the image for $arch"
fi

# ---- the base: Debian's packages only
# What the appliance needs besides the kiosk: the kernel, systemd as init, udev, Mesa (EGL/GBM on
# the KMS display, llvmpipe where there is no GPU driver), the clock over the network, fsck.
packages=(systemd-sysv udev kmod e2fsprogs dosfstools initramfs-tools zstd
  systemd-timesyncd systemd-resolved libnss-resolve
  libgl1-mesa-dri libegl1 libegl-mesa0 libgbm1 libgles2)
# What the .deb depends on (its Depends: as CPack's shlibdeps writes them, and the font of the
# overlay), so that installing it needs no network. Listed here, and the .deb's own Depends added
# (the first of each alternative): a dependency already listed leaves the base's key, and so the
# cached base, as it is; a new one makes a new base.
packages+=(libc6 libgcc-s1 libstdc++6 libdrm2 libosmesa6 libx11-6 libevdev2 libudev1 libsystemd0
  libgpiod2 libhidapi-hidraw0 libusb-1.0-0 libpng16-16 libjpeg62-turbo libfreetype6 fonts-dejavu-core
  libsqlite3-0 zlib1g lib3mf1 libmeshoptimizer2d)
if [ -n "$deb" ]; then
  mapfile -t -O "${#packages[@]}" packages < <(dpkg-deb -f "$deb" Depends | tr ',' '\n' |
    sed 's/|.*//; s/(.*)//; s/:any//; s/[[:space:]]//g' | grep -v '^$')
fi
# Debian's components: main only, and for the Pi non-free-firmware too (raspi-firmware, the Pi's boot
# firmware, is there, as in Debian's own raspi image-specs).
components=main
case "$arch" in
  amd64) packages+=(linux-image-amd64 systemd-boot-efi) ;;
  arm64) packages+=(linux-image-arm64 raspi-firmware); components="main non-free-firmware" ;;
esac
mapfile -t packages < <(printf '%s\n' "${packages[@]}" | sort -u)

build_base() {  # build_base OUT.tar: mmdebstrap into a tar; its text is part of the base's cache key
  mmdebstrap --variant=minbase --arch="$arch" --format=tar \
    --include="$(IFS=,; echo "${packages[*]}")" \
    --aptopt='APT::Install-Recommends "false"' --aptopt='Acquire::Languages "none"' \
    --dpkgopt='path-exclude=/usr/share/man/*' --dpkgopt='path-exclude=/usr/share/locale/*' \
    --dpkgopt='path-exclude=/usr/share/doc/*' --dpkgopt='path-include=/usr/share/doc/*/copyright' \
    --dpkgopt='path-exclude=/usr/share/info/*' \
    --essential-hook='mkdir -p "$1/etc/initramfs-tools/conf.d" && echo "COMPRESS=zstd" > "$1/etc/initramfs-tools/conf.d/compress"' \
    --customize-hook='rm -f "$1"/etc/ssh/ssh_host_* "$1/var/cache/apt/"*.bin; : > "$1/etc/machine-id"' \
    "$suite" "$1" \
    "deb $mirror $suite $components" "deb $mirror $suite-updates $components" "deb $security $suite-security $components"
}
base_key=$( { echo "$arch $suite $mirror $security $components"; printf '%s\n' "${packages[@]}"; declare -f build_base; } | sha256sum | cut -c1-16)
base_tar="$cache/base-$arch-$base_key.tar"
if [ -s "$base_tar" ]; then
  log "base $base_key (cached): ${#packages[@]} packages asked for"
else
  log "building the base $base_key with mmdebstrap from $mirror (${#packages[@]} packages asked for; a few minutes)"
  t0=$SECONDS
  if ! build_base "$base_tar.part.$$" > "$cache/base-$arch-$base_key.log" 2>&1; then
    tail -20 "$cache/base-$arch-$base_key.log" >&2
    rm -f "$base_tar.part.$$"
    grep -q 'Failed to fetch\|Could not resolve\|Temporary failure' "$cache/base-$arch-$base_key.log" && { log "the mirror $mirror cannot be reached"; exit 77; }
    die "mmdebstrap failed (log: $cache/base-$arch-$base_key.log)"
  fi
  mv "$base_tar.part.$$" "$base_tar"
  # Older bases of this architecture are of no use any more.
  find "$cache" -maxdepth 1 -name "base-$arch-*" ! -name "$(basename "$base_tar" .tar).*" -delete
  log "base built in $((SECONDS - t0)) s: $(du -h "$base_tar" | cut -f1)"
fi
[ "$base_only" = 1 ] && { echo "$base_tar"; exit 0; }

# ---- the image: keyed by the .deb, the base and this step (the script and its overlay)
deb_hash=$(sha256sum "$deb" | cut -c1-16)
image_key=$( { echo "$base_key $deb_hash $data_size"; cat "$0"; (cd "$here/overlay" && find . -type f | sort | xargs sha256sum); } | sha256sum | cut -c1-16)
image_cached="$cache/image-$arch-$image_key.img"
mkdir -p "$out_dir" || exit 1
out_img="$(cd "$out_dir" && pwd)/emboss-$arch.img"
copy_out() {
  cp --sparse=always "$image_cached" "$out_img.part" && mv "$out_img.part" "$out_img" || die "cannot write $out_img"
  [ -f "$image_cached.bmap" ] && cp "$image_cached.bmap" "${out_img%.img}.bmap"
  [ -f "$image_cached.info" ] && cp "$image_cached.info" "${out_img%.img}.info"
}
if [ -s "$image_cached" ]; then
  copy_out
  log "image $image_key (cached) in $((SECONDS - t_start)) s"
  echo "$out_img"
  exit 0
fi

t0=$SECONDS
work=$(mktemp -d "$cache/work.XXXXXX")
trap 'rm -rf "$work"' EXIT
root="$work/root"
mkdir -p "$root"
tar -C "$root" --numeric-owner -xpf "$base_tar" || die "cannot unpack the base"

# The .deb, installed as apt would (its maintainer scripts run in the image: the user from
# sysusers.d, the unit enabled). Its dependencies are all in the base.
cp "$deb" "$root/tmp/emboss.deb"
mount -t proc proc "$root/proc" 2>/dev/null && proc_mounted=1 || proc_mounted=0
trap '[ "$proc_mounted" = 1 ] && umount "$root/proc"; rm -rf "$work"' EXIT
if ! chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive dpkg -i /tmp/emboss.deb > "$work/dpkg.log" 2>&1; then
  cat "$work/dpkg.log" >&2
  missing=$(sed -n 's/^ *Package \(.*\) is not installed\./\1/p' "$work/dpkg.log" | sort -u | tr '\n' ' ')
  [ -n "$missing" ] && die "the .deb depends on $missing, which the base lacks: add them to the package list in build-image.sh"
  die "installing the .deb in the image failed"
fi
rm -f "$root/tmp/emboss.deb"
[ -x "$root/usr/bin/emboss-kiosk" ] || die "the .deb has no /usr/bin/emboss-kiosk"
[ "$proc_mounted" = 1 ] && umount "$root/proc" && proc_mounted=0

# The appliance's configuration: fstab, journald, networkd, the USB stick for exports (overlay/).
cp -a "$here/overlay/." "$root/"
chown -R root:root "$root/etc/fstab" "$root/etc/systemd" "$root/etc/udev" 2>/dev/null
echo emboss-kiosk > "$root/etc/hostname"
printf '127.0.0.1\tlocalhost\n127.0.1.1\temboss-kiosk\n::1\tlocalhost ip6-localhost ip6-loopback\n' > "$root/etc/hosts"
# The machine id is made at every boot (the root is read-only; nothing here needs it to persist).
: > "$root/etc/machine-id"
rm -f "$root/var/lib/dbus/machine-id"
mkdir -p "$root/var/lib/emboss-kiosk" "$root/media/emboss-export"
ln -sf ../run/systemd/resolve/stub-resolv.conf "$root/etc/resolv.conf"
sysd() { systemctl --root="$root" --quiet "$@" 2>&1 | grep -v 'Created symlink\|Removed' >&2; }
sysd set-default multi-user.target
sysd enable emboss-kiosk.service systemd-timesyncd.service systemd-networkd.service systemd-resolved.service
# Nothing else on the kiosk's screen: no login prompt on tty1 (the unit conflicts with it as well),
# no automatic getty for other VTs the kernel's console might switch to.
sysd mask getty@tty1.service autovt@.service
# Nothing writes to the root file system: no apt timers (and no apt lists to update from).
sysd mask apt-daily.timer apt-daily-upgrade.timer apt-daily.service apt-daily-upgrade.service 2>/dev/null
# e2scrub needs LVM snapshots, which the image has not.
sysd mask e2scrub_all.timer e2scrub_reap.service 2>/dev/null
systemctl --root="$root" is-enabled emboss-kiosk.service >/dev/null || die "emboss-kiosk.service is not enabled in the image"

# ---- the partitions: fixed partition UUIDs (the kernel command line and fstab name them so)
# amd64: GPT. arm64: MBR, which the Raspberry Pi's boot ROM reads on every model.
case "$arch" in
  amd64)
    root_uuid=6a1f9a5e-2b55-4c1e-9d3a-0e6b0551a001
    data_uuid=6a1f9a5e-2b55-4c1e-9d3a-0e6b0551a002
    esp_uuid=6a1f9a5e-2b55-4c1e-9d3a-0e6b0551a003 ;;
  arm64)
    disk_id=0x6a1f9a5e
    root_uuid=6a1f9a5e-02
    data_uuid=6a1f9a5e-03 ;;
esac
cmdline="root=PARTUUID=$root_uuid ro rootwait quiet loglevel=3 systemd.show_status=false fsck.mode=auto fsck.repair=yes vt.global_cursor_default=0"
sed -i "s/@ROOT_PARTUUID@/$root_uuid/; s/@DATA_PARTUUID@/$data_uuid/" "$root/etc/fstab"

kver=$(ls "$root/lib/modules" | sort -V | tail -1)
[ -n "$kver" ] && [ -f "$root/boot/initrd.img-$kver" ] || die "the base has no kernel with an initrd"
mib() { echo $(( ($1 + 1048575) / 1048576 )); }
to_bytes() { numfmt --from=iec "$1"; }

esp_mib=256
case "$arch" in
  amd64)
    # systemd-boot from the EFI system partition (what a PC's firmware starts: EFI/BOOT/BOOTX64.EFI).
    # The kernel and the initrd are copied there; the image is replaced as a whole, never upgraded
    # in place, so nothing has to keep them in step with /boot.
    esp_dir="$work/esp"
    mkdir -p "$esp_dir/EFI/BOOT" "$esp_dir/EFI/systemd" "$esp_dir/loader/entries" "$esp_dir/emboss"
    cp "$root/usr/lib/systemd/boot/efi/systemd-bootx64.efi" "$esp_dir/EFI/BOOT/BOOTX64.EFI"
    cp "$root/usr/lib/systemd/boot/efi/systemd-bootx64.efi" "$esp_dir/EFI/systemd/systemd-bootx64.efi"
    cp "$root/boot/vmlinuz-$kver" "$esp_dir/emboss/vmlinuz"
    cp "$root/boot/initrd.img-$kver" "$esp_dir/emboss/initrd.img"
    printf 'default emboss.conf\ntimeout 0\neditor no\n' > "$esp_dir/loader/loader.conf"
    printf 'title emboss kiosk (Debian %s, %s)\nlinux /emboss/vmlinuz\ninitrd /emboss/initrd.img\noptions %s\n' \
      "$(cat "$root/etc/debian_version")" "$kver" "$cmdline" > "$esp_dir/loader/entries/emboss.conf"
    ;;
  arm64)
    # The Raspberry Pi's firmware reads the FAT partition: raspi-firmware's files, the kernel, the
    # initrd, the device trees, config.txt and cmdline.txt.
    esp_dir="$work/esp"
    mkdir -p "$esp_dir"
    cp -r "$root/usr/lib/raspi-firmware/." "$esp_dir/"
    find "$root/usr/lib/linux-image-$kver/broadcom" -name 'bcm27*-rpi-*.dtb' -exec cp {} "$esp_dir/" \; 2>/dev/null
    cp "$root/boot/vmlinuz-$kver" "$esp_dir/vmlinuz"
    cp "$root/boot/initrd.img-$kver" "$esp_dir/initrd.img"
    printf 'arm_64bit=1\nenable_uart=1\nupstream_kernel=1\nkernel=vmlinuz\ninitramfs initrd.img followkernel\ndisable_overscan=1\ndtoverlay=vc4-kms-v3d\n' > "$esp_dir/config.txt"
    echo "$cmdline console=tty1" > "$esp_dir/cmdline.txt"
    ;;
esac

# Root: the unpacked tree with 25% and 64 MiB to spare (mkfs.ext4 -d fills it without a mount).
root_used=$(du -sb --apparent-size "$root" | cut -f1)
root_mib=$(( $(mib "$root_used") * 5 / 4 + 64 ))
data_mib=$(mib "$(to_bytes "$data_size")")
mkfs.ext4 -q -F -L emboss-root -U clear -E root_owner=0:0 -d "$root" "$work/root.ext4" "${root_mib}M" > /dev/null || die "mkfs.ext4 of the root failed"
tune2fs -c 0 -i 0 "$work/root.ext4" >/dev/null
mkdir -p "$work/data"
mkfs.ext4 -q -F -L emboss-data -d "$work/data" "$work/data.ext4" "${data_mib}M" > /dev/null || die "mkfs.ext4 of the data partition failed"
mkfs.vfat -F 32 -n EMBOSS-BOOT -C "$work/esp.vfat" $((esp_mib * 1024)) >/dev/null || die "mkfs.vfat failed"
MTOOLS_SKIP_CHECK=1 mcopy -s -i "$work/esp.vfat" "$esp_dir"/* ::/ || die "mcopy onto the EFI partition failed"

# One GPT disk: 1 MiB alignment, a MiB of slack at the end for the backup GPT.
disk="$work/disk.img"
total_mib=$((1 + esp_mib + root_mib + data_mib + 1))
truncate -s "${total_mib}M" "$disk"
case "$arch" in
  amd64)
    # Types: EFI system partition; root (x86-64, the Discoverable Partitions Specification); Linux data.
    sfdisk -q "$disk" <<EOF || die "sfdisk failed"
label: gpt
first-lba: 2048
start=1MiB, size=${esp_mib}MiB, type=C12A7328-F81F-11D2-BA4B-00A0C93EC93B, uuid=$esp_uuid, name=EFI
size=${root_mib}MiB, type=4F68BCE3-E8CD-4DB1-96E7-FBCAF984B709, uuid=$root_uuid, name=emboss-root
size=${data_mib}MiB, type=0FC63DAF-8483-4772-8E79-3D69D8477DE4, uuid=$data_uuid, name=emboss-data
EOF
    ;;
  arm64)
    sfdisk -q "$disk" <<EOF || die "sfdisk failed"
label: dos
label-id: $disk_id
start=1MiB, size=${esp_mib}MiB, type=c, bootable
size=${root_mib}MiB, type=83
size=${data_mib}MiB, type=83
EOF
    ;;
esac
put() { dd if="$1" of="$disk" bs=1M seek="$2" conv=notrunc,sparse status=none || die "writing $1 into the disk failed"; }
put "$work/esp.vfat" 1
put "$work/root.ext4" $((1 + esp_mib))
put "$work/data.ext4" $((1 + esp_mib + root_mib))

bmaptool -q create -o "$work/disk.bmap" "$disk" 2>/dev/null || rm -f "$work/disk.bmap"
{
  echo "arch=$arch"
  echo "kernel=$kver"
  echo "deb=$(dpkg-deb -f "$deb" Package)_$(dpkg-deb -f "$deb" Version)"
  echo "base=$base_key"
  echo "image=$image_key"
  echo "cmdline=$cmdline"
  echo "esp_mib=$esp_mib root_mib=$root_mib data_mib=$data_mib"
  echo "root_partuuid=$root_uuid"
} > "$work/disk.info"
mv "$disk" "$image_cached.part" && mv "$work/disk.info" "$image_cached.info" &&
  { [ -f "$work/disk.bmap" ] && mv "$work/disk.bmap" "$image_cached.bmap"; true; } && mv "$image_cached.part" "$image_cached" ||
  die "cannot store the image in the cache"
# Images of other .debs or bases of this architecture: the newest few are kept.
ls -t "$cache"/image-"$arch"-*.img 2>/dev/null | tail -n +4 | while read -r old; do rm -f "$old" "$old.bmap" "$old.info"; done
copy_out
log "image $image_key built in $((SECONDS - t0)) s: $total_mib MiB (root $root_mib, data $data_mib, EFI $esp_mib), $(du -h "$out_img" | cut -f1) used"
echo "$out_img"
