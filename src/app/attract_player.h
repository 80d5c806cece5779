// Attract mode: famous pieces embossed again stroke by stroke at a watchable pace, with slow camera moves, looping.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "app/view_changes.h"
#include "render/shading.h"
#include "scene/scene.h"

namespace emboss {

struct AttractPiece {
  std::string name;  // the file's stem, for the log
  Scene scene;
};

// A piece's life: build (operations appear one by one, each given the time a hand would take:
// tracers by their length, strikes by count), show (the camera swings slowly round the finished
// piece and back), rest (a moment still), then the next piece on a fresh sheet.
class AttractPlayer {
 public:
  AttractPlayer(std::vector<AttractPiece> pieces, int width, int height, double speed = 1.0);

  bool empty() const { return pieces_.empty(); }
  size_t size() const { return pieces_.size(); }
  // Starts piece `index` with `doneFraction` of its operations already in place (a kiosk that
  // just started shows a piece under way rather than a bare sheet).
  void start(double now, size_t index = 0, double doneFraction = 0.0);
  void update(double now);
  // Holds the replay for `seconds` (everything happens that much later): after a stall of the
  // main loop the piece goes on where it was instead of adding a stall's worth of operations at once.
  void hold(double seconds) {
    buildStart_ += seconds;
    phaseStart_ += seconds;
  }

  const Model& model() const { return *model_; }
  const CameraSpec& camera() const { return camera_; }
  ShadingParams shading() const;
  bool moving() const { return phase_ == Phase::Show; }
  ViewChanges takeChanges();

  const std::string& title() const;
  size_t pieceIndex() const { return index_; }
  double progress() const;  // 0..1 of the current piece's operations
  // Seconds the build of piece i takes (after speed).
  double buildSeconds(size_t i) const;

  static constexpr double kShowSeconds = 12.0, kRestSeconds = 2.5;

 private:
  enum class Phase { Build, Show, Rest };
  void load(size_t index, double now, double doneFraction);

  std::vector<AttractPiece> pieces_;
  std::vector<std::vector<double>> times_;  // per piece: when each operation appears, s from the start
  int w_, h_;
  double speed_;
  size_t index_ = 0;
  std::unique_ptr<Model> model_;
  size_t next_ = 0;
  Phase phase_ = Phase::Build;
  double phaseStart_ = 0, buildStart_ = 0;
  CameraSpec home_, camera_;
  ViewChanges changes_;
};

// How long a hand takes for an operation, seconds (before speed).
double strokeSeconds(const Operation& op);

}  // namespace emboss
