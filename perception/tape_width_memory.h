#pragma once

#include <deque>
#include <optional>

namespace agv::perception {

// The width of the tape followed in the frames before, so that a frame whose only line is
// narrower (a floorboard seam, a shadow's edge, thinner tape beside the path) is not taken for
// it. The width settles once kSettleFrames lines agree (10-90 % range within kSettledSpread of
// their median). A line is unlike it when narrower by more than kTolerance of the median (and
// at least kToleranceFloor_m: the edges' sub-pixel noise on narrow tape), or wider than two
// tapes side by side by as much: where two pieces overlap (a fork's branch leaving, a joint, a
// crossing) the tape reads up to twice as wide. A line of unknown width (0) is not unlike.
// Narrower is judged against the narrowest width settled since it was last forgotten: where a
// fork's branch leaves at a tangent the band followed widens slowly and the median follows it (49
// mm tape read 76 mm wide over 0.2 m), and the tape itself, once apart, was refused for 30 frames.
// After kForgetAfterFrames frames in a row without a line the width is forgotten, so that a
// path whose tape really changes is taken up again.
class TapeWidthMemory {
 public:
  static constexpr int kSettleFrames = 5;
  static constexpr int kKeptFrames = 15;
  static constexpr double kSettledSpread = 0.2;
  static constexpr double kTolerance = 0.3;
  static constexpr double kToleranceFloor_m = 0.003;
  static constexpr int kForgetAfterFrames = 30;

  // Record one frame: the followed line's width, or nullopt when the frame had no line.
  void update(std::optional<double> width_m);
  // The median width of the lines kept, once settled.
  std::optional<double> settled_width_m() const;
  // The width as it last settled (kept while lines of other widths come and go: a corner's
  // overlap, a fork's two legs), forgotten with the rest.
  std::optional<double> last_settled_width_m() const { return last_settled_m_; }
  // Whether a line of width_m is unlike the settled width (false until it settles).
  bool unlike(double width_m) const;
  // The same against the width as it last settled (false until one settles).
  bool unlike_last_settled(double width_m) const;

 private:
  std::deque<double> widths_m_;  // the last kKeptFrames lines' widths, oldest first
  int frames_without_line_ = 0;
  std::optional<double> last_settled_m_;
  std::optional<double> narrowest_settled_m_;
  // Whether a line of width_m is unlike settled_m (false without one).
  bool unlike_width(double width_m, std::optional<double> settled_m) const;
};

}  // namespace agv::perception
