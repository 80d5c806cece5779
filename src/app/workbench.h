// The visitor's bench: a sheet of metal, the tools, the metals, undo by whole strokes, turning the piece.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/stroke_builder.h"
#include "app/surface_pick.h"
#include "app/view_changes.h"
#include "app/view_orbit.h"
#include "devices/buttons.h"
#include "render/camera.h"
#include "render/shading.h"
#include "scene/scene.h"

namespace emboss {

struct BenchSetup {
  std::shared_ptr<const Workpiece> workpiece;  // null: a 120 x 80 x 1 mm plate
  Deformation deformation = Deformation::Sheet;
  std::string metal = "copper";
  int width = 1280, height = 800;  // the screen, pixels
  double tabletAspect = 1.6;
};

// The bench's home view: the sheet seen from in front and a little below, filling about
// `fill` of the screen's height (and at most `fill` of its width), room left for the overlay.
// `sideRoom` pixels stay free at the left and the right (the overlay's panels).
CameraSpec benchCamera(const Box3& workpieceBounds, int width, int height, double fill = 0.78, double sideRoom = 0);
// The room the bench's overlay panels take at each side of a screen `height` pixels high.
double benchSideRoom(int height);

// The tool catalogue (src/tools) as the bench offers it. Sizes step by 25 % from the catalogue's.
inline constexpr int kMinSizeStep = -2, kMaxSizeStep = 2;

// Not thread-safe: the main loop owns it. Times are seconds on the app's clock.
class Workbench {
 public:
  // A blending punch's beads stacked on one spot at most (admit()).
  static constexpr int kMaxBlendsOnASpot = 3;
  // A flat punch's strikes whose faces may cover a new strike's centre: about three passes of the
  // punch along a line (in one pass each centre lies under the face before it; in the next, under
  // kFlatPunchOverlap strikes of the pass before as well, and so on).
  static constexpr int kMaxStrikesOnASpot = 3 * kFlatPunchOverlap - 1;

  explicit Workbench(BenchSetup setup);

  // A fresh sheet for a new visitor: no operations, the tracer, middle size, the default metal, home view.
  void resetForVisitor(double now);
  // The visitor's "new sheet": no operations, home view; tool, size and metal stay.
  void newSheet(double now);
  // Carries out a button's action (NextTool ... NewSheet). Capture, Staff and Quit are not the bench's.
  void apply(Action action, double now);

  // The pen at screen pixel (sx, sy). A touch on the metal starts or continues a stroke; the
  // stroke ends when the tip lifts or the pen leaves the metal.
  void pen(double sx, double sy, double pressure, bool tip, bool inRange, double now);
  // Where the pen's point meets the sheet, found by the one who draws it when it can (the ray
  // through the pen's pixel as the picture was traced: the metal the visitor sees): true and the
  // point (nullopt: off the metal) in `hit`; false: pickSurface() on the model instead.
  using Picker = std::function<bool(const Model& model, const Camera& camera, double sx, double sy,
                                    std::optional<glm::dvec3>& hit)>;
  void setPicker(Picker picker) { picker_ = std::move(picker); }
  // The pen is gone (out of range, device lost): ends a stroke, hides the footprint.
  void penAway();
  // Ends a stroke in progress (its operations join the model) with the pen left where it is.
  void finishStroke() { endStroke(); }
  // Adds operations made elsewhere (a captured drawing's traced lines) as one stroke: one undo
  // takes them all back. Returns how many the model took.
  size_t addStroke(const std::vector<Operation>& ops);
  // Advances the turning animation.
  void update(double now);

  const Model& model() const { return *model_; }
  const Metal& metal() const { return metal_; }
  ToolSpec tool() const;
  size_t toolIndex() const { return tool_; }
  int sizeStep() const { return sizeStep_; }
  bool turned() const { return turned_; }
  bool moving() const { return animating_; }
  bool strokeActive() const { return stroke_.active(); }
  // The camera now (between home and turned while turning), for a width x height picture.
  const CameraSpec& camera() const { return current_; }
  const CameraSpec& homeCamera() const { return home_; }
  ShadingParams shading() const;
  // The scene to save: workpiece, metal, home camera; operations from model().
  Scene scene(const std::string& title) const;
  // Where the tablet's area lands on the screen now (pixels).
  ScreenBox tabletArea() const { return tabletArea_; }
  double tabletAspect() const { return setup_.tabletAspect; }

  struct Hover {
    bool visible = false;
    double sx = 0, sy = 0;   // where the pen's ray meets the metal, pixels
    double radius = 0;       // the tool's footprint, pixels
    bool touching = false;
  };
  const Hover& hover() const { return hover_; }
  double pressure() const { return pressure_; }
  // The region raiser's contour so far, in screen pixels (drawn by the overlay while it is open).
  std::vector<std::pair<double, double>> openContour() const;

  // Operations committed since the bench was made (never decreases); the latency meter watches it.
  std::uint64_t committed() const { return committed_; }
  size_t strokes() const { return strokes_.size(); }
  // Operations per stroke in effect, and per undone stroke (what undo and redo take).
  const std::vector<size_t>& strokeSizes() const { return strokes_; }
  const std::vector<size_t>& redoSizes() const { return redo_; }
  // Strokes finished since the visitor's sheet was new (counts on, never back; undo does not lower it).
  std::uint64_t strokesMade() const { return strokesMade_; }
  // A session read back from the journal: every operation made (undone ones included), how many
  // are in effect, the strokes they form, the metal. Stroke sizes that do not add up to `cursor`
  // are replaced by one stroke per operation. Returns false when the model refused an operation.
  bool restore(const std::vector<Operation>& ops, size_t cursor, std::vector<size_t> strokes, std::vector<size_t> redo,
               const std::string& metal, std::uint64_t strokesMade);
  ViewChanges takeChanges();

 private:
  void endStroke();
  void commit(const std::vector<Operation>& ops);
  // Whether the sheet takes `op`: a blending punch's bead is left out where kMaxBlendsOnASpot set
  // operations already cover its centre. Each blend is an R-function union whose value around the
  // spot moves towards zero as more are stacked there, and every evaluation near the stack visits
  // all of them: a visitor going over the same place again and again with the punch would make
  // each frame there dearer without end (the renderer's dense rays bound the search, not this).
  // Likewise a flat punch's strike where kMaxStrikesOnASpot strikes' faces already cover its
  // centre: each sinks the sheet a little more, and the background would sink without end.
  bool admit(const Operation& op) const;

  void undoOps(size_t n);
  void setView(bool turned, double now);
  void refreshMapping();

  BenchSetup setup_;
  std::unique_ptr<Model> model_;
  Metal metal_;
  size_t tool_ = 0;
  int sizeStep_ = 0;
  StrokeBuilder stroke_;
  bool strokeOpen_ = false;      // strokes_.back() is the stroke in progress
  std::vector<size_t> strokes_;  // operations per stroke in effect (undo takes the last)
  std::vector<size_t> redo_;     // operations per undone stroke (redo brings back the last)
  CameraSpec home_, current_;
  Orbit homeOrbit_, turnedOrbit_, fromOrbit_, toOrbit_;
  bool turned_ = false, animating_ = false;
  double animStart_ = 0;
  std::optional<Camera> camera_;
  Picker picker_;
  ScreenBox tabletArea_;
  Hover hover_;
  double pressure_ = 0;
  std::uint64_t committed_ = 0;
  std::uint64_t strokesMade_ = 0;
  ViewChanges changes_;
};

}  // namespace emboss
