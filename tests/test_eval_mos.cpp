// MOS point confusion, object-level counts (paper eq. 16) and effective-feature ratio.
#include <gtest/gtest.h>

#include <cmath>

#include "dloam/eval/mos_metrics.hpp"

using namespace dloam;
using namespace dloam::eval;
using semantic::make;

namespace {
constexpr Label kMoving = semantic::kMovingCar;
constexpr Label kStatic = semantic::kStatic;
}  // namespace

TEST(EvalMos, HandMadeConfusionIgnoresUnlabeledAndOutliers) {
  // gt:   M M M M M S S S S S | 0 1 0     (last three ignored)
  // pred: M M M S S M S S S S | M M S
  std::vector<Label> gt = {kMoving, kMoving, kMoving, kMoving, kMoving, kStatic, 10,
                           40,      kStatic, kStatic, 0,       1,       0};
  std::vector<Label> pred = {251,     259, kMoving, kStatic, 0,       kMoving, kStatic,
                             kStatic, 30,  kStatic, kMoving, kMoving, 0};
  const MosConfusion c = point_confusion(gt, pred);
  EXPECT_EQ(c.tp, 3u);
  EXPECT_EQ(c.fn, 2u);  // predicted 0 on a moving point is a miss
  EXPECT_EQ(c.fp, 1u);
  EXPECT_EQ(c.tn, 4u);
  EXPECT_EQ(c.ignored, 3u);
  EXPECT_DOUBLE_EQ(c.iou(), 0.5);
  EXPECT_DOUBLE_EQ(c.precision(), 0.75);
  EXPECT_DOUBLE_EQ(c.recall(), 0.6);
  EXPECT_DOUBLE_EQ(c.static_iou(), 4.0 / 7.0);
  EXPECT_THROW(point_confusion(gt, std::vector<Label>(3, 0)), InputError);
}

TEST(EvalMos, OneConfusionOverAllScansNotMeanOfScans) {
  MosResult result;
  add_scan(result, {kMoving}, {kMoving});                                                        // IoU 1
  add_scan(result, {kMoving, kMoving, kStatic, kStatic}, {kMoving, kStatic, kMoving, kMoving});  // IoU 1/4
  EXPECT_EQ(result.scans, 2u);
  EXPECT_DOUBLE_EQ(result.points.iou(), 2.0 / 5.0);
  EXPECT_TRUE(std::isnan(MosConfusion{}.iou()));
}

TEST(EvalMos, ObjectCountsUseMajorityOfPointsPerInstance) {
  std::vector<Label> gt, pred;
  const auto add = [&](Label g, Label p, int n) {
    for (int i = 0; i < n; ++i) {
      gt.push_back(g);
      pred.push_back(p);
    }
  };
  add(make(kMoving, 1), kMoving, 3);  // object 1: 3 of 4 predicted moving -> TP
  add(make(kMoving, 1), kStatic, 1);
  add(make(kMoving, 2), kMoving, 2);  // object 2: 2 of 4 (not more than half) -> FN
  add(make(kMoving, 2), kStatic, 2);
  add(make(10, 3), kMoving, 3);  // parked car 3: 3 of 4 predicted moving -> FP
  add(make(10, 3), kStatic, 1);
  add(make(10, 4), kMoving, 1);  // parked car 4: 1 of 4 -> fine
  add(make(10, 4), kStatic, 3);
  add(kStatic, kMoving, 5);      // background false alarm without instances: no object
  add(make(0, 5), kMoving, 10);  // ignored points never count
  ObjectCounts o = object_counts(gt, pred);
  EXPECT_EQ(o.tp, 1u);
  EXPECT_EQ(o.fn, 1u);
  EXPECT_EQ(o.fp, 1u);
  EXPECT_DOUBLE_EQ(o.iou(), 1.0 / 3.0);
  o = object_counts(gt, pred, 0.4);  // 50 % > 40 %: object 2 detected
  EXPECT_EQ(o.tp, 2u);
  EXPECT_EQ(o.fn, 0u);
  EXPECT_EQ(o.fp, 1u);
  EXPECT_THROW(object_counts(gt, pred, 1.0), InputError);
}

TEST(EvalMos, PredictedInstancesOnStaticBackgroundAreFalsePositives) {
  std::vector<Label> gt, pred;
  const auto add = [&](Label g, Label p, int n) {
    for (int i = 0; i < n; ++i) {
      gt.push_back(g);
      pred.push_back(p);
    }
  };
  add(make(kMoving, 1), make(kMoving, 9), 4);  // detected moving object (pred instance 9 overlaps it)
  add(kStatic, make(kMoving, 9), 2);           // ... and spills onto background: still not an FP
  add(kStatic, make(kMoving, 7), 3);           // pred instance 7 on background only -> FP (b)
  add(make(10, 3), make(kMoving, 8), 4);       // parked car fully predicted moving -> FP (a) once
  add(kStatic, make(kMoving, 8), 1);           //   pred instance 8 also touches background: not twice
  add(0, make(kMoving, 6), 5);                 // pred instance 6 only on ignored points -> nothing
  const ObjectCounts o = object_counts(gt, pred);
  EXPECT_EQ(o.tp, 1u);
  EXPECT_EQ(o.fn, 0u);
  EXPECT_EQ(o.fp, 2u);
  MosResult total;
  add_scan(total, gt, pred);
  add_scan(total, gt, pred);
  EXPECT_EQ(total.objects.tp, 2u);
  EXPECT_EQ(total.objects.fp, 4u);
  EXPECT_DOUBLE_EQ(total.objects.iou(), 2.0 / 6.0);
}

TEST(EvalMos, EffectiveFeatureRatio) {
  const std::vector<Label> gt = {kStatic, kMoving, 0, 10, 253, kStatic};
  // Features on 0 (static), 1 (moving), 2 (ignored), 3 (parked car), 4 (moving), 5 (static), 0 again.
  const FeatureCounts f = count_effective_features(gt, {0, 1, 2, 3, 4, 5, 0});
  EXPECT_EQ(f.total, 6u);
  EXPECT_EQ(f.effective, 4u);
  EXPECT_DOUBLE_EQ(f.ratio(), 4.0 / 6.0);
  EXPECT_TRUE(std::isnan(count_effective_features(gt, {2}).ratio()));
  EXPECT_THROW(count_effective_features(gt, {6}), InputError);
}
