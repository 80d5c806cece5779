#!/bin/busybox sh
# guest-init.sh: /init of the HIL initramfs. Mounts this machine's root read-only over 9p at /host,
# prepares a chroot in it (proc, sys, dev, configfs, tmpfs on /tmp and /run), then sources the job
# script named by hil.job= on the kernel command line and powers off. Job scripts use the hil_*
# functions below; the markers they print are read by run-vm.sh and hil-tests.sh.
/bin/busybox mkdir -p /bin /sbin /usr/bin /usr/sbin
/bin/busybox --install -s /bin
export PATH=/bin:/sbin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev

hil_fatal() { echo "EMBOSS-HIL-FATAL $*"; echo "EMBOSS-HIL-DONE"; sync; poweroff -f; sleep 10; }

for m in $(cat /etc/boot-modules); do insmod "/lib/boot-modules/$m" || hil_fatal "insmod $m"; done
mount -t 9p -o trans=virtio,version=9p2000.L,ro,msize=262144,cache=loose host /host || hil_fatal "cannot mount the host over 9p"

for arg in $(cat /proc/cmdline); do
  case "$arg" in
    hil.job=*) HIL_JOB=${arg#hil.job=} ;;
    hil.modules=*) HIL_MODULES=${arg#hil.modules=} ;;
  esac
done
mount -o bind "/host$HIL_MODULES" /lib/modules || hil_fatal "no modules at $HIL_MODULES"
echo /sbin/modprobe > /proc/sys/kernel/modprobe
ln -s /bin/busybox /sbin/modprobe 2>/dev/null

R=/host
mount -t proc proc $R/proc
mount -t sysfs sys $R/sys
mount -t devtmpfs dev $R/dev
mkdir -p /dev/pts /dev/shm
mount -t devpts devpts $R/dev/pts
mount -t tmpfs shm $R/dev/shm
# /tmp and /var/tmp: the host's, made writable by an overlay on a tmpfs (so a build tree or a test
# program under the host's /tmp stays visible); plain tmpfs when overlayfs will not take 9p.
modprobe overlay 2>/dev/null
mkdir -p /rw && mount -t tmpfs rw /rw
for d in tmp var/tmp; do
  n=$(echo $d | tr / _)
  mkdir -p /rw/$n/upper /rw/$n/work
  mount -t overlay overlay -o lowerdir=$R/$d,upperdir=/rw/$n/upper,workdir=/rw/$n/work $R/$d 2>/dev/null ||
    mount -t tmpfs $n $R/$d
done
chmod 1777 /rw/tmp/upper /rw/var_tmp/upper 2>/dev/null
mount -t tmpfs run $R/run
[ -d $R/sys/kernel/debug ] && mount -t debugfs debugfs $R/sys/kernel/debug 2>/dev/null
ip link set lo up 2>/dev/null
hostname emboss-hil

# ---- functions for job scripts
cat > /bin/hil-chroot <<'X'
#!/bin/sh
# Runs a command in the chroot (the host's root), in the caller's directory, with a clean environment.
# XDG_CACHE_HOME: one cache for every test (each gives its kiosk a HOME of its own), where the job
# puts the kiosk's shading tables made on the host (hil-tests.sh).
exec chroot /host /usr/bin/env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME=/tmp \
  XDG_CACHE_HOME=/tmp/.cache TMPDIR=/tmp LANG=C.UTF-8 TERM=dumb EMBOSS_HIL=1 HIL_KDIR="$HIL_KDIR" \
  /bin/sh -c 'cd "$1" 2>/dev/null || cd /; shift; exec "$@"' sh "$HIL_CWD" "$@"
X
chmod +x /bin/hil-chroot

hil_modprobe() {
  local m rc=0
  for m in "$@"; do modprobe "$m" || { echo "hil: modprobe $m failed"; rc=1; }; done
  if grep -q configfs /proc/filesystems && ! grep -q " $R/sys/kernel/config " /proc/mounts; then
    mount -t configfs configfs $R/sys/kernel/config
  fi
  return $rc
}

hil_chroot() { /bin/hil-chroot "$@"; }

# hil_udevd_start: systemd-udevd in the chroot, so that libudev monitors (libusb hotplug) get events.
hil_udevd_start() {
  [ -n "$HIL_UDEVD" ] || { echo "hil: no systemd-udevd available"; return 1; }
  mkdir -p $R/run/udev
  # udevadm runs as udevd when its name is systemd-udevd.
  ln -sf "$HIL_UDEVD" $R/run/systemd-udevd
  hil_chroot /run/systemd-udevd --daemon --resolve-names=never >/dev/null 2>&1 || { echo "hil: udevd did not start"; return 1; }
  local i=0
  while [ ! -e $R/run/udev/control ] && [ $i -lt 50 ]; do usleep 100000; i=$((i + 1)); done
  [ -e $R/run/udev/control ]
}

# A program of a test that crashes leaves a core in the chroot's /tmp, named by its pid and its
# executable's path ('/' as '!'); hil_test prints gdb's backtraces of it, so that a crash seen once
# (in CI, say) is not lost.
echo '/tmp/hil-core.%p.%E' > /proc/sys/kernel/core_pattern 2>/dev/null
ulimit -c unlimited 2>/dev/null
hil_backtraces() {
  local core exe
  for core in $R/tmp/hil-core.*; do
    [ -f "$core" ] || continue
    exe=$(basename "$core" | cut -d. -f3- | tr '!' '/')
    echo "hil: $exe crashed; gdb's backtraces of its core:"
    if [ -x $R/usr/bin/gdb ]; then
      hil_chroot gdb -q -batch -ex 'thread apply all bt 25' "$exe" "/tmp/$(basename "$core")" 2>&1 |
        grep -v '^\[New LWP\|^warning: ' | head -200
    else
      echo "hil: (no gdb on the host: apt-get install gdb)"
    fi
    rm -f "$core"
  done
}

# hil_test NAME TIMEOUT CMD...: runs CMD in the chroot with a time limit, between marker lines.
hil_test() {
  local name=$1 limit=$2 t0 t1 rc
  shift 2
  echo "EMBOSS-HIL-BEGIN $name"
  rm -f $R/tmp/hil-core.*
  t0=$(cut -d' ' -f1 /proc/uptime)
  timeout -s KILL "$limit" /bin/hil-chroot "$@" 2>&1
  rc=$?
  hil_backtraces
  # A program killed by SIGSEGV without a core may have died in the kernel (an oops in a system call
  # kills the calling task with SIGSEGV): the kernel's own log says which.
  if [ "$rc" -ne 0 ]; then
    echo "hil: $name failed (status $rc); the kernel's log since boot, its last 80 lines:"
    dmesg 2>/dev/null | tail -80
  fi
  t1=$(cut -d' ' -f1 /proc/uptime)
  echo "EMBOSS-HIL-END $name rc=$rc secs=$(echo "$t0 $t1" | awk '{printf "%.1f", $2 - $1}')"
  return $rc
}
export HIL_KDIR HIL_CWD

[ -n "$HIL_JOB" ] && [ -r "$R$HIL_JOB" ] || hil_fatal "no job script ($HIL_JOB)"
echo "EMBOSS-HIL-BOOTED $(cut -d' ' -f1 /proc/uptime)"
. "$R$HIL_JOB"
echo "EMBOSS-HIL-DONE"
sync
poweroff -f
sleep 10
