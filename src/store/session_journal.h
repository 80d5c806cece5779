// The visitor's session, made durable as it is made: an SQLite journal (WAL, synchronous=FULL) written
// by one thread of its own, so the pen and the frame never wait for the disk (docs/sessions.md).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "app/kiosk_log.h"

struct sqlite3;

namespace emboss {

// The state a session's undo and redo need beyond its operations.
struct JournalState {
  size_t cursor = 0;               // operations in effect (the model's undo cursor)
  std::vector<size_t> strokes;     // operations per stroke in effect
  std::vector<size_t> redo;        // operations per undone stroke
  std::string metal;
  std::uint64_t strokesMade = 0;   // strokes the visitor has finished in this session, counted from 1
};

// An unfinished session as read back at start.
struct JournalSession {
  std::int64_t id = 0;
  double started = 0, last = 0;          // wall-clock seconds (Unix time)
  std::string head;                      // the scene file without its operations (JSON)
  std::vector<std::string> operations;   // every operation made, undone ones included (JSON each)
  JournalState state;
  size_t records = 0, dropped = 0;       // records read; records dropped (a checksum that does not match)
};

// Thread-safe: the main loop calls the writers; one thread of the journal's own writes.
class SessionJournal {
 public:
  using WallClock = std::function<double()>;

  // Opens (or creates) DIR/sessions.db. A store that is torn, corrupt or not a database is moved
  // aside (sessions.db.corrupt-STAMP) after what can be read of it is copied into a fresh one;
  // a folder that cannot be written leaves the journal off (ok() false, the reason logged), the
  // kiosk running.
  SessionJournal(std::filesystem::path dir, KioskLog log, WallClock wall = {});
  ~SessionJournal();  // writes what is queued, then closes
  SessionJournal(const SessionJournal&) = delete;
  SessionJournal& operator=(const SessionJournal&) = delete;

  bool ok() const { return db_ != nullptr; }
  const std::filesystem::path& path() const { return path_; }

  // The newest session that was never ended, if any.
  std::optional<JournalSession> unfinished();
  // Every session's id, start and end (0: unfinished) and operation count, oldest first.
  struct Summary {
    std::int64_t id;
    double started, ended;
    size_t operations;
  };
  std::vector<Summary> list();

  // A new session with the scene's head (its JSON without operations). Returns its id.
  std::int64_t begin(const std::string& head);
  // Continues a session read back by unfinished().
  void resume(std::int64_t id);
  // Operations [from, from + ops.size()) of the current session; those at `from` and beyond that
  // were written before are replaced (new strokes after an undo).
  void operations(size_t from, std::vector<std::string> ops);
  // The undo cursor, strokes and metal now. The state's strokesMade is reported durable once written.
  void state(const JournalState& s);
  // Ends the current session (kept as finished).
  void end();
  // Ends session `id` (an old one closed at start).
  void endSession(std::int64_t id);
  // Sessions ended before `before` (Unix seconds) are deleted, then the oldest ended ones until
  // the store is at most `maxBytes`. Returns how many were deleted.
  size_t prune(double before, std::uintmax_t maxBytes);

  // Strokes made durable since the last call: (session id, strokesMade count), in order.
  std::vector<std::pair<std::int64_t, std::uint64_t>> takeDurable();
  // Records waiting for the disk, and the last write error (empty when the last write worked).
  size_t queued() const;
  std::string lastError() const;
  // Waits until everything queued is written or `seconds` pass. True when nothing is left.
  bool flush(double seconds);

 private:
  struct Record {
    enum class Kind { Begin, Resume, Ops, State, End, EndId };
    Kind kind = Kind::Begin;
    std::int64_t id = 0;
    size_t from = 0;
    std::vector<std::string> texts;
    std::string head;
    std::uint64_t stroke = 0;
    double at = 0, before = 0;
    std::uintmax_t maxBytes = 0;
  };
  void open();
  bool salvage(const std::string& why);
  void run();
  bool write(std::deque<Record>& batch, std::vector<std::pair<std::int64_t, std::uint64_t>>& durable);
  void push(Record r);
  double now() const;

  std::filesystem::path dir_, path_;
  KioskLog log_;
  WallClock wall_;
  sqlite3* db_ = nullptr;
  std::int64_t current_ = 0;   // the writer's session (writer thread only)
  std::string writeError_;     // the last write's error (writer thread only)
  std::int64_t nextId_ = 0;    // ids handed out by begin() (main thread)

  std::mutex dbm_;  // the connection: the writer's batches and the reads
  mutable std::mutex m_;  // the queue
  std::condition_variable cv_, idle_;
  std::deque<Record> queue_;
  std::vector<std::pair<std::int64_t, std::uint64_t>> durable_;
  std::string error_;
  bool writing_ = false, stop_ = false;
  std::thread thread_;
};

// CRC-32 (zlib's) of a record's text, kept beside it so that a flipped byte is found.
std::uint32_t recordChecksum(const std::string& text);

}  // namespace emboss
