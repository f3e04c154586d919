// Disocclusion in eq. 13 (paper III.D.3.a): a van crossing 8 m in front of a standing sensor moves
// 2.2 m sideways (22 m/s) between two scans and uncovers a static post that it hid. The post's
// range is then 6 m "behind" the surface the previous scan saw there, a range change no object makes
// in one scan: it tells that the occluder moved, not the post. Those pixels must not vote, so the
// post stays static, while the van (in previously free space) stays dynamic.
#include <gtest/gtest.h>

#include <algorithm>

#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "seg_test_scene.hpp"

using namespace dloam;

namespace {

enum Id { kGround = 0, kWall, kPost, kVan };

struct Frame {
  std::vector<Vec3> points;
  std::vector<int> id;
  SegmentationResult seg;
};

/// One ray per pixel centre from a sensor 1.73 m above flat ground: a wall 20 m ahead, a 1 m wide
/// post 14 m ahead and a 4 x 2 x 2.5 m van whose near side starts at y = van_y (8 m ahead).
Frame cast(double van_y, const SensorConfig& sensor) {
  const test::Box wall{{20.0, -10.0, -1.73}, {20.3, 10.0, 3.0}};
  const test::Box post{{14.0, -0.5, -1.73}, {14.3, 0.5, -0.23}};
  const test::Box van{{8.0, van_y, -1.73}, {12.0, van_y + 2.0, 0.77}};
  Frame f;
  test::for_each_pixel_ray(sensor, [&](int, int, const Vec3& d) {
    test::Nearest n{test::ground_distance(d, 1.73), kGround};
    n.consider(test::detail::ray_box(d, wall), kWall);
    n.consider(test::detail::ray_box(d, post), kPost);
    n.consider(test::detail::ray_box(d, van), kVan);
    if (n.t > sensor.max_range) return;
    f.points.push_back(n.t * d);
    f.id.push_back(n.id);
  });
  f.seg = segment(f.points, sensor, SegmentationConfig{});
  return f;
}

/// The cluster holding most points of object `which` (0: none).
int cluster_of(const Frame& f, int which) {
  std::vector<int> count(static_cast<std::size_t>(f.seg.num_clusters) + 1, 0);
  for (std::size_t i = 0; i < f.points.size(); ++i)
    if (f.id[i] == which && f.seg.point_label[i] > 0) ++count[static_cast<std::size_t>(f.seg.point_label[i])];
  return static_cast<int>(std::max_element(count.begin() + 1, count.end()) - count.begin());
}

}  // namespace

TEST(Disocclusion, UncoveredStaticPostDoesNotVoteMovingVanDoes) {
  const SensorConfig s = test::scene_sensor();
  const Frame prev = cast(-1.0, s);  // the van hides the post
  const Frame cur = cast(1.2, s);    // 2.2 m to the left: the post is in view
  ASSERT_EQ(std::count(prev.id.begin(), prev.id.end(), int(kPost)), 0);
  const SpeedMatrix S =
      compute_speed_matrix(cur.seg.image, cur.points, Pose::Identity(), project(prev.points, s).range, s);
  const int post = cluster_of(cur, kPost), van = cluster_of(cur, kVan);
  ASSERT_GT(post, 0);
  ASSERT_GT(van, 0);
  ASSERT_NE(post, van);
  // Every post pixel of known speed lies behind what the previous scan saw, by far more than v_max.
  int post_pixels = 0, post_behind = 0;
  for (std::size_t px = 0; px < S.speed.size(); ++px) {
    if (cur.seg.pixel_label[px] != post || S.speed[px] < 0.0f) continue;
    ++post_pixels;
    post_behind += S.behind[px] && S.speed[px] > 3.0f;
  }
  EXPECT_GT(post_pixels, DetectionConfig{}.N_min_dynamic);
  EXPECT_GT(post_behind, 0.9 * post_pixels);

  const DetectionConfig cfg = thresholds_over(DetectionConfig{}, 0.1);  // scans 0.1 s apart
  const DetectionResult det = detect_dynamic(cur.seg, S, cfg);
  EXPECT_FALSE(det.cluster_dynamic[static_cast<std::size_t>(post)]);
  EXPECT_TRUE(det.cluster_dynamic[static_cast<std::size_t>(van)]);
  // Without the rule (v_max beyond any range change) the uncovered post looks like it moved.
  DetectionConfig no_rule = cfg;
  no_rule.v_max = 1e9;
  EXPECT_TRUE(detect_dynamic(cur.seg, S, no_rule).cluster_dynamic[static_cast<std::size_t>(post)]);
}
