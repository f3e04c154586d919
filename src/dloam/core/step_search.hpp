// The motion between two scans when no prior can be trusted: the first pair of a drive, or a
// constant-velocity prediction the data contradicts (scans dropped while the platform changed its
// motion, a fast turn, a T_coarse the motion gate rejected). Multi-start coarse-to-fine
// registration of a subsample of the current scan onto the previous scan's features: the
// candidates cover what the platform can do over the interval (yaw turns and travel along the
// sensor's x axis, around the prediction and around standing still), each is registered in all
// six degrees of freedom with a correspondence radius that shrinks from metres to decimetres, and
// the candidate with the best score (the caller's measure of how well the whole scan agrees with
// the previous one) wins.
#pragma once

#include <functional>
#include <vector>

#include "dloam/core/registration.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

struct StepSearchOptions {
  double max_translation = 4.0;   ///< m: travel candidates along x in [-max, max] of each centre
  double max_rotation = 0.16;     ///< rad: yaw candidates in [-max, max] of each centre
  double translation_step = 2.0;  ///< m between travel candidates
  double rotation_step = 0.17;    ///< rad between yaw candidates (10 deg)
  /// Every candidate is scored as it is with `coarse_tolerance`; the `refine` best are registered
  /// and scored again with `fine_tolerance`.
  double coarse_tolerance = 1.0;
  double fine_tolerance = 0.2;
  std::size_t refine = 6;
  std::vector<double> radii = {3.0, 1.0, 0.4};  ///< correspondence radii of the stages (m)
  int iterations = 4;                           ///< registration iterations per stage
  /// Candidates per centre at most: over a long interval (scans dropped) the ranges grow with it,
  /// and the steps and the coarse tolerance double until the grid fits; the registration then
  /// starts with a radius of the translation step.
  std::size_t max_candidates = 1000;
};

/// How well a motion (current -> previous scan frame) explains the two scans within a tolerance
/// (m); higher is better. Called concurrently.
using StepScore = std::function<double(const Pose& T, double tolerance)>;

struct StepSearchResult {
  Pose T = Pose::Identity();  ///< current -> previous scan frame
  double fitness = 0.0;       ///< the score at T
  std::size_t candidates = 0;
};

/// Searches around each of `centres` (e.g. the prediction and the identity, duplicates skipped):
/// every combination of a yaw and a travel candidate is scored; from the best few, `source` is
/// registered onto `target` coarse to fine. Each centre is also registered with the stages after
/// the first alone, so that a nearly right prediction is not pulled by the widest radius onto an
/// object that moved or a structure one spacing along. The best fine score wins (ties: the earlier
/// candidate, so the result does not depend on the thread schedule).
StepSearchResult search_step(const FeatureSource& source, const FeatureMap& target,
                             const std::vector<Pose>& centres, const StepSearchOptions& options,
                             const StepScore& score);

}  // namespace dloam
