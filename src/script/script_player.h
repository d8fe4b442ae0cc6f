#pragma once
/// Plays a tool script the way a device driving a session does, resolving its rows aimed at the
/// tube. Such a row is resolved once, when its segment begins (at the tool's previous row's
/// time; at the start for a first row), against the tube as it is then, and stays there. The
/// hand then follows a path fixed before it moves, like a surgeon's reaching for a loop they
/// see. A target that kept chasing the tube it is moving would close a loop through the
/// simulation with one step of latency, and the force on the hand would depend on the rate
/// (docs/tool-coupling.md: 14 % RMS between 100 Hz and 1 kHz on the clearing gesture).
///
/// A `grasp@S` row is checked when it is due, as a surgeon looks before closing the jaws: if the
/// part of the tube nearest the tool's tip is more than a tube's diameter from S along the
/// centre line (the loop swung away, or another strand lies closer), the script's clock stops
/// for every tool (the other hand keeps what it holds) while this tool reaches again: it backs
/// off to its last row not aimed at the tube and plays its rows from there to the grasp row
/// again, each aimed anew, up to kMaxReaches times; then the script goes on.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "script/tool_script.h"

namespace viscera::script {

class ScriptPlayer {
 public:
  /// Reaches played again for one grasp row before the script goes on regardless.
  static constexpr int kMaxReaches = 3;

  explicit ScriptPlayer(ToolScript script);

  const ToolScript& script() const { return script_; }
  /// The target of `tool` at t. The aims whose segments have begun by t are resolved against
  /// `tube` first; while its centre line is empty (no skeleton seen yet) they wait, and the
  /// row's written position stands in. `tip` is where the tool's tip is (null: unknown, and
  /// its grasp rows pass unchecked). Call with non-decreasing t. @pre script().Has(tool).
  ToolKeyframe At(const std::string& tool, double t, const Tube& tube, const Vec3* tip = nullptr);
  /// How far the script runs behind the clock (s): the time its reaches again took. A row
  /// written at time r plays at r + delay() once they are over.
  double delay() const { return delay_; }
  /// Grasp rows reached again so far (each new reach counts).
  int reaches() const { return reaches_; }
  /// Whether the script has played out at t: its last row is due and no reach is under way.
  bool Done(double t) const { return !reach_ && t - delay_ >= script_.duration(); }

 private:
  // One tool's rows as played: the written ones with their aims resolved so far.
  struct Rows {
    std::vector<ToolKeyframe> written, played;
    std::vector<bool> pending;  // rows still to aim
    size_t next_grasp = 0;      // the first grasp row not yet checked
    void Resolve(double t, const Tube& tube, size_t last);
  };
  // A grasp row's reach played again: the tool's rows from its back-off point to the grasp row,
  // timed from when it began.
  struct Reach {
    std::string tool;
    size_t row = 0;  // the grasp row, in the tool's rows
    int tries = 0;
    Rows rows;
  };

  Reach BeginReach(const std::string& tool, size_t row, double t, const Vec3& from) const;
  // Whether the jaws at `tip` are at the part of the tube `row` aims at.
  static bool AtAimedPart(const ToolKeyframe& row, const Tube& tube, const Vec3* tip);

  ToolScript script_;
  std::map<std::string, Rows> rows_;
  std::optional<Reach> reach_;
  double delay_ = 0.0;
  int reaches_ = 0;
};

}  // namespace viscera::script
