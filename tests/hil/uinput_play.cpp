// uinput_play: a tablet for programs under test (emboss-input, the kiosk). Creates a uinput device
// described by an evemu recording, waits, replays the recording frame by frame, waits, removes it.
//
//   uinput_play FILE.events [--before S] [--start-file PATH] [--frame S] [--after S] [--loop]
//     --before S   seconds between creating the device and the first event (default 2)
//     --start-file PATH  then also wait until PATH exists (the program under test is ready)
//     --frame S    seconds between frames (default 0.005); 0 keeps the recording's own timing
//     --after S    seconds the device stays after the last event (default 1)
//     --loop       replay again and again until killed (a visitor who keeps drawing)
// Prints "node /dev/input/eventN" once the device exists, "replayed" after the last event, "done" at
// the end. Exit 0, or 1 on error.
#include "evemu_uinput.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: uinput_play FILE.events [--before S] [--frame S] [--after S] [--loop]\n");
    return 2;
  }
  const std::filesystem::path file = argv[1];
  double before = 2.0, frame = 0.005, after = 1.0;
  bool loop = false;
  std::string startFile;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--loop") loop = true;
    else if (i + 1 < argc && a == "--before") before = std::atof(argv[++i]);
    else if (i + 1 < argc && a == "--frame") frame = std::atof(argv[++i]);
    else if (i + 1 < argc && a == "--after") after = std::atof(argv[++i]);
    else if (i + 1 < argc && a == "--start-file") startFile = argv[++i];
  }
  auto rec = emboss::loadEvemu(file);
  if (!rec) {
    std::fprintf(stderr, "uinput_play: %s\n", rec.error().c_str());
    return 1;
  }
  std::filesystem::path desc = file;
  if (auto d = emboss::findEvemuDesc(file)) desc = *d;
  hil::Uinput dev;
  if (!dev.create(hil::specFor(rec->device, hil::parseProps(desc)))) {
    std::fprintf(stderr, "uinput_play: %s\n", dev.error().c_str());
    return 1;
  }
  std::printf("node %s\n", dev.node().c_str());
  std::fflush(stdout);
  hil::sleepS(before);
  if (!startFile.empty()) hil::waitFor([&] { return std::filesystem::exists(startFile); }, 600.0, 0.02);
  do {
    double last = rec->events.empty() ? 0.0 : rec->events.front().time_s;
    for (const auto& e : rec->events) {
      if (frame == 0.0) {
        hil::sleepS(e.time_s - last);
        last = e.time_s;
      }
      dev.emit(e.type, e.code, e.value);
      if (e.type == EV_SYN && e.code == SYN_REPORT && frame > 0) hil::sleepS(frame);
    }
  } while (loop);
  std::printf("replayed\n");
  std::fflush(stdout);
  hil::sleepS(after);
  std::printf("done\n");
  return 0;
}
