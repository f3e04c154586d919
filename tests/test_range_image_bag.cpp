// The CNN's input and output glue without LibTorch: the range image bag's speed images (a known
// moved object, a static wall seen from a moved sensor, missing history) and the object-level
// decision on per-pixel probabilities.
#include <gtest/gtest.h>

#include <cmath>

#include "dloam/core/cnn_decision.hpp"
#include "dloam/core/range_image_bag.hpp"
#include "dloam/core/segmentation.hpp"

using namespace dloam;

namespace {

// A wall at x = 20 m (|y| < 15 m) and a 2 m wide board at x = 10 m centred at y = board_y, seen from
// a sensor at `sensor_x` on the x axis; one ray per pixel centre of the HDL-64E image.
std::vector<Vec3> render(const SensorConfig& s, double board_y, double sensor_x) {
  std::vector<Vec3> pts;
  for (int r = 0; r < s.N_scan; ++r)
    for (int c = 0; c < s.Horizon_SCAN; ++c) {
      const double el = s.beam_elevation_deg(r) * M_PI / 180.0;
      const double az = M_PI - 2.0 * M_PI * (c + 0.5) / s.Horizon_SCAN;
      const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      if (d.x() <= 0.05) continue;
      for (double X : {10.0, 20.0}) {
        const Vec3 p = (X - sensor_x) / d.x() * d;
        const bool board = X == 10.0 && std::abs(p.y() - board_y) < 1.0 && p.z() > -1.5 && p.z() < 1.0;
        const bool wall = X == 20.0 && std::abs(p.y()) < 15.0 && p.z() > -3.0 && p.z() < 5.0;
        if (board || wall) {
          pts.push_back(p);
          break;
        }
      }
    }
  return pts;
}

Pose at_x(double x) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(x, 0, 0);
  return p;
}

}  // namespace

TEST(RangeImageBag, SpeedImagesShowTheMovedBoardAndNotTheStaticWall) {
  const SensorConfig s = sensor_preset("HDL-64E");
  // Past scan: sensor at x = 0, board at y = 0. Current: sensor moved 0.5 m forward, board at y = 1.
  const auto past_points = render(s, 0.0, 0.0);
  const auto cur_points = render(s, 1.0, 0.5);
  ScanHistory history(2, s);
  history.push(project(past_points, s).range, at_x(0.0));
  const RangeImage img = project(cur_points, s);
  const RangeImageBag bag = history.bag(img, cur_points, {}, at_x(0.5));
  ASSERT_EQ(bag.channels, bag_channels(2));
  int board_new = 0, board_new_fast = 0, wall = 0, wall_static = 0, unknown2 = 0, valid = 0;
  for (int px = 0; px < bag.rows * bag.cols; ++px) {
    const int i = img.point_of_pixel[static_cast<std::size_t>(px)];
    if (i < 0) continue;
    ++valid;
    const Vec3& p = cur_points[static_cast<std::size_t>(i)];  // current frame; world x = p.x + 0.5
    const float s1 = bag.at(kBagSpeed, px);
    unknown2 += bag.at(kBagSpeed + 1, px) == kBagSpeedUnknown;
    EXPECT_NEAR(bag.at(kBagRange, px), img.range[static_cast<std::size_t>(px)] * kBagMetricScale, 1e-6);
    if (p.x() < 12.0 && p.y() > 1.2) {  // board where the past scan saw the wall 10 m behind
      ++board_new;
      board_new_fast += s1 >= kBagSpeedClip;
    } else if (p.x() > 15.0 && std::abs(p.y()) > 5.0) {  // wall away from the board and its shadows
      ++wall;
      wall_static += s1 >= 0.0f && s1 < 0.05f;
    }
  }
  ASSERT_GT(board_new, 50);
  ASSERT_GT(wall, 1000);
  EXPECT_EQ(board_new_fast, board_new);
  EXPECT_GT(wall_static, 0.95 * wall);
  EXPECT_EQ(unknown2, valid);  // only one past scan: speed image 2 is unknown everywhere
}

TEST(RangeImageBag, HistoryKeepsTheMostRecentScansAndRefinesTheLatestPose) {
  const SensorConfig s = sensor_preset("HDL-64E");
  const auto pts = render(s, 0.0, 0.0);
  ScanHistory history(2, s);
  for (int k = 0; k < 4; ++k) history.push(project(pts, s).range, at_x(k));
  EXPECT_EQ(history.size(), 2u);
  // A wrong latest pose makes the static scene look moving; refining it fixes that.
  history.set_latest_pose(at_x(7.0));
  const RangeImage img = project(pts, s);
  auto wall_speed = [&](const RangeImageBag& bag) {
    double sum = 0;
    int n = 0;
    for (int px = 0; px < bag.rows * bag.cols; ++px)
      if (img.point_of_pixel[static_cast<std::size_t>(px)] >= 0 && bag.at(kBagSpeed, px) >= 0) {
        sum += bag.at(kBagSpeed, px);
        ++n;
      }
    return sum / std::max(n, 1);
  };
  const double wrong = wall_speed(history.bag(img, pts, {}, at_x(3.0)));
  history.set_latest_pose(at_x(3.0));
  const double right = wall_speed(history.bag(img, pts, {}, at_x(3.0)));
  EXPECT_GT(wrong, 1.0);
  EXPECT_LT(right, 0.01);
}

TEST(CnnDecision, ClustersFollowTheAlphaRuleAndMovingGroundIsRejected) {
  SegmentationResult seg;
  seg.image.rows = 1;
  seg.image.cols = 8;
  // pixels: 0-3 cluster 1, 4-5 cluster 2, 6 ground, 7 outlier; point i in pixel i, point 8 lost pixel 2.
  seg.pixel_label = {1, 1, 1, 1, 2, 2, kGroundLabel, kOutlierLabel};
  seg.num_clusters = 2;
  seg.image.point_of_pixel = {0, 1, 2, 3, 4, 5, 6, 7};
  seg.image.range.assign(8, 10.0f);
  seg.image.row_of_point.assign(9, 0);
  seg.image.col_of_point = {0, 1, 2, 3, 4, 5, 6, 7, 2};
  seg.point_label = {1, 1, 1, 1, 2, 2, kGroundLabel, kOutlierLabel, 1};
  const std::vector<float> prob{0.9f, 0.8f, 0.7f, 0.1f, 0.9f, 0.1f, 0.8f, 0.9f};
  DetectionConfig cfg;
  cfg.cnn_threshold = 0.5;
  cfg.alpha = 0.5;
  const DetectionResult d = decide_from_probability(seg, prob, cfg);
  EXPECT_EQ(d.cluster_dynamic[1], 1);  // 1 of 4 static < alpha
  EXPECT_EQ(d.cluster_dynamic[2], 0);  // 1 of 2 static = alpha: static
  EXPECT_EQ(d.num_dynamic, 1);
  EXPECT_EQ(d.ground_rejected[6], 1);
  EXPECT_EQ(d.pixel_dynamic, (std::vector<std::uint8_t>{1, 1, 1, 1, 0, 0, 0, 0}));
  const auto labels = point_labels(seg, d);
  const std::vector<bool> moving{true, true, true, true, false, false, false, false, true};
  for (std::size_t i = 0; i < labels.size(); ++i) EXPECT_EQ(semantic::is_moving(labels[i]), moving[i]) << i;
  EXPECT_THROW(decide_from_probability(seg, std::vector<float>(3, 0.f), cfg), InputError);
}
