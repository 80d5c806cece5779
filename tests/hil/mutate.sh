#!/bin/bash
# mutate.sh BUILD_DIR SOURCE_DIR [MUTANT...]: proves that each HIL test fails when the back end it
# drives is broken. Each mutant is a scratch copy of one back-end source with one deliberate bug,
# compiled and linked into the test program ahead of the project's libraries (build.sh
# HIL_EXTRA_OBJS); the project's own files are never touched. All mutants then run in one VM boot,
# and each must make its test fail. Prints one line per mutant and 'N passed, N failed' (a mutant
# that is caught counts as passed). Takes a few minutes: a manual check, not part of the CTest run.
set -u -o pipefail
[ $# -ge 2 ] || { echo "usage: mutate.sh BUILD_DIR SOURCE_DIR [MUTANT...]" >&2; exit 2; }
build=$(cd "$1" && pwd) || exit 2
src=$(cd "$2" && pwd) || exit 2
shift 2
HIL_DIR="$src/tests/hil"
. "$HIL_DIR/vm-lib.sh"

fixtures=${EMBOSS_FIXTURES:-$src/../shared/fixtures}
[ -d "$fixtures" ] || { echo "mutate.sh: no fixtures folder at $fixtures (set EMBOSS_FIXTURES)"; exit 77; }
fixtures=$(cd "$fixtures" && pwd)

# name | source file | text | replacement | test program | what the bug is
mutants=(
  "evdev-range|platform/pen/pen_evdev.cpp|a->minimum, a->maximum,|a->minimum, a->maximum + 100,|hil_evdev_uinput|the evdev back end misreads the axis ranges"
  "evdev-nograb|platform/pen/pen_evdev.cpp|if (grab) {|if (false) {|hil_evdev_uinput|the evdev back end does not grab the tablet"
  "hidraw-offset|platform/pen/pen_hidraw.cpp|std::span<const uint8_t>(buf, static_cast<size_t>(n))|std::span<const uint8_t>(buf + 1, static_cast<size_t>(n) - 1)|hil_hidraw_uhid|the raw back end drops the report-ID byte"
  "hidraw-noloss|platform/pen/pen_hidraw.cpp|if (n < 0) {|if (n < -1) {|hil_hidraw_uhid|the raw back end does not notice an unplug"
  "hidraw-sysfs|platform/pen/pen_hidraw.cpp|\"/device/report_descriptor\"|\"/device/uevent\"|hil_hidraw_uhid|the report descriptor is read from the wrong sysfs file"
  "usb-string|platform/pen/usb_uclogic.cpp|{kUclogicV2StringIndex, kUclogicV1StringIndex}|{uint8_t{201}, uint8_t{101}}|hil_usb_gadget|the handshake reads the wrong string descriptors"
  "probe-nohandshake|platform/pen/pen_probe.cpp|info.interfaceNumber <= 0|info.interfaceNumber < 0|hil_usb_gadget|the probe skips the UC-Logic handshake on interface 0"
  "gpio-polarity|platform/gpio/buttons_gpio.cpp|b.activeLow ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0|0|hil_gpio_cp2112|the GPIO back end ignores active_low"
  "gpio-edges|platform/gpio/buttons_gpio.cpp|== GPIOD_LINE_EVENT_RISING_EDGE|== GPIOD_LINE_EVENT_FALLING_EDGE|hil_gpio_cp2112|the GPIO back end reads edges the wrong way round"
  "gpio-levels-inverted|platform/gpio/buttons_gpio.cpp|if ((value == 1) != last[i]) {|if ((value == 0) != last[i]) {|hil_gpio_cp2112|the level reader reads the levels the wrong way round"
  "gpio-removable-edges|platform/gpio/buttons_gpio.cpp|(config.read == GpioRead::Auto && removable)|false|hil_gpio_cp2112|the kiosk holds interrupts on a chip that can be unplugged"
  "gestures-nodebounce|src/devices/button_gestures.cpp|b.debounceS = std::max(0.0, line.debounceS);|b.debounceS = 0.0;|hil_gpio_cp2112|the button logic does not debounce"
  "camera-width|platform/camera/camera_v4l2.cpp|return yuyvToRgba(std::span(data, bytes), width_, height_|return yuyvToRgba(std::span(data, bytes), width_ / 2, height_|hil_camera_vivid|the camera converts frames at the wrong width"
  "camera-node|platform/camera/camera_v4l2.cpp|if (device_ != \"auto\") return openNode(device_);|if (device_ != \"auto\") return openNode(\"/dev/video1\");|hil_camera_vivid|the camera opens the wrong node"
)

hil_prepare || { echo "hil: this machine cannot run the HIL virtual machine"; exit 77; }
pkgs="hidapi-hidraw libusb-1.0 libgpiod libevdev libudev libsystemd libpng libjpeg"
cflags=$(pkg-config --cflags $pkgs)
scratch="$build/hil-mutants"
rm -rf "$scratch" && mkdir -p "$scratch"
guest="$scratch/guest.sh"
declare -A what=() built=()
names=()
for m in "${mutants[@]}"; do
  IFS='|' read -r name file from to prog why <<< "$m"
  if [ $# -gt 0 ] && ! printf '%s\n' "$@" | grep -qx "$name"; then continue; fi
  names+=("$name")
  what[$name]=$why
  dir="$scratch/$name"
  mkdir -p "$dir"
  cp "$src/$file" "$dir/"
  f="$dir/$(basename "$file")"
  FROM=$from TO=$to perl -pi -e 's/\Q$ENV{FROM}\E/$ENV{TO}/g' "$f"
  if cmp -s "$f" "$src/$file"; then
    echo "mutant $name: the text to change is not in $file any more (update mutate.sh)"
    continue
  fi
  # shellcheck disable=SC2086
  if ! g++ -std=c++20 -O1 -g -DGLM_FORCE_CXX17 -I"$src/src" -I"$src/platform" -I"$(dirname "$src/$file")" $cflags \
      -c "$f" -o "$dir/mutant.o" 2> "$dir/build.log"; then
    echo "mutant $name: does not compile"; head -5 "$dir/build.log"; continue
  fi
  if ! HIL_OUT="$dir" HIL_EXTRA_OBJS="$dir/mutant.o" HIL_JOBS=1 "$HIL_DIR/build.sh" "$build" "$src" "$prog"; then
    echo "mutant $name: the test program does not link"; continue
  fi
  built[$name]="$dir/$prog"
done

{
  echo "hil_modprobe uinput evdev uhid hid-cp2112 vivid hid-generic dummy_hcd libcomposite usb_f_fs usbhid"
  echo "hil_udevd_start"
  for name in "${names[@]}"; do
    [ -n "${built[$name]:-}" ] || continue
    prog=$(basename "${built[$name]}")
    case "$prog" in
      hil_evdev_uinput) args=("$fixtures/evemu") ;;
      hil_hidraw_uhid) args=("$fixtures/hid") ;;
      *) args=() ;;
    esac
    printf 'hil_test %q 120 %q' "$name" "${built[$name]}"
    printf ' %q' "${args[@]}"
    echo
  done
} > "$guest"
console="$scratch/console.log"
hil_boot "$guest" 900 "$console" 1

caught=0 missed=0
for name in "${names[@]}"; do
  end=$(grep -a "^EMBOSS-HIL-END $name " "$console" | tail -1)
  rc=${end#*rc=}; rc=${rc%% *}
  firstfail=$(awk -v t="$name" '$0 == "EMBOSS-HIL-BEGIN " t {on = 1; next} on && index($0, "EMBOSS-HIL-END ") == 1 {exit} on && /^FAIL - / {print; exit}' "$console")
  if [ -z "${built[$name]:-}" ]; then
    missed=$((missed + 1)); echo "NOT RUN  $name (${what[$name]})"
  elif [ -n "$end" ] && [ "$rc" != 0 ] && [ -n "$firstfail" ]; then
    caught=$((caught + 1)); echo "caught   $name (${what[$name]}): ${firstfail#FAIL - }"
  elif [ -n "$end" ] && [ "$rc" != 0 ]; then
    missed=$((missed + 1)); echo "ERROR    $name (${what[$name]}): the test exited $rc without a failed check (did it run?)"
  else
    missed=$((missed + 1)); echo "MISSED   $name (${what[$name]}): the test passed anyway"
  fi
done
[ -n "${EMBOSS_HIL_LOG:-}" ] && cp "$console" "$EMBOSS_HIL_LOG"
rm -rf "$scratch"
echo "VM $HIL_BOOT_SECONDS s"
echo "$caught passed, $missed failed"
[ $missed -eq 0 ]
