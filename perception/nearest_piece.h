#pragma once

#include <optional>
#include <vector>

#include "perception/curve_fit.h"
#include "perception/line_set.h"

namespace agv::perception {

// Where the followed line's evidence is two pieces joined at a breakpoint (a line running
// into an arc, a fork's trunk into its branch): the model of the piece nearest the vehicle,
// carried back to the origin; nullopt when one piece explains it about as well (fit_joined_arcs,
// in a frame turned about the origin to `model`'s direction where the evidence comes nearest,
// then by the fit's slope up to twice). The near piece is a line unless its own points show a
// bend (Bayesian information criterion): carried back 0.2-0.4 m, a curvature of noise alone
// would move the line by millimetres. A piece that would run against `model` where the evidence
// comes nearest is none.
std::optional<CurveModel> nearest_piece(const std::vector<Chord>& chords, const DetectedLine& line,
                                        const CurveModel& model);

}  // namespace agv::perception
